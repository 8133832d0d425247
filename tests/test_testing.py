"""relacc in other people's tests: the pytest plugin, assert_agrees, grading formulas, exported fixtures."""

import json
import re
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest

import relacc
from relacc.cli import main
from relacc.engines import CHAIN_ENGINES as ENGINES
from relacc.engines import load_engine
from relacc.errors import InputError
from relacc.testing import assert_agrees, check_formula
from relacc.testing.user import load_function

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples"


def test_plugin_fixtures_give_states_truth_and_the_chain(relacc_chain, relacc_states, relacc_truth):
    """The plugin's fixtures: the shipped chain, seeded states, engine truth with scale, bound and seed."""
    s = relacc_states(case=2, n=30, seed=4)
    again = np.random.default_rng(4)  # the states are numpy.random.default_rng(seed)'s
    assert np.array_equal(s.q[:, :3], again.normal(size=(30, 3))) and s.seed == 4
    t = relacc_truth(s, engine="mujoco")
    again = relacc_truth(s, engine="mujoco")  # computed once for the session, handed out as a copy
    assert again is not t and again.acceleration.values is not t.acceleration.values
    np.testing.assert_array_equal(again.acceleration.values, t.acceleration.values)
    ours = relacc.g2_kinematics(relacc_chain, 2, s.q, s.u, s.udot)
    errors = assert_agrees(ours.acceleration, t.acceleration)
    assert errors.shape == (30,) and t.acceleration.seed == 4 and t.acceleration.source == "mujoco/quaternion"


def test_hard_states_come_from_the_catalogue(relacc_states):
    """hard=True draws gimbal-lock, spin and far-from-origin states (and never needs another chain)."""
    s = relacc_states(case=3, n=200, seed=0, hard=True)
    assert len(s) == 200
    assert np.any(np.isclose(np.abs(s.q[:, 4]), np.pi / 2, rtol=0, atol=1e-6))  # gimbal lock
    assert np.max(np.linalg.norm(s.q[:, :3], axis=1)) >= 1e8 * (1 - 1e-12)  # far from the origin
    assert np.max(np.linalg.norm(s.u[:, 3:6], axis=1)) >= 1e6 * (1 - 1e-12)  # fast spin


def test_assert_agrees_names_state_seed_component_and_columns(relacc_chain, relacc_states, relacc_truth):
    """A wrong V fails with the worst state's index and seed, its component and the columns at fault."""
    s = relacc_states(case=1, n=40, seed=11)
    V = relacc.g2_kinematics(relacc_chain, 1, s.q, s.u).V.copy()
    V[17, 1, 9:12] += 1e-6  # only omega_hat_B2's columns, only state 17
    with pytest.raises(AssertionError) as info:
        assert_agrees(V, relacc_truth(s, engine="pinocchio").V, what="V")
    msg = str(info.value)
    assert "at state 17 of seed 11" in msg and "component y" in msg
    assert msg.endswith("the columns that disagree: omega_hat_B2") and "pinocchio/quaternion" in msg


def test_assert_agrees_on_plain_arrays_and_shapes():
    """Plain arrays are judged against their own magnitude; a shape mismatch is an InputError."""
    x = np.ones((4, 3))
    assert_agrees(x * (1 + 1e-15), x)
    with pytest.raises(AssertionError, match="at state 2, component z"):
        y = x.copy()
        y[2, 2] = 1.001
        assert_agrees(y, x)
    with pytest.raises(relacc.InputError, match="shape"):
        assert_agrees(np.ones((4, 2)), x)


@pytest.mark.slow
@pytest.mark.parametrize("spec,quantity,ok,columns,matches", [
    ("student_correct.py:position", "position", True, (), ()),
    ("student_correct.py:velocity", "velocity", True, (), ()),
    ("student_correct.py:acceleration", "acceleration", True, (), ()),
    ("student_correct.py:V", "V", True, (), ()),
    ("student_correct.py:Vdot", "Vdot", True, (), ()),
    ("student_eq9_slip.py:acceleration", "acceleration", False, ("omega_B1", "omega_hat_B2"), ("eq9.2",)),
    ("student_eq9_slip.py:Vdot", "Vdot", False, ("omega_hat_B2",), ("eq9.2",)),
    ("student_block_error.py:V", "V", False, ("s2'_dot",), ()),
    ("student_frame_mixup.py:velocity", "velocity", False, ("omega_hat_B2",), ()),
])
def test_examples_are_diagnosed_as_documented(spec, quantity, ok, columns, matches):
    """Each example in examples/ gets the verdict, the columns and the matching slips docs/testing.md shows."""
    grade = check_formula(load_function(str(EXAMPLES / spec)), quantity=quantity, case=1, n=100)
    assert (grade.ok, grade.columns, grade.matches) == (ok, columns, matches), grade.text()
    assert set(grade.sources) == {"relacc"} | {f"{e}/quaternion" for e in ENGINES}


@pytest.mark.slow
def test_a_batched_formula_is_graded_in_both_forms(relacc_chain):
    """A function that takes whole batches is graded one state at a time and on the batch: right both ways is
    right; right on batches and wrong for one state (or the reverse) is wrong, and the grade says how it was
    called."""

    def velocity(chain, q, u, udot):
        return relacc.g2_kinematics(chain, 2, q, u).velocity

    def wrong_alone(chain, q, u, udot):
        v = relacc.g2_kinematics(chain, 2, q, u).velocity
        return v + 1e-6 if np.ndim(q) == 1 else v

    def wrong_batched(chain, q, u, udot):
        v = relacc.g2_kinematics(chain, 2, q, u).velocity
        return v if np.ndim(q) == 1 else v + 1e-6

    assert check_formula(velocity, quantity="velocity", case=2, n=20).ok
    alone = check_formula(wrong_alone, quantity="velocity", case=2, n=20)
    batched = check_formula(wrong_batched, quantity="velocity", case=2, n=20)
    assert not alone.ok and alone.called == "one state at a time"
    assert not batched.ok and batched.called == "a batch"


def test_grade_cli_exit_codes_and_json(capsys):
    """relacc grade: 0 right, 1 wrong (with its diagnosis), 2 not callable; --json has the documented keys."""
    assert main(["grade", str(EXAMPLES / "student_correct.py:V"), "--quantity", "V", "--case", "1",
                 "--states", "20", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"ok", "worst_error", "columns", "matches", "seed"} <= set(out) and out["ok"]
    assert main(["grade", str(EXAMPLES / "student_block_error.py:V"), "--quantity", "V", "--case", "1",
                 "--states", "20"]) == 1
    assert "columns that disagree: s2'_dot" in capsys.readouterr().out
    for spec, why in ((f"{EXAMPLES}/student_correct.py:nothing", "has no function 'nothing'"),
                      (f"{EXAMPLES}/student_correct.py:tilde", "tilde raised TypeError"),
                      (f"{EXAMPLES}/missing.py:f", "no such file"), ("not_a_module_x:f", "cannot be imported"),
                      ("student_correct", "expected MODULE:FUNCTION")):
        assert main(["grade", spec, "--quantity", "V", "--case", "1"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and why in err and "Traceback" not in err, err


def test_exported_fixtures_load_in_every_engine_and_the_manifest_maps_every_case(tmp_path):
    """relacc fixtures --out: both MJCFs and the URDF load; conventions.json's index maps match the adapters."""
    assert main(["fixtures", "--out", str(tmp_path), "--q2", "0.3,0,0.1", "--m2", "1.5", "--name", "mine"]) == 0
    manifest = json.loads((tmp_path / "conventions.json").read_text())
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "two_body.xml"))
    assert m.body_mass[2] == 1.5 and (m.nq, m.nv) == (14, 12)
    assert mujoco.MjModel.from_xml_path(str(tmp_path / "two_body_euler.xml")).nq == 12
    assert pin.buildModelFromUrdf(str(tmp_path / "two_body_euler.urdf")).nq == 12
    assert pin.buildModelFromMJCF(str(tmp_path / "two_body.xml")).nq == 14
    fixture = relacc.fixtures.load(tmp_path / "two_body.toml")
    assert fixture.stale() == [] and fixture.digest == manifest["source"]["sha256_of_chain"]
    for engine in ENGINES:
        e, info = load_engine(engine, fixture), manifest["engines"][engine]["quaternion_route"]
        assert set(info["maps"]) == {"1", "2", "3"}
        s = relacc.testing.states(1, 5, 0)
        x = e.engine_input("quaternion", relacc.Case(1), s.q, s.u, None)
        index = info.get("q_from_quaternion_coordinates") or info.get("qpos_from_quaternion_coordinates")
        assert np.array_equal(x.q, s.q[:, index])  # the documented reordering is the adapter's
        if "v_from_case_1_speeds" in info:
            assert np.allclose(x.v, s.u[:, info["v_from_case_1_speeds"]], rtol=0, atol=1e-15 * 8)
    assert set(manifest["cases"]) == {"1", "2", "3"} and manifest["units"]["length"] == "m"


@pytest.mark.slow
def test_a_fresh_project_uses_the_plugin(tmp_path):
    """docs/testing.md's test file, in a project outside the repository: it passes; made wrong, it fails by name."""
    text = (REPO / "docs" / "testing.md").read_text()
    (code,) = re.findall(r"## A test file, copy and paste.*?```python\n(.*?)```", text, re.S)
    project = tmp_path / "project"
    (project / "tests").mkdir(parents=True)
    (project / "tests" / "test_mine.py").write_text(code)

    def pytest_in(project):
        return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "tests"],
                              cwd=project, capture_output=True, text=True, timeout=600)

    good = pytest_in(project)
    assert good.returncode == 0 and "2 passed" in good.stdout, good.stdout + good.stderr
    (project / "tests" / "test_mine.py").write_text(code.replace("R1T, -tilde(r2) @ R1T])",
                                                                 "R1T.T, -tilde(r2) @ R1T])"))
    bad = pytest_in(project)
    assert bad.returncode == 1, bad.stdout
    shown = re.search(r"AssertionError: (my V against .*)", bad.stdout).group(1)
    assert "of seed 7" in shown and shown.endswith("the columns that disagree: s2'_dot")
    assert shown in text, f"docs/testing.md shows another message than pytest prints:\n{shown}"


def test_relacc_states_checks_its_arguments_and_hands_out_read_only_states(relacc_states):
    with pytest.raises(InputError, match="n: expected an integer"):
        relacc_states(n=3.9)
    with pytest.raises(InputError, match="seed: expected an integer"):
        relacc_states(seed=True)
    with pytest.raises(InputError, match="unknown case"):
        relacc_states(case=1.7)
    with pytest.raises(InputError, match="hard: expected True or False"):
        relacc_states(hard="no")
    s = relacc_states(case=1, n=3)
    with pytest.raises(ValueError, match="read-only"):
        s.q[:, 0] += 100
    first = s.q.copy()
    s.q.setflags(write=True)  # a test may make its copy writable: no other test sees the change
    s.q[:, 0] += 100
    again = relacc_states(case=1, n=3)
    assert again is not s and not again.q.flags.writeable
    np.testing.assert_array_equal(again.q, first)


def test_relacc_states_of_a_model_follow_the_file(tmp_path, relacc_states):
    """States are keyed by the model's content, not its path: after the file changes (a hinge becomes a ball), the
    same call gives the new model's states."""
    path = tmp_path / "m.xml"
    body = '<mujoco><worldbody><body name="b"><joint name="j" type="{}"/><geom type="sphere" size="0.1" mass="1"/>' \
        '</body></worldbody></mujoco>'
    path.write_text(body.format("hinge"))
    assert relacc_states(case=2, n=4, model=path).q.shape == (4, 1)
    path.write_text(body.format("ball"))
    assert relacc_states(case=2, n=4, model=path).q.shape == (4, 4)
