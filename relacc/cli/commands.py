"""One function per ``relacc`` subcommand: ``cmd_<name>(args) -> exit code``.

Each imports what it needs when it runs (engines, report, plots), so that
``relacc --help`` and the other commands stay light.
"""

from __future__ import annotations

import json
import sys

import numpy as np

import relacc
from relacc import files, fixtures
from relacc.cli.compare import cmd_compare  # noqa: E402,F401  (dispatched by name from main)
from relacc.cli.diff import cmd_diff  # noqa: E402,F401  (dispatched by name from main)
from relacc.cli.progress import bar, end_line
from relacc.cli.progress import line as progress_line
from relacc.core.conventions import CASE_NAMES, CONVENTIONS, COORDINATES, QUANTITIES, SPEEDS
from relacc.core.tolerances import EPS
from relacc.errors import InputError


def _numbers(text: str, name: str) -> list[float]:
    import re

    fields = re.split(r"\s*,\s*|\s+", text.strip())
    if "" in fields:
        raise InputError(f"--{name}: an empty field in {text!r}; give numbers separated by commas or spaces")
    try:
        return [float(x) for x in fields]
    except ValueError:
        raise InputError(f"--{name}: expected numbers separated by commas or spaces, got {text!r}") from None


def _state_from_args(args) -> dict:
    state = {}
    if args.state:
        state, _ = files.read_document(args.state, json.loads, "JSON", what="state file")
        if not isinstance(state, dict):
            raise InputError(f"{args.state}: expected a JSON object with case, q, u (and udot)")
        unknown = sorted(set(state) - {"case", "q", "u", "udot", "variant"})
        if unknown:
            raise InputError(f"{args.state}: unknown keys {unknown}; accepted are case, q, u, udot and variant")
    for key in ("case", "q", "u", "udot", "variant"):
        value = getattr(args, key, None)
        if value is not None:
            state[key] = value if key in ("case", "variant") else _numbers(value, key)
    for key in ("case", "q", "u"):
        if key not in state:
            raise InputError(f"missing {key}: give --{key} or a JSON state file with case, q, u (and udot)")
    return state


def _fmt(v) -> str:
    return "[" + ", ".join(f"{x: .17g}" for x in np.ravel(v)) + "]"


def cmd_eval(args) -> int:
    state = _state_from_args(args)
    fixture = fixtures.load(args.model)
    k = relacc.g2_kinematics(
        fixture.chain, state["case"], state["q"], state["u"], state.get("udot"),
        variant=state.get("variant", "corrected"),
    )
    case = int(k.case)
    if args.json:
        out = {
            "case": case,
            "variant": k.variant,
            "model": str(fixture.source),
            "position": k.position.tolist(),
            "velocity": k.velocity.tolist(),
            "acceleration": None if k.acceleration is None else k.acceleration.tolist(),
            "V": k.V.tolist(),
            "Vdot": k.Vdot.tolist(),
            "conventions": CONVENTIONS,
        }
        print(json.dumps(out, indent=2))
        return 0
    print(f"G2 kinematics, case {case} ({CASE_NAMES[case]}), variant {k.variant}")
    print(f"model {fixture.source}: q2' = {fixture.chain.q2.tolist()} (B1 comps, m), "
          f"r2' = {fixture.chain.r2.tolist()} (B2 comps, m)")
    print(f"q = {COORDINATES[case]}\nu = {SPEEDS[case]}\n")
    for name in ("position", "velocity", "acceleration"):
        value = getattr(k, name)
        if value is not None:
            print(f"{name:13s}{_fmt(value)}\n{'':13s}{CONVENTIONS[name]}")
    print(f"\nV  ({CONVENTIONS['V']}):")
    print(np.array2string(k.V, precision=6, suppress_small=True, max_line_width=200))
    print(f"Vdot  ({CONVENTIONS['Vdot']}):")
    print(np.array2string(k.Vdot, precision=6, suppress_small=True, max_line_width=200))
    return 0


def _progress(args):
    if args.quiet:
        return None
    return lambda line: print(f"  {line}", file=sys.stderr, flush=True)


def _harness(args):
    from relacc.validation.check import Harness

    return Harness(fixtures.load(args.model), engines=args.engines, n_states=args.states, seed=args.seed,
                   progress=_progress(args))


def _is_robot(args) -> bool:
    """Whether ``--model`` names an MJCF or URDF file (checked as a tree) rather than a chain TOML."""
    from pathlib import Path

    return args.model is not None and Path(args.model).suffix.lower() in (".xml", ".urdf", ".xacro")


CHAIN_STATES, MODEL_STATES = 1000, 20
"""``relacc check``'s default states per case: the chain's, a model file's (a full dynamics evaluation per engine
each). An explicit ``--states`` is always what runs."""


def cmd_check(args) -> int:
    if _is_robot(args):
        return _check_tree(args)
    if args.states is None:
        args.states = CHAIN_STATES
    harness = _harness(args)
    if args.scheduler:
        from relacc.cluster.sweeps import check

        report = check(args.scheduler, harness, cases=args.cases, progress=None if args.quiet else bar)
    else:
        report = harness.check(cases=args.cases)
    if args.json:
        print(json.dumps(report.as_json(), indent=2))
        return 0 if report.passed else 1
    tol = report.comparisons[0].tolerance if report.comparisons else 0
    print(f"relacc check: {report.n_states} states per case, seed {report.seed}; "
          f"normalized error = max|x - x_engine| / magnitude of the terms; tolerance {tol:.3g} "
          f"({tol / EPS:.0f} eps)")
    print("versions: " + ", ".join(f"{k} {v}" for k, v in report.versions.items()))
    header = (f"{'case':4s}  {'engine':9s}  {'route':10s}  {'quantity':12s}  {'max':>9s}  {'median':>9s}  "
              f"{'max/eps':>7s}  result")
    print(header)
    print("-" * len(header))
    for c in report.comparisons:
        print(f"{c.case:<4d}  {c.engine:9s}  {c.route:10s}  {c.quantity:12s}  {c.max_error:9.2e}  "
              f"{c.median_error:9.2e}  {c.max_error / EPS:7.1f}  {'pass' if c.passed else 'FAIL'}")
    print("\nconventions (every number is about G2, in fixed-frame components):")
    for q in QUANTITIES:
        print(f"  {q:12s} {CONVENTIONS[q]}")
    for verdict in report.referee:
        print(f"referee: {verdict.sentence()}")
    n, bad = len(report.comparisons), len(report.failures)
    print(f"\n{'all ' + str(n) + ' comparisons agree' if not bad else f'{bad} of {n} comparisons DISAGREE'}")
    return 0 if report.passed else 1


def _check_tree(args) -> int:
    from relacc.validation.treecheck import check_tree

    if args.scheduler:
        raise InputError("--scheduler runs the chain's sweeps; for a model file, run relacc check --model FILE here "
                         "or relacc compare FILE... --scheduler")
    states = MODEL_STATES if args.states is None else args.states  # each is a full dynamics evaluation per engine
    report = check_tree(args.model, engines=args.engines, cases=args.cases, n_states=states, seed=args.seed,
                        progress=_progress(args))
    if args.json:
        print(json.dumps(report.as_json(), indent=2))
        return 0 if report.passed else 1
    print(f"relacc check {report.model}: relacc's tree (relacc's own reading of the file) against each engine, "
          f"{report.n_states} random states and the reference configuration, seed {report.seed}; normalized error "
          "= max|x - x_engine| / magnitude of the terms, in each case's coordinates through each engine's speed map")
    for name, why in report.not_loaded.items():
        print(f"  {name}: not loaded: {why}")
    for line in report.not_evaluated:
        print(f"not evaluated: {line}")
    header = f"{'case':4s}  {'engine':9s}  {'quantity':22s}  {'max':>9s}  {'tolerance':>9s}  {'max/eps':>9s}  result"
    print(header)
    print("-" * len(header))
    for r in report.rows:
        err = "undefined" if r.max_error == float("inf") else f"{r.max_error:9.2e}"
        ratio = "" if r.max_error == float("inf") else f"{r.max_error / EPS:9.3g}"
        print(f"{r.case:<4d}  {r.engine:9s}  {r.quantity:22s}  {err:>9s}  {r.tolerance:9.2e}  {ratio:>9s}  "
              f"{'pass' if r.passed else 'FAIL'}")
    bad, n = sum(not r.passed for r in report.rows), len(report.rows)
    print(f"\nall {n} comparisons agree" if not bad else f"\n{bad} of {n} comparisons DISAGREE "
          "(relacc compare FILE says why)")
    return 0 if report.passed else 1


def cmd_errata(args) -> int:
    from relacc.validation.errata import errata

    harness = _harness(args)
    items = errata(harness)
    ok = all(e.agrees for e in items)
    if args.json:
        print(json.dumps([e.as_json() for e in items], indent=2))
        return 0 if ok else 1
    print(f"relacc errata: {harness.n_states} states per case, seed {harness.seed}, engines "
          f"{', '.join(harness.engines)}; errors are max normalized errors (tolerance "
          f"{items[0].tolerance:.3g})")
    print(f"{'id':15s}  {'status':9s}  {'printed':>9s}  {'corrected':>9s}  explanation")
    for e in items:
        p = "-" if e.printed_error is None else f"{e.printed_error:9.2e}"
        print(f"{e.id:15s}  {e.status:9s}  {p:>9s}  {e.corrected_error:9.2e}  {e.equation.explanation}")
    return 0 if ok else 1


def cmd_grade(args) -> int:
    import contextlib

    # the user's module and function may print: that goes to stderr, so that stdout stays relacc's (and --json JSON)
    with contextlib.redirect_stdout(sys.stderr):
        grade = _grade(args)
    print(json.dumps(grade.as_json(), indent=2) if args.json else grade.text())
    return 0 if grade.ok else 1


def _grade(args):
    from relacc.testing.grade import check_formula
    from relacc.testing.user import load_function

    fn = load_function(args.function)
    if _is_robot(args) or args.body is not None:
        if not _is_robot(args) or args.body is None:
            raise InputError("--body NAME goes with --model FILE.xml|FILE.urdf (a model's body); without them "
                             "relacc grades the note's G2 on the chain")
        grade = check_formula(fn, quantity=args.quantity, case=args.case, n=args.states, seed=args.seed,
                              model=args.model, body=args.body, timeout=args.timeout)
    else:
        if args.quantity not in ("position", "velocity", "acceleration", "V", "Vdot"):
            raise InputError(f"--quantity {args.quantity} is a model's body quantity: give --model FILE and --body")
        grade = check_formula(fn, quantity=args.quantity, case=args.case, n=args.states, seed=args.seed,
                              chain=fixtures.load(args.model).chain, timeout=args.timeout)
    return grade


def cmd_fixtures(args) -> int:
    fixture = fixtures.load(args.model)
    changes = {k: getattr(args, k) for k in ("q2", "r2", "r1", "m1", "m2", "I1", "I2", "name")
               if getattr(args, k) is not None}
    if args.out is None:
        if changes:
            raise InputError(f"--{', --'.join(changes)}: change the chain only when exporting it (give --out DIR)")
        changed = fixtures.write(fixture, check=args.check)
        if args.check:
            if changed:
                print(f"out of date: {', '.join(changed)} (run `relacc fixtures` to regenerate)", file=sys.stderr)
                return 1
            print(f"up to date: {', '.join(fixtures.MODEL_FILES)}")
            return 0
        print(f"wrote {', '.join(changed)}" if changed else "already up to date")
        return 0
    if args.check:
        raise InputError("--check compares the files beside --model; it does not go with --out")
    import re

    if "name" in changes and not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_.-]*", changes["name"]):
        raise InputError(f"--name {changes['name']!r}: a chain's name starts with a letter or _ and holds letters, "
                         "digits, _, . and - (it names the model in every engine file)")
    files.check_new_directory(args.out)
    from relacc.core.chain import TwoBodyChain
    from relacc.fixtures.export import export
    from relacc.fixtures.model import Fixture

    values = {k: getattr(fixture.chain, k) for k in ("q2", "r2", "r1", "m1", "m2", "I1", "I2")}
    for key, text in changes.items():
        if key == "name":
            continue
        numbers = _numbers(text, key)
        values[key] = numbers[0] if key in ("m1", "m2") and len(numbers) == 1 else (
            np.reshape(numbers, (3, 3)) if key in ("I1", "I2") and len(numbers) == 9 else numbers)
    chain = TwoBodyChain(**values)
    from relacc.engines import chain_exports

    written = export(Fixture(changes.get("name", fixture.name), chain, None), args.out, chain_exports())
    print("wrote " + ", ".join(str(p) for p in written))
    return 0


def cmd_simulate(args) -> int:
    import time as _time

    from relacc import simulate
    from relacc.fixtures.shipped import scene_path
    from relacc.simulate import scenes

    if (args.scene is None) == (args.model is None):
        raise InputError("give a SCENE (a scene file or a shipped scene's name) or --model FILE (its default "
                         "scene), one of them")
    if args.ensemble is None:
        given = [flag for flag, value in (("--spread", args.spread), ("--seed", args.seed),
                                          ("--scheduler", args.scheduler)) if value is not None]
        if args.model is not None:  # the default scene's speeds come from --seed
            given = [g for g in given if g != "--seed"]
        if given:
            raise InputError(f"{', '.join(given)} {'goes' if len(given) == 1 else 'go'} with --ensemble N (the "
                             "perturbed members); a single run of the scene has no random state")
    else:
        args.spread = 0.05 if args.spread is None else args.spread
    if args.out is not None:
        files.check_new_directory(args.out)
    if args.observe is not None and not _is_robot(args):
        raise InputError("--observe BODY goes with --model FILE.xml|FILE.urdf (a model's default scene); a scene "
                         "file names its point in [simulate] observe")
    if args.model is not None:
        scene = scenes.model_scene(args.model, seed=0 if args.seed is None else args.seed,
                                   **({"observe": args.observe} if _is_robot(args) else {}))
    else:
        scene = scenes.load(scene_path(args.scene))
    if args.ensemble is not None:
        args.seed = 0 if args.seed is None else args.seed
    changes = {k: v for k, v in (("dt", args.dt), ("integrator", args.integrator), ("duration", args.duration))
               if v is not None}
    if args.engines:
        changes["engines"], changes["left_out"] = args.engines, ()
    if changes:
        scene = scene.replace(**changes)
    start = _time.perf_counter()
    last = [0.0]

    def progress(engine, fraction):  # a progress bar once the run has taken more than 2 s
        now = _time.perf_counter()
        if args.quiet or now - start < 2.0 or now - last[0] < 0.2:
            return
        last[0] = now
        progress_line(engine, fraction)

    if args.ensemble is not None:
        return _ensemble(scene, args)
    result = simulate.run(scene, progress=progress, keep=False, out=args.out)
    end_line()
    if args.json:
        print(json.dumps(result.summary(), indent=2))
        return result.exit_code
    for path in result.csv:
        print(f"wrote {path}")
    print(simulate.format_text(result))
    return result.exit_code


def _ensemble(scene, args) -> int:
    """``relacc simulate --ensemble N``: every engine's steps per second and its members' G2 differences; the
    verdict: every engine's acceleration against relacc's at the members' initial states (exit 1 when one differs)."""
    from relacc import simulate
    from relacc.simulate.members import run_members

    if args.out is not None:
        raise InputError("--out writes one run's CSVs; it does not go with --ensemble")

    def say(name):
        if not args.quiet:
            print(f"  {name}: {args.ensemble} members x {scene.n_steps} steps", file=sys.stderr, flush=True)

    if args.scheduler:
        from relacc.cluster.sweeps import ensemble_members

        part = ensemble_members(args.scheduler, scene, args.ensemble, args.spread, args.seed,
                                progress=None if args.quiet else bar)
    else:
        part = run_members(scene, 0, args.ensemble, args.spread, args.seed, progress=say)
    from relacc.simulate.members import acceleration_check

    check = acceleration_check(scene, args.ensemble, args.spread, args.seed)
    differing = {k: c for k, c in check.items() if not c["error"] <= c["bound"]}
    verdict = ("nothing to judge: only one evaluator ran" if not check else
               f"every engine's acceleration agrees with relacc's at the members' initial states ({', '.join(check)})"
               if not differing else "DISAGREE: at the members' initial states the acceleration differs from "
               "relacc's: " + "; ".join(f"{k} by {c['error']:.2e} (bound {c['bound']:.1e})"
                                        for k, c in differing.items()))
    summary = {**part.summary(scene, args.spread, args.seed), "acceleration_vs_engines": check,
               "agree": not differing, "verdict": verdict, "left_out": dict(scene.left_out),
               "not_evaluated": list(scene.unevaluated)}
    code = 1 if differing else 0
    if args.json:
        print(json.dumps(summary, indent=2))
        return code
    print(f"{scene.title} ({scene.name}): an ensemble of {args.ensemble} members (spread {args.spread}, seed "
          f"{args.seed}), {scene.n_steps} steps of {scene.dt} s each, {scene.integrator}")
    print(f"{'engine':10s} {'steps/s':>12s} {'seconds':>9s} {'threads':>7s}   (integration only, summed over "
          "workers; member 0: the scene's own state)")
    for n, r in summary["engines"].items():
        print(f"{n:10s} {r['steps_per_second']:12.4g} {r['seconds']:9.3f} {r['threads']:7d}")
    print(f"largest {scene.observe} position difference over the run, per member (m):")
    for k, v in summary["largest_point_position_difference"].items():
        print(f"  {k:20s} max {v['max']:.3e} (member {v['worst_member']}), median {v['median']:.3e}")
    for line in simulate.scene_notes(scene):
        print(line)
    print(f"verdict: {verdict}")
    return code


def cmd_tradeoff(args) -> int:
    from relacc import tradeoff

    progress = None if (args.quiet or args.json) else (lambda line: print(f"  {line}", file=sys.stderr, flush=True))
    if args.observe is not None and not _is_robot(args):
        raise InputError("--observe BODY goes with --model FILE.xml|FILE.urdf (a model's default scene)")
    if _is_robot(args):
        from relacc.tradeoff import models

        model_result = models.run(args.model, quick=args.quick, seed=args.seed, progress=progress,
                                  observe=args.observe)
        print(json.dumps(model_result.as_json(), indent=2) if args.json else models.format_text(model_result))
        return model_result.exit_code
    result = tradeoff.run(quick=args.quick, seed=args.seed, progress=progress, fixture=fixtures.load(args.model))
    if args.json:
        print(json.dumps(result.as_json(), indent=2))
        return 0
    print(tradeoff.format_text(result))
    return 0


def cmd_report(args) -> int:
    if _is_robot(args):
        from relacc.report import model as model_report

        if args.processes is not None:
            raise InputError("--processes applies to the chain's report; a model file's report runs in one process")
        path, agree, notes = model_report.write(args.model, args.out, n_states=args.states, seed=args.seed,
                                                quick=args.quick, progress=_progress(args))
        print(f"wrote {path}: {'everything agrees' if agree else 'DISAGREEMENTS found (see the verdict)'}")
        for line in notes:
            print(line)
        return 0 if agree else 1
    from relacc.report import build_report, default_second

    path, ctx = build_report(out=args.out, n_states=args.states, seed=args.seed, quick=args.quick,
                             model=args.model, progress=_progress(args),
                             second=default_second(args.quick) if args.processes is None else args.processes == 2)
    failures = ctx.failures()
    verdict = "everything agrees" if not failures else "DISAGREEMENTS found (see the verdict)"
    print(f"wrote {path}: {verdict}")
    for line in failures:
        print(f"  {line}")
    return 0 if not failures else 1
