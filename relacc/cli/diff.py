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

    outputs = {flag: getattr(args, flag, None) for flag in ("junit", "sarif", "out")}
    for flag, path in outputs.items():
        if path is not None:
            files.check_output_file(path, f"--{flag}")  # before the work: a bad path is one line up front
    a, b = args.model
    import time

    start = time.perf_counter()
    result = diff(a, b, rtol=rtol, states=args.states, seed=args.seed)
    seconds = time.perf_counter() - start
    if args.engines is not None:
        result.engines = engine_verdicts((a, b), args.engines, states=args.states, seed=args.seed)
    written = {}
    if outputs["out"]:
        from relacc.report.diff_page import render

        written[outputs["out"]] = render(result)
    if outputs["junit"] or outputs["sarif"]:
        from relacc.report import ci

        found = ci.diff_results(result)
        if outputs["junit"]:
            written[outputs["junit"]] = ci.junit([(f"{a} -> {b}", found, seconds)], set(), "diff")
        if outputs["sarif"]:
            written[outputs["sarif"]] = ci.sarif(found, None)
    files.replace_all(written)  # every file or none
    code = answer(result, args.json)
    if outputs["out"] and not args.json:
        print(f"wrote {outputs['out']}")
    return code


def engine_verdicts(paths, engines, *, states: int, seed: int) -> dict:
    """``{"a": ..., "b": ...}``: for each file, ``relacc compare``'s verdict on it (``{"file", "exit", "agree",
    "compared", "line"}``: whether ``engines`` (empty: every one installed) read it as relacc does), a file named
    twice compared once. A file no
    engine can compare is said so (exit 2), not raised: the diff stands without it."""
    import os

    from relacc.errors import RelaccError
    from relacc.validation.robots import compare
    from relacc.validation.robots.comparison import verdict_line

    done: dict = {}
    out = {}
    for side, path in zip("ab", paths):
        key = os.path.realpath(path)
        if key not in done:
            try:
                r = compare(path, engines=engines or None, n_states=states, seed=seed)
            except RelaccError as exc:
                done[key] = {"exit": 2, "agree": False, "compared": [], "line": f"cannot be compared: {exc}"}
            else:
                data = r.as_json()
                done[key] = {"exit": r.exit_code, "agree": data["agree"], "compared": data["compared"],
                             "line": verdict_line(data)}
        out[side] = {"file": str(path), **done[key]}
    return out


def answer(result, as_json: bool) -> int:
    """Print a :class:`relacc.validation.diff.Diff` (text, or JSON) and return its exit code: 0 the same robot, 1
    differences."""
    if as_json:
        print(json.dumps(result.as_json(), indent=1))
    else:
        print("\n".join(text(result)))
    return 0 if result.same else 1


def text(result) -> list[str]:
    """The text answer: the verdict first, the engines' verdicts on each file (when asked), the notes, then the
    differences by element, then the dynamics."""
    lines = [f"relacc diff: {result.verdict()}"]
    lines += [f"  engines on {side.upper()} ({e['file']}): {e['line']}" for side, e in result.engines.items()]
    lines += [f"  note: {note}" for note in result.notes]
    ordered = sorted(result.differences, key=lambda d: (d.element, d.quantity))
    lines += [d.line() for d in ordered[:SHOWN]]
    if len(ordered) > SHOWN:
        lines.append(f"  {len(ordered) - SHOWN} more in --json")
    from relacc.validation.diff_dynamics import row_words

    for row in result.dynamics:
        words = row_words(row)
        lines.append(f"  dynamics: {row['quantity']}: worst of {row['states']} states (state {row['worst_state']}; 0 "
                     f"is the reference) {row['normalized']:.2g} of its largest entry, printing allows "
                     f"{row['tolerance']:.2g}" + ("  BEYOND" if row["beyond"] else "")
                     + (f"; {words}" if words else ""))
    return lines


