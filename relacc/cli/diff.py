"""``relacc diff A B``: two descriptions of one robot, aligned, every difference classified and located
(:mod:`relacc.validation.diff`); text or JSON."""

from __future__ import annotations

import json

SHOWN = 20
"""Differences the text lists; the rest are counted ("N more in --json")."""


def cmd_diff(args) -> int:
    from relacc.core.tolerances import PRINTED_DIGITS, PRINTED_RTOL
    from relacc.errors import InputError
    from relacc.reading.xacro import set_arguments
    from relacc.validation.diff import diff

    set_arguments(args.xacro_arg)
    rtol = PRINTED_RTOL if args.rtol is None else args.rtol
    if rtol < PRINTED_RTOL:
        raise InputError(f"--rtol {rtol:g}: at least {PRINTED_RTOL:g} (what printing to {PRINTED_DIGITS} significant "
                         "digits changes); --rtol only widens the tolerance")
    from relacc import files

    outputs = {flag: getattr(args, flag, None) for flag in ("junit", "sarif")}
    for flag, path in outputs.items():
        if path is not None:
            files.check_output_file(path, f"--{flag}")  # before the work: a bad path is one line up front
    a, b = args.model
    import time

    start = time.perf_counter()
    result = diff(a, b, rtol=rtol, states=args.states, seed=args.seed)
    seconds = time.perf_counter() - start
    if any(outputs.values()):
        from relacc.report import ci

        found = ci.diff_results(result)
        written = {}
        if outputs["junit"]:
            written[outputs["junit"]] = ci.junit([(f"{a} -> {b}", found, seconds)], set(), "diff")
        if outputs["sarif"]:
            written[outputs["sarif"]] = ci.sarif(found, None)
        files.replace_all(written)
    return answer(result, args.json)


def answer(result, as_json: bool) -> int:
    """Print a :class:`relacc.validation.diff.Diff` (text, or JSON) and return its exit code: 0 the same robot, 1
    differences."""
    if as_json:
        print(json.dumps(result.as_json(), indent=1))
    else:
        print("\n".join(text(result)))
    return 0 if result.same else 1


def text(result) -> list[str]:
    """The text answer: the verdict first, the notes, then the differences by element, then the dynamics."""
    pairs = result.matched["parts"]
    how: dict = {}
    for pair in pairs:
        how[pair["how"]] = how.get(pair["how"], 0) + 1
    matched = f"{len(pairs)} moving parts matched ({', '.join(f'{n} by {k}' for k, n in how.items())})" if pairs \
        else "no moving part matched"
    if result.same:
        lines = [f"relacc diff: the same robot within printing to 6 significant digits (rtol {result.rtol:g}): "
                 f"{matched}"]
    else:
        kinds: dict = {}
        for d in result.differences:
            kinds[d.kind] = kinds.get(d.kind, 0) + 1
        beyond = [row["quantity"] for row in result.dynamics if row["beyond"]]
        said = ", ".join(f"{n} {k}" for k, n in kinds.items()) or "none in the description"
        lines = [f"relacc diff: not the same robot: {len(result.differences)} difference"
                 f"{'s' if len(result.differences) != 1 else ''} ({said})"
                 + (f"; the {', '.join(beyond)} differ beyond printing" if beyond else "") + f"; {matched}"]
    lines += [f"  note: {note}" for note in result.notes]
    ordered = sorted(result.differences, key=lambda d: (d.element, d.quantity))
    lines += [d.line() for d in ordered[:SHOWN]]
    if len(ordered) > SHOWN:
        lines.append(f"  {len(ordered) - SHOWN} more in --json")
    for row in result.dynamics:
        lines.append(f"  dynamics: {row['quantity']}: worst of {row['states']} states (state {row['worst_state']}; 0 "
                     f"is the reference) {row['normalized']:.2g} of its largest entry, printing allows "
                     f"{row['tolerance']:.2g}" + ("  BEYOND" if row["beyond"] else ""))
    return lines


