"""Fuzzing: random inputs and malformed files at every public entry point; only RelaccError comes out.

Hypothesis runs under the suite's derandomized "relacc" profile (conftest.py).
"""

import contextlib
import io
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import relacc
from relacc import fixtures
from relacc.cli import main
from relacc.core import speeds
from relacc.core.derivatives import advance
from relacc.validation.check import Harness

REPO = Path(__file__).resolve().parents[1]

FLOATS = st.floats(allow_nan=True, allow_infinity=True, width=64)
SCALARS = st.one_of(st.none(), st.booleans(), st.integers(-10, 10), FLOATS, st.text(max_size=5),
                    st.complex_numbers(max_magnitude=1e3))
ARRAYS = st.one_of(
    hnp.arrays(st.sampled_from([np.float64, np.int64, np.bool_, np.complex128, np.float32]),
               hnp.array_shapes(min_dims=0, max_dims=3, max_side=15), elements=None),
    st.lists(st.one_of(FLOATS, st.integers(-5, 5)), max_size=16),
    st.lists(st.lists(FLOATS, max_size=14), max_size=3),
)
JUNK = st.one_of(SCALARS, ARRAYS, st.dictionaries(st.text(max_size=3), st.integers(), max_size=2))
CASES = st.one_of(st.sampled_from([1, 2, 3, relacc.Case.BODY_FRAME]), SCALARS)


def _unit_q(case, data):
    """A valid coordinate vector for the case, sometimes corrupted by hand."""
    n = 12 if case == 3 else 14
    q = np.array(data.draw(st.lists(st.floats(-1e6, 1e6), min_size=n, max_size=n)))
    if case != 3:
        for sl in (slice(3, 7), slice(10, 14)):
            norm = np.linalg.norm(q[sl])
            q[sl] = q[sl] / norm if norm > 0 else (1, 0, 0, 0)
    return q


def _only_relacc_errors(call):
    try:
        result = call()
    except relacc.RelaccError:
        return None
    return result


def _assert_finite(k):
    for name in ("position", "velocity", "acceleration", "V", "Vdot"):
        value = getattr(k, name)
        assert value is None or np.all(np.isfinite(value)), f"{name} not finite"


@given(CASES, JUNK, JUNK, st.one_of(st.none(), JUNK), st.sampled_from(["corrected", "printed", "x", ("eq4",)]))
def test_g2_kinematics_junk(chain, case, q, u, udot, variant):
    """Any junk q, u, udot, case or variant gives a RelaccError or finite results."""
    k = _only_relacc_errors(lambda: relacc.g2_kinematics(chain, case, q, u, udot, variant=variant))
    if k is not None:
        _assert_finite(k)


@pytest.mark.slow
@given(st.data())
def test_g2_kinematics_valid_shapes_extreme_values(chain, data):
    """Well-shaped states with values up to 1e300 (speeds up to 1e200) give finite results or a RelaccError."""
    case = data.draw(st.sampled_from([1, 2, 3]))
    q = _unit_q(case, data)
    q[:3] *= data.draw(st.sampled_from([1.0, 1e100, 1e300]))
    u = np.array(data.draw(st.lists(st.floats(-1e200, 1e200), min_size=12, max_size=12)))
    k = _only_relacc_errors(lambda: relacc.g2_kinematics(chain, case, q, u, u))
    if k is not None:
        _assert_finite(k)


@given(st.dictionaries(st.sampled_from(["q2", "r2", "r1", "m1", "m2", "I1", "I2"]), JUNK, min_size=0, max_size=7))
def test_two_body_chain_junk(kwargs):
    """TwoBodyChain with junk fields raises RelaccError (or TypeError for missing required arguments)."""
    if "q2" not in kwargs or "r2" not in kwargs:
        kwargs.setdefault("q2", [0.1, 0.2, 0.3])
        kwargs.setdefault("r2", [0.3, 0.2, 0.1])
    _only_relacc_errors(lambda: relacc.TwoBodyChain(**kwargs))


@given(CASES, JUNK, JUNK, st.one_of(st.none(), JUNK))
def test_speed_maps_junk(case, q, nu, nu_dot):
    """body_speed_map, case_speeds, inverse_condition and advance accept only valid input."""
    _only_relacc_errors(lambda: speeds.body_speed_map(case, q, nu))
    _only_relacc_errors(lambda: speeds.case_speeds(case, q, nu, nu_dot))
    _only_relacc_errors(lambda: speeds.inverse_condition(case, q))
    _only_relacc_errors(lambda: advance(case, q, nu, nu_dot if isinstance(nu_dot, (int, float)) else 0.1))


@given(st.data())
def test_malformed_model_files(tmp_path_factory, fixture, data):
    """Random edits of the model TOML (deleted, duplicated or altered lines) give a FixtureError or a chain."""
    lines = fixture.source.read_text().splitlines()
    for _ in range(data.draw(st.integers(1, 4))):
        i = data.draw(st.integers(0, len(lines) - 1))
        action = data.draw(st.sampled_from(["delete", "duplicate", "garble", "value"]))
        if action == "delete":
            del lines[i]
        elif action == "duplicate":
            lines.insert(i, lines[i])
        elif action == "garble":
            lines[i] = data.draw(st.text(max_size=20))
        elif "=" in lines[i]:
            key = lines[i].split("=")[0]
            lines[i] = key + "= " + data.draw(st.sampled_from(
                ["nan", "inf", "-1", "[1, 2]", '"x"', "[[1,0,0],[0,1,0],[0,0,-1]]", "[1e400, 0, 0]", "0", "true"]))
        if not lines:
            break
    path = tmp_path_factory.mktemp("fuzz") / "chain.toml"
    path.write_text("\n".join(lines))
    _only_relacc_errors(lambda: fixtures.load(path))


ARGV = st.lists(st.one_of(
    st.sampled_from(["eval", "check", "errata", "fixtures", "--case", "--q", "--u", "--udot", "--json", "--states",
                     "--seed", "--engines", "--cases", "--check", "--variant", "printed", "1", "3", "7", "-1",
                     "0,0,0,1,0,0,0,0,0,0,1,0,0,0", "mujoco", "bullet", "1,2", "a", "--model", "nope.toml", "-"]),
    st.text(max_size=6)), max_size=8)


@pytest.mark.slow
@given(ARGV)
def test_cli_never_raises(argv):
    """The command line exits 0, 1 or 2 (argparse usage errors: 2) and never shows a traceback."""
    if argv and argv[0] in ("check", "errata"):
        argv = argv + ["--states", "2", "--quiet"]
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse's usage errors
            code = exc.code
    assert code in (0, 1, 2), code
    assert "Traceback" not in err.getvalue()


@given(JUNK, JUNK, st.sampled_from(["pinocchio", "mujoco", "bullet", 3]))
def test_harness_and_engines_junk(fixture, n_states, seed, engine):
    """Harness and engine loading reject junk with RelaccError."""
    _only_relacc_errors(lambda: Harness(fixture, engines=(engine,), n_states=n_states, seed=seed))


@pytest.mark.slow
@given(st.data())
def test_malformed_scene_files(tmp_path_factory, data):
    """Random edits of a shipped scene (lines deleted, garbled, values replaced) give a FixtureError or a scene."""
    from relacc.fixtures import shipped
    from relacc.simulate import scenes

    source = shipped.scene_paths()[0]
    lines = source.read_text().splitlines()
    for _ in range(data.draw(st.integers(1, 3))):
        i = data.draw(st.integers(0, len(lines) - 1))
        action = data.draw(st.sampled_from(["delete", "garble", "value"]))
        if action == "delete":
            del lines[i]
        elif action == "garble":
            lines[i] = data.draw(st.text(max_size=20))
        elif "=" in lines[i]:
            lines[i] = lines[i].split("=")[0] + "= " + data.draw(st.sampled_from(
                ["nan", "-1", "[1, 2]", '"rk9"', '["bullet"]', "0", "1e300", "[]", "true", '"two_body"']))
        if not lines:
            break
    models = tmp_path_factory.mktemp("scene") / "models"
    (models / "scenes").mkdir(parents=True)
    for f in source.parent.parent.glob("two_body*"):
        (models / f.name).write_text(f.read_text())
    path = models / "scenes" / "s.toml"
    path.write_text("\n".join(lines))
    _only_relacc_errors(lambda: scenes.load(path))


@given(CASES, JUNK, JUNK)
def test_equations_of_motion_junk(chain, case, q, u):
    """Kane's equations reject junk with RelaccError; what they return is finite."""
    from relacc import dynamics

    out = _only_relacc_errors(lambda: dynamics.equations_of_motion(chain, case, q, u))
    if out is not None:
        assert all(np.all(np.isfinite(a)) for a in out)


JUNK_VALUES = {
    "--states": ["0", "-1", "1e3", "abc", "", "99999999999", "1.5"],
    "--seed": ["-1", "x", "1.5", "", "9" * 30],
    "--engines": ["bullet", "", ",", "pinocchio,bullet"],
    "--cases": ["0", "4", "1,,x", "a", ""],
    "--variant": ["eq99", "", "printed,corrected"],
    "--dt": ["0", "-1", "nan", "inf", "x"],
    "--duration": ["0", "-1e-3", "nan", "x"],
    "--integrator": ["rk5", ""],
    "--case": ["0", "4", "x", "1.0"],
    "--quantity": ["speed", "", "v"],
    "--q2": ["1,2", "a,b,c", "1,2,nan", ""],
    "--m2": ["-1", "0", "x", "1,2"],
    "FUNCTION": ["nofunction", "missing.py:f", "json:nothing_here", ":f", "os:getcwd", "json:loads"],
}
"""Values each flag never accepts."""

COMMANDS = {
    "eval": (["--case", "1", "--q", "0,0,0,1,0,0,0,0,0,0,1,0,0,0", "--u", ",".join(["0"] * 12)],
             ["--case", "--variant", "--model", "STATE"]),
    "check": (["--states", "3", "--cases", "2", "--engines", "mujoco", "--quiet"],
              ["--states", "--seed", "--engines", "--cases", "--model"]),
    "errata": (["--states", "3", "--engines", "mujoco", "--quiet"], ["--states", "--seed", "--engines", "--model"]),
    "fixtures": (["--check"], ["--model"]),
    "simulate": (["tumbling", "--duration", "0.002", "--quiet"],
                 ["--dt", "--duration", "--integrator", "--engines", "--out", "SCENE"]),
    "tradeoff": (["--quick", "--quiet"], ["--seed", "--model"]),
    "report": (["--quick", "--quiet", "--out", "r.html"], ["--states", "--seed", "--out", "--model"]),
    "grade": (["examples/student_correct.py:V", "--quantity", "V", "--case", "1", "--states", "3"],
              ["--quantity", "--case", "--states", "--seed", "--model", "FUNCTION"]),
    "export": (["--out", "exported"], ["--q2", "--m2", "--model"]),
    "compare": (["models/two_body.xml", "--states", "2", "--engines", "pinocchio"],
                ["--states", "--seed", "--engines", "--out", "--urdf", "MODEL"]),
}
"""Each command: valid, cheap arguments, and the arguments fuzzed one at a time."""


@pytest.mark.slow
@given(st.sampled_from(sorted(COMMANDS)), st.data())
def test_every_command_turns_malformed_input_into_one_line_and_exit_2(tmp_path_factory, command, data):
    """Every command with one argument malformed (bad values, junk files, bad paths): exit 2, one line."""
    base, fuzzed = COMMANDS[command]
    flag = data.draw(st.sampled_from(fuzzed), label="flag")
    tmp = tmp_path_factory.mktemp("cli")
    junk = data.draw(st.binary(max_size=200) | st.text(max_size=200).map(str.encode), label="file")
    for name in ("junk", "junk.toml", "junk.json"):
        (tmp / name).write_bytes(junk)
    (tmp / "a_file").write_text("x")
    if flag in JUNK_VALUES:
        value = data.draw(st.sampled_from(JUNK_VALUES[flag]), label="value")
    elif flag in ("--model", "STATE", "SCENE", "MODEL", "--urdf"):
        value = data.draw(st.sampled_from([str(tmp / name) for name in ("junk", "junk.toml", "junk.json",
                                                                          "missing.toml", "missing")] + [str(tmp)]),
                          label="path")
    else:  # --out: a path that cannot be written
        value = data.draw(st.sampled_from([str(tmp / "a_file" / "sub"), str(tmp) if command in ("report", "compare")
                                           else str(tmp / "a_file")]), label="out")
    base = [str(REPO / b) if b.startswith(("examples/", "models/")) else str(tmp / b) if b == "exported" else b
            for b in base]
    argv = ["fixtures" if command == "export" else command] + base
    if flag in ("STATE", "SCENE", "FUNCTION", "MODEL"):
        argv = [command, value] + (["--json"] if command == "eval" else base[1:])
    elif flag in argv:
        argv[argv.index(flag) + 1] = value
    else:
        argv += [flag, value]
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    text = err.getvalue()
    assert code == 2, (argv, code, text)
    assert text.count("\n") == 1 and "Traceback" not in text, (argv, text)
