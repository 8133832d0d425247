"""The rules of docs/guarantees.md held by every command that takes a model file: a file where nothing moves is one
line and exit 2; what a file has that relacc does not evaluate is named in every result; a URDF runs wherever an MJCF
does; an engine that cannot read every joint is left out of a model's default scene, and the result says so."""

import json
from pathlib import Path

import numpy as np
import pytest

from relacc.cli import main

NOTHING_MOVES = '<mujoco><worldbody><body name="a"><geom type="sphere" size="0.1" mass="1"/></body></worldbody>' \
    '</mujoco>'
COUPLED = """<mujoco model="coupled"><worldbody><body name="a"><joint name="j1" type="hinge" axis="0 1 0"/>
<geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05"/><body name="b" pos="0 0 -0.5">
<joint name="j2" type="hinge" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05"/></body></body>
</worldbody><equality><joint joint1="j1" joint2="j2"/></equality></mujoco>
"""
WELDED_BASE = """<robot name="turned"><link name="base"/>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 1 0"/>
<limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
<link name="l1"><inertial><origin xyz="0.1 0 -0.2" rpy="0 0 1.570796"/><mass value="1"/>
<inertia ixx="1" iyy="2" izz="2.5" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>
"""
# Pinocchio's MJCF parser reads only the first body written in <worldbody> (docs/reading.md): it lacks "target"'s joint
TWO_ROOTS = """<mujoco model="two_roots"><worldbody>
<body name="arm"><joint name="shoulder" type="hinge" axis="0 0 1"/><geom type="capsule" fromto="0 0 0 0.3 0 0"
size="0.02"/></body>
<body name="target" pos="0.2 0.2 0"><joint name="target_x" type="slide" axis="1 0 0"/><geom type="sphere" size="0.02"/>
</body></worldbody></mujoco>
"""
UNNAMED_FREE = '<mujoco><worldbody><body pos="0 0 1"><joint type="free"/><geom size="0.05 0.1" type="cylinder"/>' \
    '</body></worldbody></mujoco>'
"""pybullet_data's cylinder.xml: one unnamed free body (relacc's ``body 1``, Pinocchio's ``Bis``, Drake's ``body1``)."""
SHORT = {"simulate": ["--duration", "0.02"], "tradeoff": ["--quick"], "check": ["--states", "2"],
         "report": ["--quick", "--states", "2"], "compare": ["--states", "2"]}


def _model(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def _argv(command, path, tmp_path):
    argv = [command, str(path)] if command == "compare" else [command, "--model", str(path)]
    if command == "report":
        argv += ["--out", str(tmp_path / "page.html")]
    return argv + SHORT[command]


@pytest.mark.parametrize("command", ["check", "simulate", "tradeoff", "report", "compare"])
def test_a_file_where_nothing_moves_is_one_line(tmp_path, capsys, command):
    path = _model(tmp_path, "still.xml", NOTHING_MOVES)
    code = main(_argv(command, path, tmp_path) + ["--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "nothing moves" in err[0], err


@pytest.mark.parametrize("command", ["check", "simulate", "tradeoff", "compare"])
def test_an_equality_constraint_is_named_in_every_json_result(tmp_path, capsys, command):
    path = _model(tmp_path, "coupled.xml", COUPLED)
    main(_argv(command, path, tmp_path) + ["--json", "--quiet"])
    out = json.loads(capsys.readouterr().out)
    assert any("equality constraint" in line for line in out["not_evaluated"]), out


@pytest.mark.slow
def test_an_equality_constraint_is_named_by_report_and_grade(tmp_path, capsys):
    path = _model(tmp_path, "coupled.xml", COUPLED)
    main(_argv("report", path, tmp_path) + ["--quiet"])
    assert "not evaluated: 1 equality constraint" in capsys.readouterr().out
    module = _model(tmp_path, "mine.py", "import numpy as np\ndef f(tree, q, u, udot):\n    return np.zeros(3)\n")
    main(["grade", f"{module}:f", "--model", str(path), "--body", "b", "--quantity", "position", "--case", "2",
          "--json"])
    out = json.loads(capsys.readouterr().out)
    assert any("equality constraint" in line for line in out["not_evaluated"]), out


@pytest.mark.slow
@pytest.mark.parametrize("command", ["simulate", "tradeoff", "report"])
def test_a_urdf_with_a_welded_base_runs_observed_at_its_first_moving_link(tmp_path, capsys, command):
    """The base link moves with nothing (MuJoCo fuses it into the world): the default scene observes l1."""
    path = _model(tmp_path, "turned.urdf", WELDED_BASE)
    code = main(_argv(command, path, tmp_path) + ["--quiet"])
    out = capsys.readouterr()
    assert code == 0 and not out.err, out.err
    if command != "report":
        assert "l1" in out.out


def test_an_unnamed_body_is_observed_on_every_engine(tmp_path, capsys):
    """pybullet_data's cylinder.xml: one unnamed free body. relacc names it "body 1" (MuJoCo's index), Pinocchio
    "Bis", Drake "body1": Pinocchio's adapter raised a KeyError and Drake's a RuntimeError, each a traceback out of
    ``relacc simulate --model``. The body is now found through the joint that moves it; the four engines' G2 agree
    to the error model (the run's own verdict, exit 0)."""
    path = _model(tmp_path, "unnamed.xml", UNNAMED_FREE)
    code = main(["simulate", "--model", str(path), "--duration", "0.02", "--json", "--quiet"])
    out = capsys.readouterr()
    assert code == 0 and not out.err, out.err
    assert sorted(json.loads(out.out)["engines"]) == ["drake", "mujoco", "pinocchio", "relacc"], out.out


def test_the_integrator_sweep_of_a_free_body_runs_every_engines_explicit_schemes(tmp_path, capsys):
    """pybullet_data's cylinder.xml under ``relacc tradeoff --model``: Drake's explicit Euler drifts a free joint's
    quaternion norm by its truncation error (4e-5 at the sweep's coarsest step), and the sweep's runs, which only
    need their final positions, also checked relacc's acceleration at those states: relacc refuses a non-unit
    quaternion, so the command ended "pass unit quaternions", exit 2. The sweep's runs no longer check (the engines
    are judged once, on the run with relacc in it); every scheme gives a row, Drake's Euler at first order."""
    path = _model(tmp_path, "unnamed.xml", UNNAMED_FREE)
    code = main(["tradeoff", "--model", str(path), "--quick", "--quiet", "--json"])
    out = capsys.readouterr()
    assert code == 0 and not out.err, out.err
    rows = json.loads(out.out)["integrators"]
    euler = [r for r in rows if r["engine"] == "drake" and r["integrator"] == "euler"]
    assert euler and all(np.isfinite(r["error"]) for r in euler), euler


def test_an_engine_whose_reading_has_no_mass_is_left_out_with_the_reason(tmp_path, capsys):
    """brax's double_pendulum.xml: every geom ``contype="0" conaffinity="0"``, which Pinocchio's MJCF parser leaves
    out of the inertia (its own model weighs 0 kg: the reference). Its forward dynamics is not finite, and the run
    ended "the integration diverged ... reduce the step", advice that cannot help. The default scene now leaves
    Pinocchio out and says why; asked for by name, it is one line saying the same, exit 2."""
    import pinocchio as pin

    path = _model(tmp_path, "visual.xml", '<mujoco><default><geom contype="0" conaffinity="0"/></default><worldbody>'
                                          '<body name="a"><joint name="h1" axis="1 0 0"/><geom size=".15" mass="1" '
                                          'pos="0 .5 0"/><body name="b" pos="0 .5 0"><joint name="h2" axis="1 0 0"/>'
                                          '<geom size=".15" mass="1" pos="0 .5 0"/></body></body></worldbody></mujoco>')
    assert sum(i.mass for i in pin.buildModelFromMJCF(str(path)).inertias) == 0.0
    _pinocchio_left_out_then_one_line(path, capsys, "mass matrix is singular",
                                      "forward dynamics at the initial state is not finite")


def test_an_engine_that_lacks_joints_is_left_out_of_the_default_scene_and_said(tmp_path, capsys):
    path = _model(tmp_path, "two_roots.xml", TWO_ROOTS)
    _pinocchio_left_out_then_one_line(path, capsys, "target_x", "lacks the joints target_x")


def _pinocchio_left_out_then_one_line(path, capsys, why: str, line: str):
    """The model's default scene runs without Pinocchio and says ``why`` (exit 0); asked for by name, Pinocchio is
    one line holding ``line``, exit 2."""
    code = main(["simulate", "--model", str(path), "--duration", "0.02", "--json", "--quiet"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and "pinocchio" not in out["engines"], out["engines"]
    assert why in out["left_out"]["pinocchio"], out["left_out"]
    code = main(["simulate", "--model", str(path), "--duration", "0.02", "--engines", "relacc,pinocchio", "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and line in err[0], err


@pytest.mark.parametrize("engine", ["relacc", "pinocchio", "mujoco", "drake"])
def test_a_diverging_stiff_scene_is_one_line_on_every_engine(tmp_path, capsys, engine):
    """The shipped ant scene with its hip springs at 1e7 N m/rad under explicit Euler at dt = 1e-3 s (omega dt of
    order 1e2: the scheme is unstable): each engine's run ends in one line naming the divergence, exit 2 (Drake's
    callback saw a non-finite state; relacc's overflowed on the way)."""
    from relacc.fixtures.shipped import scene_path

    text = scene_path("ant_tumbling").read_text().replace("stiffness = 2.0", "stiffness = 1e7")
    text = text.replace('integrator = "rk4"', 'integrator = "euler"').replace("duration = 1.0", "duration = 0.2")
    text = text.replace('integrator = "runge_kutta5"', 'integrator = "explicit_euler"')
    path = _model(tmp_path, "stiff.toml", text)
    code = main(["simulate", str(path), "--engines", engine, "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "diverged" in err[0] and "reduce the step" in err[0], err


def test_a_fifo_is_refused_not_read(tmp_path, capsys):
    """A FIFO named like a model, a scene, a state or a module would block the reader forever: one line, exit 2."""
    import os

    for name, argv in (("m.xml", ["compare", "{}"]), ("m.urdf", ["check", "--model", "{}"]),
                       ("s.toml", ["simulate", "{}"]), ("state.json", ["eval", "{}"]),
                       ("mine.py", ["grade", "{}:f", "--quantity", "V", "--case", "1"])):
        path = tmp_path / name
        os.mkfifo(path)
        code = main([a.format(path) for a in argv])
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2 and len(err) == 1 and "a FIFO, not a regular file" in err[0], (name, err)


def test_an_empty_scheduler_address_is_refused(capsys):
    assert main(["check", "--scheduler", "", "--states", "2"]) == 2
    assert "empty address" in capsys.readouterr().err


# --- memory: estimated from the model and the command, refused before any allocation ---------------------------

def _gym(name):
    from pathlib import Path

    import gymnasium
    return Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / f"{name}.xml"


def test_grading_a_model_body_on_too_many_states_is_refused_at_once(tmp_path, capsys):
    """ant, 1e7 states: 2e7 evaluated states x 13 bodies x 14 speeds x GRADE_DOUBLES doubles (~470 GB) are refused
    before any state is drawn (the red team saw 20.6 GB in 120 s)."""
    import time

    module = _model(tmp_path, "mine.py", "import numpy as np\ndef f(tree, q, u, udot):\n    return np.zeros(3)\n")
    start = time.monotonic()
    code = main(["grade", f"{module}:f", "--model", str(_gym("ant")), "--body", "torso", "--quantity", "position",
                 "--case", "2", "--states", "10000000"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "13 bodies, 14 speeds" in err[0] and "GiB" in err[0], err
    assert time.monotonic() - start < 10


def test_tree_states_are_estimated_from_the_tree():
    from relacc.core.tree import Tree, random_states
    from relacc.errors import InputError
    from relacc.testing import states

    tree = Tree.from_file(_gym("humanoid"))
    with pytest.raises(InputError, match="random states of 'humanoid' needs about"):
        random_states(tree, 3, 10**9, 0)
    with pytest.raises(InputError, match="random states of 'humanoid' needs about"):
        states(2, 10**9, model=tree)


@pytest.mark.parametrize("n", [2000, pytest.param(20000, marks=pytest.mark.slow),
                               pytest.param(100000, marks=pytest.mark.slow)])  # 4-19 s under tracemalloc
@pytest.mark.parametrize("case", [1, 2, 3])
def test_the_state_estimate_covers_what_is_measured(case, n):
    """tracemalloc's peak while drawing humanoid states (numpy reports its allocations to it) is at most the
    estimate :func:`relacc.limits.tree_states_bytes` that random_states checks first."""
    import tracemalloc

    from relacc.core.tree import Tree, random_states
    from relacc.limits import tree_states_bytes

    tree = Tree.from_file(_gym("humanoid"))
    tracemalloc.start()
    try:
        random_states(tree, case, n, 0)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak <= tree_states_bytes(tree, n, case), (case, n, peak, tree_states_bytes(tree, n, case))


def test_a_huge_ensemble_is_refused_before_its_members_are_drawn(capsys):
    import time

    start = time.monotonic()
    code = main(["simulate", "tumbling", "--ensemble", "10000000", "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "an ensemble of 10000000 members" in err[0], err
    assert time.monotonic() - start < 5  # the red team saw 4.6-7.4 GB and 14-19 s before the refusal


# --- an interrupt at any moment ----------------------------------------------------------------------------------

def _catches_sigterm(pid: int) -> bool:
    """Whether the process has its own SIGTERM handler yet (/proc's SigCgt mask): relacc's entry installs it as its
    first instruction, so this is the sign the process is relacc's (Python's own start, before it, is not)."""
    import signal

    try:
        with open(f"/proc/{pid}/status") as fh:
            mask = next(int(line.split()[1], 16) for line in fh if line.startswith("SigCgt:"))
    except (OSError, StopIteration):
        return False
    return bool(mask >> (signal.SIGTERM - 1) & 1)


@pytest.mark.slow
@pytest.mark.parametrize("delay", [0.0, 0.05, 0.15, 0.3, 0.6, 1.0, 1.6])
@pytest.mark.parametrize("signum", ["SIGINT", "SIGTERM"])
def test_an_interrupt_at_any_moment_is_one_line_and_130(tmp_path, signum, delay):
    """From relacc's first instruction (waited for, not slept for) to the process's end, across the parser, the
    imports (pydrake's included), the work and the exit: either the command finished (exit 0, its output whole) or
    exit 130 with exactly one line on stderr."""
    import signal
    import subprocess
    import sys
    import time

    proc = subprocess.Popen([sys.executable, "-m", "relacc", "check", "--states", "3", "--quiet"], cwd=tmp_path,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not _catches_sigterm(proc.pid) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.001)
    time.sleep(delay)
    proc.send_signal(getattr(signal, signum))
    out, err = proc.communicate(timeout=120)
    lines = err.strip().splitlines()
    finished = proc.returncode == 0 and "comparisons agree" in out and not err
    interrupted = proc.returncode == 130 and len(lines) == 1 and lines[0].endswith("interrupted; no output file "
                                                                                     "was changed")
    assert finished or interrupted, (signum, delay, proc.returncode, out[-300:], err[-2000:])
    assert list(tmp_path.iterdir()) == []


def test_an_engine_run_alone_is_checked_at_its_own_states_normalized_and_says_so(tmp_path):
    """A scene run on Drake alone with its explicit Euler (a scene file's ``drake_integrator``): relacc's acceleration
    is checked along Drake's trajectory, whose free-joint quaternion drifts off unit by Euler's truncation error
    (well above the 1e-12 relacc accepts as input), so the check ended "pass unit quaternions". It is now made at
    those quaternions normalized, which is the rotation Drake itself evaluates (its rotation of a quaternion is
    ``2 / |q|^2``-scaled); the result says whose trajectory and how far they were off; the accelerations agree
    within the run's own bound."""
    from relacc import simulate
    from relacc.simulate import scenes

    path = _model(tmp_path, "unnamed.xml", UNNAMED_FREE)
    base = scenes.model_scene(path, seed=0, duration=0.4, dt=0.08)
    result = simulate.run(base.replace(engines=("drake",), drake_integrator="euler"), keep=False)
    c = result.note_check["drake"]
    assert c["along"] == "drake" and c["quaternions_normalized"] > 1e-12, c
    assert c["error"] <= c["bound"], c


def _flat_tree(tmp_path, n: int) -> Path:
    """A free root with ``n`` hinged children: ``n + 1`` bodies, ``n + 6`` speeds, every link its own Jacobian."""
    body = "".join(f'<body name="b{i}" pos="0.1 0 0"><joint name="j{i}" type="hinge"/><geom size="0.05"/></body>'
                   for i in range(n))
    path = tmp_path / f"flat{n}.xml"
    path.write_text(f'<mujoco model="flat{n}"><worldbody><body name="root"><freejoint/><geom size="0.1"/>{body}'
                    "</body></worldbody></mujoco>")
    return path


@pytest.mark.parametrize("command", [["compare"], ["check", "--model"]])
def test_a_comparison_that_cannot_fit_is_refused_before_any_engine_loads(tmp_path, capsys, monkeypatch, command):
    """Issue 50 item 8: 30,000 bodies read for 88 s, then asked for 161 GiB and advised "pass fewer states at a time"
    for one state; check --model of 3,000 bodies grew to 4.3 GB with no estimate. The comparison's memory
    (relacc.limits.compare_bytes) is estimated from the model as soon as it is read and refused before any engine
    loads, saying the model's size; with one state at once, the advice is not to pass fewer states."""
    import time

    from relacc import limits
    from relacc.limits import compare_bytes

    path = _flat_tree(tmp_path, 300)
    from relacc.reading import read

    tree = read(path).tree
    monkeypatch.setattr(limits, "available_memory", lambda: int(compare_bytes(tree, 0) * 1.5))
    start = time.monotonic()
    assert main(command + [str(path), "--states", "5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "(301 bodies, 306 speeds) at 6 states at once" in err[0] and "fewer states" in err[0]
    monkeypatch.setattr(limits, "available_memory", lambda: int(compare_bytes(tree, 0) / 2))
    assert main(command + [str(path), "--states", "5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "at 6 states at once" in err[0]
    assert time.monotonic() - start < 30


def test_one_state_of_a_model_too_large_for_its_partials_says_so(tmp_path, monkeypatch):
    """The same for the API: one state whose partial velocities cannot fit is not told to pass fewer states."""
    from relacc import limits
    from relacc.core.tree import tree_kinematics
    from relacc.core.tree.coordinates import reference_q
    from relacc.errors import InputError
    from relacc.reading import read

    tree = read(_flat_tree(tmp_path, 300)).tree
    monkeypatch.setattr(limits, "available_memory", lambda: 2**21)
    with pytest.raises(InputError, match=r"1 state of 'flat300' \(301 bodies, 306 speeds\).*even one state"):
        tree_kinematics(tree, 2, reference_q(tree, 2), np.zeros(tree.nv))


FLOATING_ROOT = """<robot name="float">
  <link name="world"/>
  <link name="base"><inertial><mass value="2"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.04"/>
  </inertial></link>
  <link name="arm"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
  <joint name="root" type="floating"><parent link="world"/><child link="base"/><origin xyz="0 0 1"/></joint>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def test_a_urdfs_floating_root_is_one_free_joint_in_every_engine(tmp_path, capsys):
    """Issue 49 item 9: a URDF whose root joint is floating read as 13 speeds in Pinocchio (relacc's adapter added a
    free flyer to a model whose parser had already made one) and "the integration diverged ... reduce the step",
    exit 2, in simulate; Drake's parser leaves the floating joint's child a free body, which relacc then welded to the
    world. Each engine now reads one free joint: compare agrees, and the default scene runs on all four."""
    from relacc.validation.robots import compare

    path = tmp_path / "float.urdf"
    path.write_text(FLOATING_ROOT)
    result = compare(path, n_states=3, seed=1)
    assert {e: (r.nq, r.nv) for e, r in result.engines.items() if r.loaded} == {e: (8, 7) for e in result.compared}
    assert set(result.compared) == {"relacc", "pinocchio", "mujoco", "drake"}
    # PyBullet reads the floating joint as fixed, iDynTree drops it: each says so and takes no part
    assert all("floating" in result.engines[e].error for e in ("pybullet_file", "idyntree"))
    assert result.agree, [a.as_json() for a in result.audit]
    assert main(["simulate", "--model", str(path), "--duration", "0.05", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["agree"] is True


def test_an_engine_whose_run_diverges_because_it_misreads_is_named_and_the_rest_compared(tmp_path, monkeypatch,
                                                                                          capsys):
    """Issue 49 item 9: a run that diverges where relacc's does not is judged by its acceleration at the scene's start:
    here MuJoCo's (planted: twice its own, and a stepper that diverges) differs, so the result names it (exit 1) and
    the others are compared; with its acceleration right, the divergence is the integrator's and stays exit 2."""
    from types import SimpleNamespace

    from relacc.errors import IntegrationError
    from relacc.simulate import subjects

    path = tmp_path / "float.urdf"
    path.write_text(FLOATING_ROOT)
    real = subjects.adapter

    def planted(scene, name, double=True):
        engine = real(scene, name)
        if name == "mujoco":
            forward, stepper = engine.forward, engine.stepper
            if double:
                monkeypatch.setattr(engine, "forward", lambda *a, **k: 2.0 * np.asarray(forward(*a, **k)))

            def diverging(*a, **k):
                stepper(*a, **k)

                def record(*b, **c):
                    raise IntegrationError("the state became non-finite")
                return SimpleNamespace(record=record)
            monkeypatch.setattr(engine, "stepper", diverging)
        return engine

    monkeypatch.setattr(subjects, "adapter", planted)
    assert main(["simulate", "--model", str(path), "--duration", "0.05", "--json"]) == 1
    data = json.loads(capsys.readouterr().out)
    assert "mujoco" in data["verdict"] and "its run diverged" in data["verdict"], data["verdict"]
    monkeypatch.setattr(subjects, "adapter", lambda scene, name: planted(scene, name, double=False))
    assert main(["simulate", "--model", str(path), "--duration", "0.05"]) == 2
    assert "mujoco: between t = 0 s" in capsys.readouterr().err


ON_AXIS = """<mujoco model="on_axis"><worldbody>
  <body name="turntable" pos="0 0 1"><joint name="spin" type="hinge" axis="0 0 1"/>
    <inertial pos="0 0 0.0005" mass="5" diaginertia="0.1 0.1 0.2"/>
    <body name="arm" pos="0.4 0 0"><joint name="lift" type="hinge" axis="0 1 0"/>
      <inertial pos="0.3 0 0" mass="1" diaginertia="0.01 0.02 0.02"/></body>
  </body>
</worldbody></mujoco>
"""


def test_a_models_scene_is_observed_where_something_moves(tmp_path, capsys):
    """Issue 49 item 9: simulate --model and tradeoff --model watched "the first body a joint moves"; on the iCub its
    mass centre sits 0.5 mm from its axis and moved 0.07 mm in a second, so differences of 1e-17 m between engines
    said nothing. The default is the body whose mass centre moves fastest at the start (here the arm, whose mass
    centre is 0.7 m from the spin axis); --observe BODY chooses, and a name that is no body is one line."""
    from relacc.simulate import scenes
    from relacc.tradeoff.models import why_no_order

    path = tmp_path / "on_axis.xml"
    path.write_text(ON_AXIS)
    assert scenes.model_scene(path).observe == "arm"
    assert scenes.model_scene(path, observe="turntable").observe == "turntable"
    assert main(["simulate", "--model", str(path), "--observe", "nothing", "--duration", "0.01"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no body of on_axis.xml is named so" in err[0] and "turntable, arm" in err[0], err
    # and a run whose order cannot be read says why
    rows = [{"engine": "mujoco", "integrator": "rk4", "error": e, "diverged": False} for e in (1e-15, 3e-16, 2e-17)]
    assert "every error is below 1e-12 m" in why_no_order(rows, "mujoco", "rk4")
    rows = [{"engine": "mujoco", "integrator": "euler", "error": e, "diverged": False} for e in (1e-3, 1e-1, 2e-1)]
    assert "only 1 of its steps" in why_no_order(rows, "mujoco", "euler")


COMMENTED_FLOATING = """<robot name="commented">
  <!-- <link name="world"/>
  <joint name="floating_base_joint" type="floating"><parent link="world"/><child link="base"/></joint> -->
  <link name="base"><inertial><mass value="2"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.04"/>
  </inertial></link>
  <link name="arm"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def test_a_commented_out_floating_joint_is_no_joint(tmp_path):
    """The floating root's reading must not see a joint in a comment: example-robot-data's G1 comments its world link
    and `floating_base_joint` out, and Drake's adapter then left its pelvis free (35 speeds against 29)."""
    from relacc.validation.robots import compare

    path = tmp_path / "commented.urdf"
    path.write_text(COMMENTED_FLOATING)
    result = compare(path, n_states=2, seed=1)
    assert {e: r.nv for e, r in result.engines.items()} == {e: 1 for e in result.engines}, result.engines
    assert result.agree
