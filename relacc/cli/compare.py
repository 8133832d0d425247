"""``relacc compare``: one model file in MuJoCo, Pinocchio and Drake; the audit and the dynamics, as text or JSON."""

from __future__ import annotations

import json
import os
import sys

from relacc.core.tolerances import EPS

INTERNAL = 3
"""The exit code of relacc's own failure on a file (:data:`relacc.cli.main.INTERNAL`)."""


def cmd_compare(args) -> int:
    from relacc import files
    from relacc.reading.xacro import set_arguments

    set_arguments(getattr(args, "xacro_arg", None))
    if args.urdf is not None:
        return _urdf_is_diff(args)
    found = models(args.model)
    if getattr(args, "models_only", False):
        from relacc.reading.read import is_description

        def other(path) -> bool:  # a file that reads as something else; one missing or unreadable is an error
            return os.path.isfile(path) and os.access(path, os.R_OK) and not is_description(path)

        skipped = [shown for path, shown in found if other(path)]
        found = [(path, shown) for path, shown in found if not other(path)]
        if skipped:
            print(f"relacc compare: skipped {len(skipped)} file{'s' if len(skipped) > 1 else ''} that "
                  f"{'are' if len(skipped) > 1 else 'is'} not a robot description: {', '.join(skipped[:5])}"
                  f"{', ...' if len(skipped) > 5 else ''}", file=sys.stderr)
        if not found and not any(getattr(args, flag, None) is not None for flag in ("junit", "sarif",
                                                                                      "write_baseline")):
            return 0  # nothing to compare; with CI outputs asked for, they are written, empty
    args.model = [path for path, _ in found]
    args.shown = {path: shown for path, shown in found}
    with files.inputs(args.model):  # a directory's files are inputs too: --out may be none of them
        return _compare(args)


def _robots(results: list, args) -> list:
    """``results`` (``[(model, result or error)]``) without the files that hold no robot to compare
    (:class:`relacc.errors.NotARobot`: a xacro of macros, a xacro fragment, nothing that moves) where
    ``--models-only`` asks for robots only; those said in one line on stderr."""
    from relacc.errors import NotARobot

    if not getattr(args, "models_only", False):
        return results
    skipped = [args.shown.get(m, m) for m, r in results if isinstance(r, NotARobot)]
    if skipped:
        print(f"relacc compare: skipped {len(skipped)} file{'s' if len(skipped) > 1 else ''} with no robot to compare "
              f"(no <link>: a xacro of macros; a xacro fragment, its joints naming another file's links; nothing that "
              f"moves): {', '.join(skipped[:5])}{', ...' if len(skipped) > 5 else ''}", file=sys.stderr)
    return [(m, r) for m, r in results if not isinstance(r, NotARobot)]


def _urdf_is_diff(args) -> int:
    """``compare MODEL.xml --urdf MODEL.urdf``: two files of one robot, which ``relacc diff`` compares (issue 47: one
    way to compare two files); said in one line on stderr, then ``diff URDF MJCF``'s answer and exit code."""
    from relacc.cli.diff import answer
    from relacc.errors import InputError
    from relacc.validation.diff import diff

    if len(args.model) != 1 or args.out or args.junit or args.sarif or args.baseline or args.write_baseline:
        raise InputError("--urdf compares one MJCF with a URDF of the same robot, which is relacc diff now: run "
                         "relacc diff MODEL.urdf MODEL.xml")
    result = diff(args.urdf, args.model[0], states=min(args.states, 8), seed=args.seed)
    print(f"relacc compare: --urdf compares two files of one robot, which relacc diff does: relacc diff {args.urdf} "
          f"{args.model[0]}", file=sys.stderr)
    return answer(result, args.json)


def _compare(args) -> int:
    from relacc import files
    from relacc.validation.robots import compare

    out = None
    if args.out is not None:
        out = files.check_output_file(args.out)  # before the work: a bad path is a one-line error up front
    ci_outputs = {flag: getattr(args, flag) for flag in ("junit", "sarif", "write_baseline")
                  if getattr(args, flag, None) is not None}
    for flag, path in ci_outputs.items():
        files.check_output_file(path, f"--{flag.replace('_', '-')}")
    accepted = None
    if getattr(args, "baseline", None) is not None:
        from relacc.report import ci

        accepted = ci.read_baseline(args.baseline)
    if ci_outputs or accepted is not None:
        return _with_ci(args, out, accepted)
    many = len(args.model) > 1 or args.scheduler
    if args.verbose and (not many or args.json):
        from relacc.errors import InputError

        raise InputError("--verbose prints each model's detail after the summary of several models; one model's "
                         "detail, and --json, are whole already")
    if many:
        return _many(args)
    from relacc.errors import NotARobot

    try:
        result = compare(args.model[0], urdf=args.urdf, engines=args.engines, n_states=args.states, seed=args.seed)
    except NotARobot as exc:
        if not _robots([(args.model[0], exc)], args):
            return 0
        raise
    if out is not None:
        from relacc.report.robot import write

        write(result, out)
    if args.json:
        print(json.dumps(result.as_json(), indent=2))
    else:
        print(text(result) + (f"\nwrote {out}" if out is not None else ""))
    return result.exit_code


def models(paths) -> list[tuple[str, str]]:
    """``[(path, shown name)]`` of the model files named: a file as given (shown as given); a directory, its ``.xml``
    and ``.urdf`` files (recursively, sorted; shown by their path relative to the directory given).

    Raises:
        InputError: a directory holding no such file, or one it cannot read (a subdirectory included: nothing
            is skipped without a word).
    """
    import os
    from pathlib import Path

    from relacc.errors import InputError

    out = []
    for given in paths:
        path = Path(given)
        if not path.is_dir():
            out.append((given, given))
            continue

        def unreadable(exc, given=given):
            raise InputError(f"{given}: cannot read {exc.filename} ({exc.strerror}); relacc compares every model "
                             "under a directory or none") from None

        found = sorted(Path(root) / name for root, _, names in os.walk(path, onerror=unreadable) for name in names
                       if Path(name).suffix.lower() in (".xml", ".urdf", ".xacro") and (Path(root) / name).is_file())
        if not found:
            raise InputError(f"{given}: a directory with no .xml or .urdf file in it")
        out += [(str(p), str(p.relative_to(path))) for p in found]
    return out


def _with_ci(args, out, accepted) -> int:
    """The comparison with CI outputs (``--junit``, ``--sarif``, ``--write-baseline``) and a baseline (``--baseline``):
    each model compared and timed, the usual text or JSON printed, the files written; with a baseline, a model whose
    every failing result it accepts exits 0 (an internal error never does)."""
    import time

    from relacc import files
    from relacc.errors import RelaccError
    from relacc.report import ci
    from relacc.validation.robots import compare

    outcomes: list = []
    for model in args.model:
        start = time.perf_counter()
        outcome: object
        try:
            outcome = compare(model, urdf=args.urdf, engines=args.engines, n_states=args.states, seed=args.seed)
        except RelaccError as exc:
            outcome = exc
        except Exception as exc:  # noqa: BLE001 - relacc's own failure on this file: said, and the run goes on
            from relacc.cli.main import internal_error

            outcome = Internal(internal_error(exc))
        outcomes.append((model, outcome, time.perf_counter() - start))
    kept = {m for m, _ in _robots([(m, o) for m, o, _ in outcomes], args)}
    outcomes = [(m, o, t) for m, o, t in outcomes if m in kept]  # none left: the CI files written all the same, empty
    per_model = [(m, ci.results(m, o), t) for m, o, t in outcomes]
    found = [r for _, rs, _ in per_model for r in rs]
    if args.junit is not None:
        files.write_text(args.junit, ci.junit(per_model, accepted or set()))
    if args.sarif is not None:
        files.write_text(args.sarif, ci.sarif(found, accepted))
    if args.write_baseline is not None:
        ci.write_baseline(args.write_baseline, found)
    results_ = [(m, o) for m, o, _ in outcomes]
    codes = [exit_code(o) for _, o in results_]
    if accepted is not None:  # what the baseline accepts fails nothing
        codes = [code if code == INTERNAL or ci.failing(rs, accepted) else 0
                 for code, (_, rs, _) in zip(codes, per_model)]
    if not results_:
        pass  # every file skipped (said on stderr)
    elif len(results_) == 1 and not isinstance(results_[0][1], Exception):
        result = results_[0][1]
        if out is not None:
            from relacc.report.robot import write

            write(result, out)
        print(json.dumps(result.as_json(), indent=2) if args.json else text(result))
    else:
        if out is not None:
            from relacc.report.robot import write_many

            write_many([(args.shown.get(m, m), r) for m, r in results_], out)
        if args.json:
            print(json.dumps([{"model": m, "shown": args.shown.get(m, m), "error": str(r), "exit": exit_code(r)}
                              if isinstance(r, Exception) else {**r.as_json(), "shown": args.shown.get(m, m),
                                                                "exit": exit_code(r)} for m, r in results_], indent=2))
        else:
            if len(results_) == 1:
                print(f"relacc compare: {results_[0][0]}: error: {results_[0][1]}")
            else:
                print(summary_table([(args.shown.get(m, m), r) for m, r in results_]))
    new = sum(len(ci.failing(rs, accepted or set())) for _, rs, _ in per_model)
    if not args.json:
        said = [f"wrote {p}" for p in (args.junit, args.sarif, args.write_baseline) if p is not None]
        if accepted is not None:
            said.insert(0, f"baseline {args.baseline}: {new} new result{'s' if new != 1 else ''} (the accepted ones "
                           "do not fail the run)")
        print("\n".join(said))
    return max(codes, default=0)


def _many(args) -> int:
    """Several models (or one on a cluster): each compared alone; exit the highest of their codes."""
    from relacc.errors import RelaccError

    if args.scheduler:
        from relacc.cli.progress import bar
        from relacc.cluster.sweeps import compare_models

        results = compare_models(args.scheduler, args.model, urdf=args.urdf, engines=args.engines,
                                 n_states=args.states, seed=args.seed, progress=None if args.quiet else bar)
    else:
        from relacc.validation.robots import compare

        results = []
        for model in args.model:
            try:
                results.append((model, compare(model, urdf=args.urdf, engines=args.engines, n_states=args.states,
                                               seed=args.seed)))
            except RelaccError as exc:
                results.append((model, exc))
            except Exception as exc:  # noqa: BLE001 - relacc's own failure on this file: said, and the run goes on
                from relacc.cli.main import internal_error

                results.append((model, Internal(internal_error(exc))))
    results = _robots(results, args)
    if not results:
        return 0
    if args.out is not None and len(results) == 1:  # one model on a cluster: its own page
        from relacc.report.robot import write

        _, only = results[0]
        if isinstance(only, (RelaccError, Internal)):
            raise only
        write(only, args.out)
    elif args.out is not None:
        from relacc.report.robot import write_many

        write_many([(args.shown.get(m, m), r) for m, r in results], args.out)
    codes = [exit_code(r) for _, r in results]
    if args.json:
        print(json.dumps([{"model": m, "shown": args.shown.get(m, m), "error": str(r), "exit": exit_code(r)}
                          if isinstance(r, Exception) else {**r.as_json(), "shown": args.shown.get(m, m),
                                                            "exit": r.exit_code} for m, r in results], indent=2))
        return max(codes)
    print(f"relacc compare: {len(results)} models: {codes.count(0)} agree, {codes.count(1)} disagree, "
          f"{codes.count(2)} cannot be compared" + (f", {codes.count(INTERNAL)} internal errors (exit 3: please report "
                                                    "them)" if INTERNAL in codes else ""))
    print(summary_table([(args.shown.get(m, m), r) for m, r in results]))
    for line in findings_lines(results):
        print(line)
    if args.verbose:
        for (model, r), code in zip(results, codes):
            print()
            print(f"{model}: error: {r}" if isinstance(r, Exception) else text(r))
    else:
        print("(each model's detail: --verbose, --json or --out PAGE.html)")
    if args.out is not None:
        print(f"wrote {args.out}")
    return max(codes)


class Internal(Exception):
    """relacc's own failure on one file of several (one line, :func:`relacc.cli.main.internal_error`): recorded for
    that file, exit 3, and the run goes on with the next."""


def exit_code(result) -> int:
    """A model's exit code: 2 for an input error, 3 for an internal one, else its comparison's."""
    from relacc.errors import RelaccError

    if isinstance(result, RelaccError):
        return 2
    if isinstance(result, Exception):
        return INTERNAL
    return result.exit_code


def findings_lines(results) -> list[str]:
    """Each finding about a file, and each difference no known reading explains, as ``file:line: what``: what a
    linter prints, and what an editor or CI log links to the element."""
    from relacc.report.ci import results as ci_results

    out = []
    for model, r in results:
        if isinstance(r, Exception):
            continue
        for found in ci_results(model, r):
            if found.rule in ("RELACC001", "RELACC003", "RELACC005"):
                out.append(f"  {found.located()}")
    return out


def summary_table(results) -> str:
    """One aligned line per model: exit, the readings that took part, audit differences, dynamics rows outside
    tolerance, how many of those have no known cause, findings; or, for a model that cannot be compared, why."""
    from relacc.errors import RelaccError
    from relacc.validation.robots.causes import CauseKind

    width = max([len(m) for m, _ in results] + [5])
    lines = [f"  {'exit':4s}  {'model':{width}s}  {'audit':>5s}  {'dynamics':>8s}  {'unexplained':>11s}  "
             f"{'findings':>8s}  compared"]
    for model, r in results:
        if isinstance(r, Exception):
            what = "cannot be compared" if isinstance(r, RelaccError) else "internal error"
            lines.append(f"  {exit_code(r):<4d}  {model:{width}s}  {what}: {r}")
            continue
        data = r.as_json()
        bad = [x for q in data["dynamics"].values() for x in q["engines"].values() if not x["ok"]]
        unexplained = sum(x["cause_kind"] == CauseKind.NOT_EXPLAINED for x in bad) + sum(
            a["cause_kind"] == CauseKind.NOT_EXPLAINED for a in data["audit"])
        lines.append(f"  {r.exit_code:<4d}  {model:{width}s}  {len(data['audit']):>5d}  {len(bad):>8d}  "
                     f"{unexplained:>11d}  {len(data['findings']):>8d}  {', '.join(data['compared'])}")
    return "\n".join(lines)


AUDIT_META = ("item", "where", "cause", "cause_kind", "place")
"""An audit row's keys that are not a reading's value."""


def text(result) -> str:
    """The comparison as lines of text: the readings, findings, audit rows with causes and places, dynamics per
    quantity and evaluator (aligned), the referee, the verdict."""
    data = result.as_json()
    lines = [f"relacc compare {data['model']}" + (f" (Pinocchio: {data['urdf']})" if data["urdf"] else "")
             + f"; {data['states']} random states and the reference configuration, seed {data['seed']}",
             "readings (relacc reads the file itself and holds every engine to it; coordinates: relacc's case 2, the "
             "file's joints in order, through each engine's speed map):"]
    done_by_relacc = []  # what relacc did to an engine's text (a weld, meshes or constraints left out): said
    for name, e in data["engines"].items():
        status = f"nq {e['nq']}, nv {e['nv']}" if e["loaded"] else f"not taking part: {e['error']}"
        own = [w for w in e["warnings"] if w.startswith("relacc ")]
        done_by_relacc += [(name, w) for w in own]
        n = len(e["warnings"]) - len(own)
        warned = f"; {n} {'note' if name == 'relacc' else 'parser warning'}{'s' if n != 1 else ''} (in --json)" \
            if n else ""
        lines.append(f"  {name:9s} {status}{warned}")
    said: dict = {}
    for name, w in done_by_relacc:  # one line per thing relacc did, naming the engines it did it for
        said.setdefault(_first_clause(w), []).append(name)
    lines += [f"  for {', '.join(names)}: {what}" for what, names in said.items()]
    lines.append(f"compared: {', '.join(data['compared'])}")
    for f in data["findings"]:
        lines.append(f"finding: body {f['body']} ({f['place']}): {f['condition']}: {f['numbers']}")
    for body, why in data["taken"].items():
        lines.append(f"taken: body {body}: {why}")
    for line in data["not_evaluated"]:
        lines.append(f"not evaluated: {line}")
    lines.append(f"audit: {len(data['audit'])} difference{'s' if len(data['audit']) != 1 else ''}")
    for a in data["audit"]:
        values = ", ".join(f"{k} {_short(v)}" for k, v in a.items() if k not in AUDIT_META)
        lines.append(f"  {a['item']}: {a['where']}: {values}")
        lines.append(f"    cause: {a['cause']}" + (f" [{a['place']}]" if a.get("place") else ""))
    lines.append("dynamics against relacc's reading (normalized error at the worst state; tolerance c eps per link):")
    width = max([len(e) for row in data["dynamics"].values() for e in row["engines"]] + [9])
    for quantity, row in data["dynamics"].items():
        for engine, r in row["engines"].items():
            verdict = "agree" if r["ok"] else "DIFFER"
            error = f"{r['max_error']:9.3g} ({r['max_error'] / EPS:9.3g} eps)" if r["max_error"] is not None \
                else f"{'inf':>9s} ({'':>9s}    )"
            lines.append(f"  {quantity:22s} {engine:{width}s} {error}  tolerance {r['tolerance']:.3g}  {verdict}"
                         + (f": {r['cause']}" if r["cause"] else ""))
    if data["referee"]:
        lines.append("referee (relacc's reading and every engine, pair by pair):")
        lines += [f"  {v['verdict']}" for v in data["referee"]]
    from relacc.validation.robots.comparison import verdict_line

    lines.append(verdict_line(data))
    return "\n".join(lines)


def _first_clause(text: str) -> str:
    """A note's first clause (up to its first colon or parenthesis): one short line."""
    cut = min([i for i in (text.find(" ("), text.find(": ")) if i > 0] or [len(text)])
    return text[:cut]


def _short(value) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(_short(v) for v in value) + "]"
    return f"{value:.6g}" if isinstance(value, float) else str(value)
