"""The ``relacc`` command line.

Subcommands: ``eval`` (one state), ``check`` (cross-validation), ``errata``
(where the note is wrong), ``fixtures`` (write the engine model files),
``report`` (the HTML agreement report). Every :class:`relacc.RelaccError`
becomes one line on stderr and exit status 2; a failed check exits 1.
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

import relacc
from relacc import fixtures
from relacc.cases import as_case
from relacc.conventions import CASE_NAMES, CONVENTIONS, COORDINATES, QUANTITIES, SPEEDS
from relacc.errors import InputError, RelaccError
from relacc.tolerances import EPS


def _numbers(text: str, name: str) -> list[float]:
    try:
        return [float(x) for x in text.replace(",", " ").split()]
    except ValueError:
        raise InputError(f"--{name}: expected numbers separated by commas or spaces, got {text!r}") from None


def _state_from_args(args) -> dict:
    state = {}
    if args.state:
        try:
            text = sys.stdin.read() if args.state == "-" else open(args.state, encoding="utf-8").read()
        except OSError as exc:
            raise InputError(f"{args.state}: cannot read the state file ({exc.strerror or exc})") from None
        try:
            state = json.loads(text)
        except json.JSONDecodeError as exc:
            raise InputError(f"{args.state}: not valid JSON: {exc}") from None
        if not isinstance(state, dict):
            raise InputError(f"{args.state}: expected a JSON object with case, q, u (and udot)")
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
    from relacc.check import Harness

    engines = args.engines.split(",") if args.engines else None
    kwargs = {} if engines is None else {"engines": engines}
    return Harness(fixtures.load(args.model), n_states=args.states, seed=args.seed,
                   progress=_progress(args), **kwargs)


def _cases(text) -> tuple[int, ...]:
    try:
        return tuple(int(as_case(int(x))) for x in text.split(","))
    except ValueError:
        raise InputError(f"--cases: expected comma-separated case numbers (1, 2, 3), got {text!r}") from None


def cmd_check(args) -> int:
    harness = _harness(args)
    report = harness.check(cases=_cases(args.cases))
    if args.json:
        print(json.dumps(report.as_dict(), indent=2))
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
    n, bad = len(report.comparisons), len(report.failures)
    print(f"\n{'all ' + str(n) + ' comparisons agree' if not bad else f'{bad} of {n} comparisons DISAGREE'}")
    return 0 if report.passed else 1


def cmd_errata(args) -> int:
    from relacc.errata import errata

    harness = _harness(args)
    items = errata(harness)
    ok = all(e.agrees for e in items)
    if args.json:
        print(json.dumps([e.as_dict() for e in items], indent=2))
        return 0 if ok else 1
    print(f"relacc errata: {harness.n_states} states per case, seed {harness.seed}, engines "
          f"{', '.join(harness.engines)}; errors are max normalized errors (tolerance "
          f"{items[0].tolerance:.3g})")
    print(f"{'id':15s}  {'status':9s}  {'printed':>9s}  {'corrected':>9s}  explanation")
    for e in items:
        p = "-" if e.printed_error is None else f"{e.printed_error:9.2e}"
        print(f"{e.id:15s}  {e.status:9s}  {p:>9s}  {e.corrected_error:9.2e}  {e.equation.explanation}")
    return 0 if ok else 1


def cmd_fixtures(args) -> int:
    fixture = fixtures.load(args.model)
    changed = fixtures.write(fixture, check=args.check)
    if args.check:
        if changed:
            print(f"out of date: {', '.join(changed)} (run `relacc fixtures` to regenerate)", file=sys.stderr)
            return 1
        print(f"up to date: {', '.join(fixtures.MODEL_FILES)}")
        return 0
    print(f"wrote {', '.join(changed)}" if changed else "already up to date")
    return 0


def cmd_simulate(args) -> int:
    import time as _time

    from relacc import scenes, simulate

    scene = scenes.load(args.scene)
    changes = {k: v for k, v in (("dt", args.dt), ("integrator", args.integrator), ("duration", args.duration))
               if v is not None}
    if args.engines:
        changes["engines"] = tuple(args.engines.split(","))
    if changes:
        scene = scene.replace(**changes)
    start = _time.perf_counter()
    last = [0.0]

    def progress(engine, fraction):  # a progress bar once the run has taken more than 2 s
        now = _time.perf_counter()
        if args.quiet or now - start < 2.0 or now - last[0] < 0.2:
            return
        last[0] = now
        bar = "#" * int(30 * fraction)
        print(f"\r  {engine:9s} [{bar:30s}] {100 * fraction:5.1f} %", end="", file=sys.stderr, flush=True)

    result = simulate.run(scene, progress=progress)
    if _time.perf_counter() - start >= 2.0 and not args.quiet:
        print(file=sys.stderr)
    if args.out:
        for path in simulate.write_csv(result, args.out):
            if not args.json:
                print(f"wrote {path}")
    summary = result.summary()
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0
    print(simulate.format_text(result))
    return 0


def cmd_tradeoff(args) -> int:
    from relacc import tradeoff

    progress = None if (args.quiet or args.json) else (lambda line: print(f"  {line}", file=sys.stderr, flush=True))
    result = tradeoff.run(quick=args.quick, seed=args.seed, progress=progress)
    if args.json:
        print(json.dumps(result.as_json(), indent=2))
        return 0
    print(tradeoff.format_text(result))
    return 0


def cmd_report(args) -> int:
    from relacc.report import build_report

    path, ctx = build_report(out=args.out, n_states=args.states, seed=args.seed, quick=args.quick,
                             model=args.model, progress=_progress(args))
    agree = ctx.check.passed and all(e.agrees for e in ctx.errata)
    verdict = "everything agrees" if agree else "DISAGREEMENTS found (see the verdict)"
    print(f"wrote {path}: {verdict}")
    return 0 if agree else 1


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="relacc",
        description="Check the relative-coordinate formulas of a two-body chain against Pinocchio and MuJoCo.",
    )
    parser.add_argument("--version", action="version", version=f"relacc {relacc.__version__}")
    sub = parser.add_subparsers(dest="command", required=True)

    def model_opt(p):
        p.add_argument("--model", default=None, help="chain TOML (default: models/two_body.toml)")

    p = sub.add_parser("eval", help="evaluate G2's kinematics for one state")
    p.add_argument("state", nargs="?", help="JSON file (or - for stdin) with case, q, u, optional udot, variant")
    p.add_argument("--case", type=int, help="1, 2 or 3")
    p.add_argument("--q", help="coordinates, comma or space separated")
    p.add_argument("--u", help="generalized speeds (12)")
    p.add_argument("--udot", help="their time derivatives (12)")
    p.add_argument("--variant", choices=("corrected", "printed"))
    p.add_argument("--json", action="store_true", help="print JSON")
    model_opt(p)
    p.set_defaults(func=cmd_eval)

    def harness_opts(p, states=1000):
        p.add_argument("--states", type=int, default=states, help=f"states per case (default {states})")
        p.add_argument("--seed", type=int, default=0, help="seed (default 0)")
        p.add_argument("--engines", help="comma-separated: pinocchio,mujoco (default both)")
        p.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
        model_opt(p)

    p = sub.add_parser("check", help="cross-validate the core against the engines")
    harness_opts(p)
    p.add_argument("--cases", default="1,2,3", help="comma-separated cases (default 1,2,3)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("errata", help="evaluate every printed formula of the note against the engines")
    harness_opts(p)
    p.add_argument("--json", action="store_true", help="print a JSON list")
    p.set_defaults(func=cmd_errata)

    p = sub.add_parser("fixtures", help="write the engine model files from the TOML source")
    p.add_argument("--check", action="store_true", help="only check they are up to date")
    model_opt(p)
    p.set_defaults(func=cmd_fixtures)

    p = sub.add_parser("simulate", help="run a scene on relacc, Pinocchio and MuJoCo and compare them")
    p.add_argument("scene", help="scene TOML file (models/scenes/*.toml)")
    p.add_argument("--out", help="directory for one CSV per engine")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.add_argument("--engines", help="comma-separated subset of relacc,pinocchio,mujoco")
    p.add_argument("--dt", type=float, help="override the scene's time step (s)")
    p.add_argument("--duration", type=float, help="override the scene's duration (s)")
    p.add_argument("--integrator", help="override the scene's integrator")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("tradeoff", help="work-precision sweeps: accelerations and integrators")
    p.add_argument("--quick", action="store_true", help="a small sweep (seconds)")
    p.add_argument("--json", action="store_true", help="print all points and orders as JSON")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=cmd_tradeoff)

    p = sub.add_parser("report", help="write the self-contained HTML agreement report")
    p.add_argument("--out", default="reports/agreement.html", help="output file")
    p.add_argument("--states", type=int, default=None, help="states per case (default 2000, --quick 200)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--quick", action="store_true", help="a small run for tests and CI")
    p.add_argument("--quiet", action="store_true")
    model_opt(p)
    p.set_defaults(func=cmd_report)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except RelaccError as exc:
        print(f"relacc {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"relacc {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
