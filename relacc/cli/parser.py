"""The ``relacc`` argument parser: every subcommand with a description, examples and its exit codes.

Common flags mean the same everywhere they appear: ``--json`` (print JSON on
stdout instead of text), ``--seed`` (the seed of every random state, an
integer >= 0), ``--model`` (a chain TOML; default: the shipped
``two_body.toml``), ``--quiet`` (no progress on stderr).
"""

from __future__ import annotations

import argparse
import sys

EXIT_CODES = """exit codes:
  0  success: everything compared agrees
  1  a disagreement: a comparison is outside its tolerance
  2  a usage or input error (one line on stderr); for grade, a function that cannot be called
  3  an internal error of relacc's (one line on stderr; please report it with the command and its files)"""

def _engine_names() -> tuple[str, ...]:
    """The engines relacc has, in report order: each package ``relacc/engines/<name>_/`` with a ``card.py`` (its
    :class:`relacc.engines.traits.Traits`, ordered by its ``order``), found without importing ``relacc.engines`` so
    that ``--help`` stays light (the registry loads numpy); ``tests/test_layout.py`` holds it to
    :data:`relacc.engines.ENGINES`."""
    import importlib.util
    import re
    from pathlib import Path

    spec = importlib.util.find_spec("relacc.engines")
    found = []
    for folder in (spec.submodule_search_locations or []) if spec else []:
        for card in Path(folder).glob("*_/card.py"):  # each name="..." with its order=N in one call (a package
            # may declare several loadings of its engine, Traits(...) or replace(...))
            text = card.read_text(encoding="utf-8")
            for name, order in re.findall(r'\bname="([^"]+)"[^\n]*?\border=(\d+)', text):
                found.append((int(order), name))
    return tuple(name for _, name in sorted(found))


ENGINE_NAMES = _engine_names()
SIM_ENGINE_NAMES = ("relacc",) + ENGINE_NAMES
INTEGRATOR_NAMES = ("rk4", "euler", "implicit", "implicitfast")
MAX_STATES = 10**9
"""Largest --states any command accepts (larger requests are refused before any work)."""
MAX_SEED = 2**63 - 1


def _observe(p) -> None:
    p.add_argument("--observe", metavar="BODY", default=None,
                   help="with --model FILE.xml|FILE.urdf: the body at whose mass centre the engines are compared "
                        "(default: the body whose mass centre moves fastest at the start)")


class OneLineParser(argparse.ArgumentParser):
    """argparse, but a usage error is one line on stderr (``relacc <cmd>: error: ...``) and exit 2."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _int_in(low: int, high: int):
    def convert(text: str) -> int:
        try:
            value = int(text, 10)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"must be at least {low}, got {value}")
        if value > high:
            raise argparse.ArgumentTypeError(f"must be at most {high:g}, got {value}")
        return value

    return convert


def _positive_float():
    def convert(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        if not (value > 0 and value < float("inf")):
            raise argparse.ArgumentTypeError(f"expected a positive finite number, got {text!r}")
        return value

    return convert


def _choices_list(name: str, allowed):
    """A comma-separated subset of ``allowed``, as a tuple in the given order."""
    def convert(text: str) -> tuple:
        items = tuple(x.strip() for x in text.split(",") if x.strip())
        bad = [x for x in items if x not in allowed]
        if not items or bad:
            raise argparse.ArgumentTypeError(f"unknown {name.lstrip('-')} {bad or [text]}: accepted are a "
                                             f"comma-separated subset of {','.join(allowed)}")
        twice = sorted({x for x in items if items.count(x) > 1})
        if twice:
            raise argparse.ArgumentTypeError(f"{name} names {', '.join(twice)} twice; name each once")
        return items

    return convert


def _variant(text: str):
    """``corrected``, ``printed`` or comma-separated equation ids (as the API's ``variant=``)."""
    if text in ("corrected", "printed"):
        return text
    from relacc.core.note.equations import IDS

    ids = [x.strip() for x in text.split(",") if x.strip()]
    bad = [x for x in ids if x not in IDS]
    if not ids or bad:
        raise argparse.ArgumentTypeError(f"expected corrected, printed or equation ids from "
                                         f"{', '.join(IDS)}; got {text!r}")
    return frozenset(ids)


def _case(text: str) -> int:
    """One case number; the message is the API's (:func:`relacc.core.cases.as_case`)."""
    if text.strip() not in ("1", "2", "3"):
        raise argparse.ArgumentTypeError(f"unknown case {text!r}: accepted cases are 1, 2 and 3")
    return int(text)


def _cases(text: str) -> tuple[int, ...]:
    items = [x.strip() for x in text.split(",") if x.strip()]
    if not items or any(x not in ("1", "2", "3") for x in items):
        raise argparse.ArgumentTypeError(f"expected a comma-separated subset of 1,2,3, got {text!r}")
    return tuple(int(x) for x in items)


def _sub(sub, name, help_, description, examples):
    epilog = "examples:\n" + "\n".join(f"  {e}" for e in examples) + "\n\n" + EXIT_CODES
    return sub.add_parser(name, help=help_, description=description, epilog=epilog,
                          formatter_class=argparse.RawDescriptionHelpFormatter)


def _model(p, files="a chain TOML"):
    p.add_argument("--model", metavar="PATH", default=None,
                   help=f"the model file ({files}; default: the shipped two_body.toml, never read from the "
                        "working directory)")


def _seed(p, default=0):
    p.add_argument("--seed", type=_int_in(0, MAX_SEED), default=default,
                   help="seed of every random state, an integer >= 0 (default 0)")


def _json(p, what="the result"):
    p.add_argument("--json", action="store_true", help=f"print JSON on stdout instead of text ({what})")


def _quiet(p):
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")


def _address(text: str) -> str:
    """A scheduler address, not blank (an empty one would otherwise run here, unasked)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("expected local, local:N or tcp://host:port, got an empty address")
    return text


def _scheduler(p, what):
    p.add_argument("--scheduler", metavar="ADDRESS", type=_address,
                   help=f"run {what} on a Dask cluster: local or local:N (N worker processes here, started and "
                        "stopped by relacc) or tcp://host:port (a running `dask scheduler`); the same seed gives "
                        "the same answer")


def _states(p, default, what="states per case", shown=None):
    p.add_argument("--states", type=_int_in(1, MAX_STATES), default=default, metavar="N",
                   help=f"{what} (default {default if shown is None else shown})")


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(
        prog="relacc",
        description="Check the relative-coordinate formulas of a two-body chain (the velocity and classical "
                    "acceleration of G2) against Pinocchio, MuJoCo and Drake.",
        epilog="examples:\n  relacc check\n  relacc report --quick --out report.html\n  relacc simulate tumbling\n\n"
               + EXIT_CODES + "\n\nrelacc COMMAND --help describes each command.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    from relacc import __version__

    parser.add_argument("--version", action="version", version=f"relacc {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=OneLineParser)

    p = _sub(sub, "eval", "evaluate G2's kinematics for one state",
             "G2's position, velocity, classical acceleration, V and Vdot for one state, every number with its "
             "point, frame of components and units. The state comes from flags or a JSON file "
             '{"case": 1, "q": [...], "u": [...], "udot": [...], "variant": "corrected"}.',
             ["relacc eval --case 3 --q 0,0,0,0.1,0.2,0.3,0,0,0,0,0,0 --u 0,0,0,0,0,1,0,0,0,0,0,0",
              "relacc eval state.json --json", "echo '{\"case\": 2, ...}' | relacc eval -"])
    p.add_argument("state", nargs="?", metavar="STATE.json",
                   help="JSON file (or - for stdin) with case, q, u and optionally udot, variant")
    p.add_argument("--case", type=_case, metavar="{1,2,3}",
                   help="the choice of generalized speeds: 1 fixed-frame, 2 body-frame angular velocity, "
                        "3 1-2-3 angle rates")
    p.add_argument("--q", help="coordinates, comma or space separated (14 for cases 1-2, 12 for case 3)")
    p.add_argument("--u", help="generalized speeds (12)")
    p.add_argument("--udot", help="their time derivatives (12)")
    p.add_argument("--variant", type=_variant, metavar="VARIANT",
                   help="corrected (default), printed, or comma-separated equation ids taken as printed "
                        "(e.g. eq9.2,case2-a.2)")
    _json(p)
    _model(p)

    p = _sub(sub, "check", "cross-validate the core against the engines",
             "Every case x engine x route x quantity: the core's corrected formulas against each engine on the "
             "same seeded states; the error is normalized by the magnitude of the terms and held to the error "
             "model. States are generated and evaluated in chunks, so memory stays bounded for any --states.",
             ["relacc check", "relacc check --states 100000 --cases 3 --engines mujoco",
              "relacc check --json --seed 7 > check.json",
              "relacc check --states 100000000 --scheduler tcp://10.0.0.5:8786"])
    _states(p, None, shown="1000 for the chain, 20 for a model file: each of its states is a full dynamics "
                           "evaluation per engine")
    _seed(p)
    p.add_argument("--cases", type=_cases, default=(1, 2, 3), metavar="1,2,3",
                   help="comma-separated subset of 1,2,3 (default all)")
    p.add_argument("--engines", type=_choices_list("--engines", ENGINE_NAMES), default=None,
                   metavar=",".join(ENGINE_NAMES), help="comma-separated engines (default: every one installed)")
    _json(p)
    _quiet(p)
    _model(p, "a chain TOML, or an MJCF .xml or URDF .urdf model")
    _scheduler(p, "the sweep (tasks of at least 100,000 states)")

    p = _sub(sub, "errata", "evaluate every printed formula of the note against the engines",
             "For each equation id of the note: ok, wrong, ambiguous or missing, with the normalized error of "
             "its printed form and of the corrected form against every engine.",
             ["relacc errata", "relacc errata --json"])
    _states(p, 1000)
    _seed(p)
    p.add_argument("--engines", type=_choices_list("--engines", ENGINE_NAMES), default=None,
                   metavar=",".join(ENGINE_NAMES), help="comma-separated engines (default: every one installed)")
    _json(p, "a list, one object per equation id")
    _quiet(p)
    _model(p)

    p = _sub(sub, "grade", "grade your own implementation of a formula against the engines",
             "Call MODULE:FUNCTION as fn(chain, q, u, udot) on ordinary and hard states of a case (one state: "
             "q (nq,), u (12,), udot (12,), the case's coordinates; a function that takes whole batches works "
             "too) and compare what it returns with every engine and relacc's corrected formulas: G2's "
             "position, velocity or classical acceleration (3,), or V / Vdot (3, 12), fixed-frame components. "
             "When it is wrong: which generalized-speed columns disagree, and which of the note's known slips "
             "reproduce it. MODULE is a dotted module or a path to a .py file.",
             ["relacc grade examples/student_correct.py:acceleration --quantity acceleration --case 1",
              "relacc grade mypkg.kinematics:v_g2 --quantity velocity --case 2 --json",
              "relacc grade examples/student_arm.py:velocity --model examples/three_link_arm.xml --body forearm "
              "--quantity velocity --case 2"])
    p.add_argument("function", metavar="MODULE:FUNCTION", help="the formula to grade")
    p.add_argument("--quantity", required=True, choices=("position", "velocity", "acceleration", "omega", "alpha",
                                                          "V", "Vdot", "Omega", "Omegadot"),
                   help="what the function returns (omega, alpha, Omega, Omegadot: a model's body, with --body)")
    p.add_argument("--body", metavar="NAME", default=None,
                   help="with --model FILE.xml|FILE.urdf: the body whose quantity fn(tree, q, u, udot) returns, at "
                        "its mass centre")
    p.add_argument("--case", required=True, type=_case, metavar="{1,2,3}", help="the case of its q and u")
    _states(p, 200, "ordinary states, and as many hard ones")
    _seed(p)
    p.add_argument("--timeout", type=_positive_float(), default=120.0, metavar="SECONDS",
                   help="seconds the function may take over one batch of states before it is stopped (default 120); "
                        "it runs in a child process, imported there only")
    _json(p, "ok, worst_error, columns, matches, seed")
    _model(p, "a chain TOML, or an MJCF .xml or URDF .urdf model")

    p = _sub(sub, "fixtures", "write a chain's engine model files (and export them with their conventions)",
             "Render the MJCF and URDF files of a chain from its TOML source, beside it, all or nothing; each file "
             "carries the SHA-256 of the chain it came from. With --out, export instead: the chain's TOML, its "
             "engine files and conventions.json (every engine's coordinate layout and the map from each case's q "
             "and u to it), into DIR; --q2, --r2, ... change the chain first.",
             ["relacc fixtures --check", "relacc fixtures --model my_chain.toml",
              "relacc fixtures --out exported/ --q2 0.3,0,0.1 --m2 1.5"])
    p.add_argument("--check", action="store_true", help="only check that the files are up to date (exit 1 if not)")
    p.add_argument("--out", metavar="DIR", help="export the chain, its engine files and conventions.json to DIR")
    p.add_argument("--name", help="the exported chain's name")
    for flag, what in (("--q2", "q2' (3 numbers, m, B1 components)"), ("--r2", "r2' (3 numbers, m, B2 components)"),
                       ("--r1", "r1' (3 numbers, m, B1 components)"), ("--m1", "mass of B1 (kg)"),
                       ("--m2", "mass of B2 (kg)"), ("--I1", "inertia of B1 about G1 (9 numbers, row-major, kg m^2)"),
                       ("--I2", "inertia of B2 about G2 (9 numbers, row-major, kg m^2)")):
        p.add_argument(flag, help=f"with --out: {what}")
    _model(p)

    p = _sub(sub, "simulate", "run a scene on relacc and the engines and compare them",
             "Integrate a scene (which chain, from which state, under which effects, for how long) on every "
             "engine it lists and compare G2 along the runs. SCENE is a TOML file or the name of a shipped "
             "scene. The verdict: at the same states every engine's acceleration must be relacc's within c eps "
             "kappa(M) (the trajectories differ by each integrator's truncation: shown, not judged); exit 1 when one "
             "is not (that engine reads the model or the scene's effects differently).",
             ["relacc simulate tumbling", "relacc simulate my_scene.toml --out runs/ --json",
              "relacc simulate gimbal_spin --engines relacc,mujoco --dt 1e-4",
              "relacc simulate tumbling --ensemble 1000 --spread 0.05 --engines relacc,mujoco",
              "relacc simulate ant_tumbling", "relacc simulate --model robot.xml --duration 0.5"])
    p.add_argument("scene", metavar="SCENE", nargs="?", default=None,
                   help="scene TOML file, or a shipped scene's name (tumbling, gravity_spring, forced_damped, "
                        "gimbal_spin, ant_tumbling, kuka_swinging); or give --model")
    _model(p, "an MJCF .xml or URDF .urdf, or a chain TOML: its default scene, tumbling in space from its "
              "reference configuration with speeds from --seed, nothing acting")
    p.add_argument("--out", metavar="DIR", help="a new directory for one CSV per engine")
    _json(p, "the summary")
    p.add_argument("--engines", type=_choices_list("--engines", SIM_ENGINE_NAMES), metavar="ENGINES",
                   help=f"comma-separated subset of {','.join(SIM_ENGINE_NAMES)}")
    p.add_argument("--dt", type=_positive_float(), help="override the scene's time step (s)")
    p.add_argument("--duration", type=_positive_float(), help="override the scene's duration (s)")
    p.add_argument("--integrator", choices=INTEGRATOR_NAMES, help="override the scene's integrator")
    p.add_argument("--ensemble", type=_int_in(1, 10**7), metavar="N",
                   help="run N members from perturbed initial states (member 0: the scene's own) on every engine's "
                        "batched API, and report steps per second and the largest G2 difference per member")
    p.add_argument("--spread", type=_positive_float(), default=None,
                   help="with --ensemble: size of the perturbations (m, rad, m/s, rad/s; default 0.05)")
    _seed(p, default=None)
    _observe(p)
    _quiet(p)
    _scheduler(p, "an --ensemble (one task per 1,024 members)")

    p = _sub(sub, "compare", "does each engine read the robot the file describes?",
             "relacc reads the MJCF or URDF itself, by the format's specification, and holds MuJoCo, Pinocchio (its "
             "MJCF parser) and Drake to that reading: it audits what each made of the file (joints, axes, "
             "masses, inertias, armature, damping, gravity), each difference with its cause and its place in the "
             "file, compares their dynamics (mass matrix, bias and gravity forces, forward dynamics, each link's "
             "centre-of-mass Jacobian, J_dot v and classical acceleration) at the reference configuration and at "
             "random states through speed maps, names the odd one out (engine against engine too), and names the "
             "bodies that are not physical. An engine that refuses the file is one line; the others are compared. "
             "Exit 1 when anything differs or a body is not physical, 2 when relacc cannot read the file or no "
             "engine takes part.",
             ["relacc compare robot.xml", "relacc compare robot.xml --engines pinocchio,mujoco",
              "relacc compare robot.xml --json --out robot.html",
              "relacc compare models/*.xml --scheduler local:2 --json > all.json",
              "relacc compare path/to/robots/ --states 5"])
    p.add_argument("model", metavar="MODEL.xml", nargs="+",
                   help="the MJCF file (or a URDF, which every engine then reads by its URDF parser); several, or a "
                        "directory (its .xml and .urdf files, in sorted order, searched recursively): each compared "
                        "alone, one summary (exit: the highest of theirs)")
    p.add_argument("--urdf", metavar="MODEL.urdf",
                   help="a URDF of the same robot: the two files are compared by relacc diff MODEL.urdf MODEL.xml "
                        "(said on stderr); compare reads one file in every engine")
    p.add_argument("--engines", type=_choices_list("--engines", ENGINE_NAMES), metavar="ENGINES",
                   help=f"comma-separated subset of {','.join(ENGINE_NAMES)} (default: those installed)")
    _states(p, 20, "random states besides the reference configuration")
    _seed(p)
    _json(p, "the summary")
    p.add_argument("--out", metavar="PAGE.html", help="also write a self-contained HTML page, atomically (several "
                   "models: one page, a row per model linked to its sections)")
    p.add_argument("--verbose", action="store_true", help="several models: each model's detail after the summary "
                   "(the summary alone by default)")
    p.add_argument("--xacro-arg", action="append", default=[], metavar="NAME:=VALUE",
                   help="an argument of the .xacro files compared ($(arg NAME)), as ROS's xacro takes it; repeat for "
                        "several")
    p.add_argument("--models-only", action="store_true",
                   help="skip, and say so in one line, the files given that are not robot descriptions (an XML whose "
                        "root is neither <mujoco> nor <robot>: a ROS package.xml, a launch file, an MJCF fragment) or "
                        "hold no robot to compare (a xacro of macros or a fragment, nothing that moves): what a "
                        "pre-commit hook passes")
    p.add_argument("--junit", metavar="FILE.xml",
                   help="also write JUnit XML: one testcase per model, failing with each result at file:line "
                        "(docs/ci.md)")
    p.add_argument("--sarif", metavar="FILE.sarif", help="also write SARIF 2.1.0 (GitHub code scanning shows it "
                   "inline): one result per finding, audit difference, dynamics row and refusal, each with its rule, "
                   "level and file:line (docs/ci.md)")
    p.add_argument("--baseline", metavar="FILE.json", help="results this file accepts (written by --write-baseline) "
                   "do not fail the run: a repository with known issues fails only on new ones")
    p.add_argument("--write-baseline", metavar="FILE.json", help="write every failing result as accepted, for "
                   "--baseline")
    _scheduler(p, "one task per model")
    _quiet(p)

    p = _sub(sub, "diff", "are two descriptions (a URDF and its MJCF) the same robot? what differs, where",
             "relacc reads both files itself (MJCF, URDF or xacro, each by its format's specification), fuses each "
             "body welded to another into one moving part (a URDF link on a fixed joint, an MJCF body without "
             "joints; bodies welded to the world are the world's), matches parts and joints by name, then by "
             "structure, and compares what the physics depends on whatever frames each file chose: each part's mass, "
             "mass centre and inertia, each joint's type, axis, anchor, zero, armature, damping, spring and range, "
             "and gravity, at the reference configuration, after the one rigid motion that places B's robot on A's. "
             "Each difference is classified (changed, added, dropped, rounded, placement, convention, unmatched) and "
             "located (file:line in each). Then the mass matrix, bias forces and forward dynamics of both at matched "
             "coordinates. A difference counts beyond what printing each number to 6 significant digits can change "
             "(relative 5e-6 of the magnitude of the terms it is formed from; --rtol widens it). Exit 0: the same "
             "robot; 1: differences; 2: a file relacc cannot read.",
             ["relacc diff robot.urdf robot.xml", "relacc diff old.urdf new.urdf --json > changes.json",
              "relacc diff arm.urdf.xacro arm.xml --xacro-arg prefix:=left_ --rtol 1e-4"])
    p.add_argument("model", metavar="FILE", nargs=2, help="A and B: two descriptions (.xml MJCF, .urdf, .xacro)")
    p.add_argument("--rtol", type=_positive_float(), default=None, metavar="R",
                   help="the relative error allowed each printed number (default 5e-6: half a unit in the 6th "
                        "significant digit; only wider is accepted)")
    _states(p, 8, "random states besides the reference configuration, for the dynamics")
    _seed(p)
    _json(p, "the differences (docs/diff.md gives the contract)")
    p.add_argument("--xacro-arg", action="append", default=[], metavar="NAME:=VALUE",
                   help="an argument of a .xacro file ($(arg NAME)); repeat for several")
    p.add_argument("--junit", metavar="FILE.xml", help="also write JUnit XML: one testcase, failing with each "
                   "difference at its file:line in B (docs/ci.md)")
    p.add_argument("--sarif", metavar="FILE.sarif", help="also write SARIF 2.1.0: one result (RELACC010) per "
                   "difference, at its file:line in B (docs/ci.md)")
    p.add_argument("--engines", nargs="?", const=(), default=None,
                   type=_choices_list("--engines", ENGINE_NAMES), metavar="ENGINES",
                   help="also say in one line per file whether the engines (default: every one installed) read it as "
                        "relacc does: relacc compare's verdict on each file, a few seconds each")
    p.add_argument("--out", metavar="PAGE.html", help="also write a self-contained HTML page, atomically: the two "
                   "trees side by side with each difference numbered at its element")

    p = _sub(sub, "tradeoff", "work-precision sweeps: accelerations and integrators",
             "What accuracy costs in time: G2's acceleration by the analytic formulas, finite differences, "
             "Richardson, complex step and the engines (on --model's chain); whole trajectories by every "
             "engine's integrators (on each shipped scene's own chain).",
             ["relacc tradeoff --quick", "relacc tradeoff --json > tradeoff.json"])
    p.add_argument("--quick", action="store_true", help="a small sweep (seconds)")
    _json(p, "all points and orders")
    _seed(p)
    _observe(p)
    _quiet(p)
    _model(p, "a chain TOML, or an MJCF .xml or URDF .urdf model: its default scene's integrator sweep")

    p = _sub(sub, "report", "write the self-contained HTML agreement report",
             "Run the cross-validation, errata, hard cases, scenes, tradeoff and throughput, and write one "
             "self-contained HTML page (no network needed to view it), atomically.",
             ["relacc report", "relacc report --quick --out /tmp/report.html",
              "relacc report --model robot.xml --out /tmp/robot.html"])
    p.add_argument("--out", metavar="FILE", default="reports/agreement.html",
                   help="output file (default reports/agreement.html, relative to the working directory)")
    p.add_argument("--states", type=_int_in(1, 10**6), default=None, metavar="N",
                   help="states per case (default 2000, --quick 200; a model file: 20, --quick 5)")
    _seed(p)
    p.add_argument("--quick", action="store_true", help="a small run for tests and CI")
    p.add_argument("--processes", type=_int_in(1, 2), default=None, metavar="N",
                   help="1: everything in this process; 2: the scenes, sweeps, hard cases and Hypothesis search "
                        "shared with a second one (default: 2 for a full report on a machine with 2 cores or more, "
                        "else 1; the benchmarks run alone either way)")
    _quiet(p)
    _model(p, "a chain TOML, or an MJCF .xml or URDF .urdf model: its audit, per-body agreement in the three "
              "cases, conventions, referee and default scene")
    return parser


def subcommands(parser: argparse.ArgumentParser) -> dict:
    """``{name: subparser}`` of a parser built by :func:`build_parser` (for tests and docs)."""
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


if __name__ == "__main__":  # pragma: no cover
    build_parser().print_help(sys.stdout)
