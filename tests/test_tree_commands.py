"""Commands and testing tools on any model: check --model, grade --model --body, the plugin's model=."""

import json
import subprocess
import sys
from pathlib import Path

import gymnasium
import numpy as np
import pytest

import relacc
from relacc.errors import InputError
from relacc.testing import assert_agrees, check_formula, states, truth

ROOT = Path(__file__).resolve().parents[1]
ARM = ROOT / "examples" / "three_link_arm.xml"
ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"


def _relacc(*argv, cwd=None):
    return subprocess.run([sys.executable, "-m", "relacc", *argv], capture_output=True, text=True, cwd=cwd,
                          timeout=600)


@pytest.mark.slow
def test_check_takes_a_model_file(tmp_path):
    """relacc check --model FILE.xml: relacc's tree against every engine in all three cases (hopper: Pinocchio's
    composite J_dot v is the one known difference, exit 1); JSON names every comparison."""
    out = _relacc("check", "--model", str(ASSETS / "hopper.xml"), "--states", "4", "--json", "--quiet", cwd=tmp_path)
    assert out.returncode == 1, out.stderr
    data = json.loads(out.stdout)
    failed = {(r["engine"], r["quantity"]) for r in data["comparisons"] if not r["passed"]}
    assert failed == {("pinocchio", "J_dot v")}
    assert {r["case"] for r in data["comparisons"]} == {1, 2, 3}
    assert {r["engine"] for r in data["comparisons"]} == {"mujoco", "pinocchio", "drake"}
    assert list(tmp_path.iterdir()) == []


def test_check_holds_the_compiled_kernels_to_the_engines_and_compare_the_numpy_walk(monkeypatch):
    """`relacc check --model` evaluates relacc's tree with the compiled kernels a user's call runs (it holds them to
    the engines); `relacc compare` with the plain-numpy walk and Kane's equations, which need no compilation for its
    few states (relacc.validation.robots.reading.BACKEND). Counted at the two kernels' entries, on the hopper."""
    from relacc.core.tree import kinematics as tk
    from relacc.dynamics import tree as td
    from relacc.validation.robots import compare
    from relacc.validation.treecheck import check_tree

    calls = {"kinematics": 0, "dynamics": 0}

    def counted(key, fn):
        def wrapper(*args, **kwargs):
            calls[key] += 1
            return fn(*args, **kwargs)
        return wrapper

    monkeypatch.setattr(tk, "_fast", counted("kinematics", tk._fast))
    monkeypatch.setattr(td, "_fast", counted("dynamics", td._fast))
    compare(ASSETS / "hopper.xml", n_states=2, engines=["mujoco"])
    assert calls == {"kinematics": 0, "dynamics": 0}
    check_tree(ASSETS / "hopper.xml", engines=["mujoco"], n_states=2, cases=(2,))
    assert calls["kinematics"] > 0 and calls["dynamics"] > 0, calls


@pytest.mark.slow
def test_check_on_ant_agrees_in_every_case(tmp_path):
    out = _relacc("check", "--model", str(ASSETS / "ant.xml"), "--states", "3", "--cases", "1,3", "--quiet",
                  cwd=tmp_path)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "all 48 comparisons agree" in out.stdout


@pytest.mark.slow
def test_grade_a_students_arm():
    """The example's correct formulas pass; its slip is wrong, with the two joints whose speeds show it."""
    from relacc.testing.user import load_function

    module = str(ROOT / "examples" / "student_arm.py")
    for fn, q in (("position", "position"), ("velocity", "velocity"), ("acceleration", "acceleration")):
        g = check_formula(load_function(f"{module}:{fn}"), model=ARM, body="forearm", quantity=q, case=2, n=30)
        assert g.ok, g.text()
    g = check_formula(load_function(f"{module}:acceleration_slip"), model=ARM, body="forearm",
                      quantity="acceleration", case=2, n=30)
    assert not g.ok and g.columns == ("shoulder_yaw", "elbow") and g.body == "forearm"
    assert "joints whose speeds show it: shoulder_yaw, elbow" in g.text()


@pytest.mark.slow
def test_grade_checks_its_arguments(tmp_path):
    out = _relacc("grade", f"{ROOT / 'examples' / 'student_arm.py'}:velocity", "--model", str(ARM),
                  "--quantity", "velocity", "--case", "2", cwd=tmp_path)
    assert out.returncode == 2 and "--body NAME goes with --model" in out.stderr
    out = _relacc("grade", f"{ROOT / 'examples' / 'student_arm.py'}:velocity", "--model", str(ARM), "--body", "elbow",
                  "--quantity", "velocity", "--case", "2", cwd=tmp_path)
    assert out.returncode == 2 and "no body 'elbow'" in out.stderr


def test_states_and_truth_of_a_model():
    """relacc_states / relacc_truth with model=: MuJoCo's truth against relacc's, per body, and a planted error
    named by body and component."""
    s = states(case=3, n=25, seed=4, model=ARM)
    mujoco, mine = truth(s, engine="mujoco"), truth(s, engine="relacc")
    for q in ("position", "velocity", "acceleration", "omega", "alpha"):
        assert_agrees(mine.of(q).values, mujoco.of(q))
    bad = np.array(mine.velocity.values)
    bad[7, 2, 1] += 1e-8
    with pytest.raises(AssertionError, match=r"at state 7 of seed 4, body hand, component y"):
        assert_agrees(bad, mujoco.velocity)
    with pytest.raises(InputError, match="mujoco gives no 'V' for case 3"):
        mujoco.of("V")
    with pytest.raises(ValueError):
        s.q[0, 0] = 1.0  # read-only: copy to change


def test_hard_states_of_a_model_include_gimbal_lock():
    s = states(case=3, n=9, seed=0, hard=True, model=ASSETS / "ant.xml")
    tree = s.tree
    root = tree.qadr(3)[0]
    assert np.all(np.abs(s.q[2::3, root + 4] - (np.pi / 2 - 1e-3)) <= 1e-15)
    assert np.all(np.abs(s.q[0::3, root:root + 3]) >= 1e6 - 10)
    k = relacc.tree_kinematics(tree, 3, s.q, s.u, s.udot)
    assert np.all(np.isfinite(k.acceleration))


def _mujoco_position(path, body):
    """A user's own formula for a body's mass centre in any case, written on MuJoCo alone (not relacc): case 3's
    1-2-3 angles made a quaternion by scipy (intrinsic XYZ: Rx Ry Rz), then MuJoCo's forward kinematics."""
    import mujoco
    from scipy.spatial.transform import Rotation

    model = mujoco.MjModel.from_xml_path(str(path))
    data = mujoco.MjData(model)
    free = [j for j in range(model.njnt) if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]

    def position(tree, q, u, udot):
        q = np.asarray(q, dtype=float)
        if q.size != model.nq:  # case 3: [p, theta] in place of [p, quat] at each free joint
            parts, at = [], 0
            for j in range(model.njnt):
                if j in free:
                    x, y, z, w = Rotation.from_euler("XYZ", q[at + 3:at + 6]).as_quat()
                    parts += [q[at:at + 3], [w, x, y, z]]
                    at += 6
                else:
                    parts.append(q[at:at + 1])
                    at += 1
            q = np.concatenate(parts)
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        return data.xipos[model.body(body).id].copy()

    return position


@pytest.mark.parametrize("name,body", [("ant.xml", "aux_3"), ("hopper.xml", "foot")])
@pytest.mark.parametrize("case", [1, 2, 3])
def test_grade_answers_on_gymnasium_models_in_every_case(name, body, case):
    """grade --model on ant (a free root, case 3 with angles) and hopper (slides and hinges): a correct formula
    written on MuJoCo alone passes in every case; the same formula off by 1e-6 m in y fails, named."""
    fn = _mujoco_position(ASSETS / name, body)
    g = check_formula(fn, model=ASSETS / name, body=body, quantity="position", case=case, n=10, seed=case)
    assert g.ok, g.text()

    def off(tree, q, u, udot):
        return fn(tree, q, u, udot) + np.array([0.0, 1e-6, 0.0])

    g = check_formula(off, model=ASSETS / name, body=body, quantity="position", case=case, n=10, seed=case)
    assert not g.ok and g.body == body


@pytest.mark.slow
def test_report_takes_a_model_file(tmp_path):
    """relacc report --model hopper.xml: the model's page with every section; Pinocchio's known composite J_dot v
    difference makes it exit 1, named with its cause; the page renders in Chromium and leaves the cwd empty."""
    import shutil

    from playwright.sync_api import sync_playwright

    out_dir = tmp_path / "out"
    work = tmp_path / "cwd"
    work.mkdir()
    page = out_dir / "hopper.html"
    out = _relacc("report", "--model", str(ASSETS / "hopper.xml"), "--quick", "--quiet", "--out", str(page),
                  cwd=work)
    assert out.returncode == 1, out.stdout + out.stderr
    assert out.stdout.strip() == f"wrote {page}: DISAGREEMENTS found (see the verdict)"
    assert list(work.iterdir()) == []
    html = page.read_text()
    assert "stack-of-tasks/pinocchio#2519" in html and "http://" not in html.replace("http://www.w3.org", "")
    chromium = shutil.which("chromium")
    assert chromium, "Debian's chromium is required for this test (apt-get install chromium; .ci/run does it)"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=["--no-sandbox", "--disable-gpu"])
        view = browser.new_page()
        errors = []
        view.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        view.goto(page.as_uri())
        ids = view.eval_on_selector_all("section", "els => els.map(e => e.id)")
        bodies = view.eval_on_selector_all("#bodies tr td:first-child", "els => els.map(e => e.textContent)")
        cells = view.eval_on_selector_all("#cases th", "els => els.map(e => e.textContent)")
        drawn = view.eval_on_selector("#drawing svg", "e => e.getBoundingClientRect().width")
        hard = view.eval_on_selector_all("#hard-cases tr", "els => els.filter(e => e.querySelector('.badge.pass'))"
                                         ".map(e => e.querySelector('td').textContent)")
        browser.close()
    assert errors == []
    assert ids == ["verdict", "engines", "drawing", "audit", "dynamics", "referee", "cases", "bodies", "conventions",
                   "hard-cases", "simulation"]
    assert hard == ["1", "2", "3"], hard  # a row per case, each within its bound
    assert drawn > 0, "the drawing of the robot did not render"
    assert bodies == ["torso", "thigh", "leg", "foot"]
    assert cells == ["quantity", "case 1", "case 2", "case 3"]
