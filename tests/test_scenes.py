"""Scenes: shipped scenes agree across engines, converge at the integrator's order, conserve what they should."""

import json
from pathlib import Path

import numpy as np
import pytest

from relacc import simulate
from relacc.cli import main
from relacc.core.tolerances import EPS, ROUNDING_FACTOR, rounding_tolerance
from relacc.errors import FixtureError, InputError
from relacc.fixtures import shipped
from relacc.simulate import scenes
from tests.cli import one_line, run_relacc

SHIPPED = shipped.scene_paths()
CHAIN = shipped.scene_paths("chain")
ENGINES = ("relacc", "pinocchio", "mujoco", "drake")
FLOOR = 1e-12
"""Differences below this (m, or relative energy) are rounding, where orders cannot be read."""


@pytest.fixture(scope="module", params=SHIPPED, ids=lambda p: p.stem)
def scene_run(request):
    scene = scenes.load(request.param)
    return scene, simulate.run(scene)


def test_four_scenes_are_shipped():
    """At least: tumbling, gravity with spring-damper, forced and damped, fast spin near gimbal lock."""
    assert {"tumbling", "gravity_spring", "forced_damped", "gimbal_spin"} <= {p.stem for p in SHIPPED}


def implicit_in_damping(scene) -> bool:
    """Whether MuJoCo's step is another scheme than the others' here: its Euler integrator takes joint damping
    implicitly (``mj_implicit``'s damping term), so on a scene integrated by ``euler`` with a damper its trajectory
    differs from the semi-implicit Euler of the others by a first-order term (kuka_swinging: 5.5e-4 m)."""
    return scene.integrator == "euler" and any(e.damping for e in scene.effects.joints.values())


@pytest.mark.slow
def test_engines_agree_to_a_micrometre(scene_run):
    """With the scene's own integrator and step, every pair of engines that steps the same scheme keeps the
    observed point within 1e-6 m."""
    scene, result = scene_run
    _, _, pairs = result.differences()
    assert set(result.trajectories) == set(scene.engines) >= set(ENGINES)
    same = {k: p for k, p in pairs.items() if not (implicit_in_damping(scene) and "mujoco" in k.split("-"))}
    assert max(p["position"] for p in same.values()) <= 1e-6, f"{scene.name}: {pairs}"


@pytest.mark.slow
def test_note_accelerations_match_engines_along_the_run(scene_run):
    """Along relacc's trajectory the note's a_G2 equals each engine's to c eps kappa(M) of the terms."""
    scene, result = scene_run
    for engine, check in result.note_check.items():
        assert rounding_tolerance() <= check["bound"] < 1e-9, check
        assert check["error"] <= check["bound"], f"{scene.name} {engine}: {check}"


@pytest.mark.slow
def test_trajectories_are_finite_and_start_at_the_scene_state(scene_run):
    """Every trajectory is finite and all engines start with the same G2 position."""
    scene, result = scene_run
    starts = [tr.position[0] for tr in result.trajectories.values()]
    for tr in result.trajectories.values():
        for a in (tr.q, tr.u, tr.position, tr.velocity, tr.acceleration, tr.energy):
            assert np.all(np.isfinite(a))
    # one state's G2 by each engine's kinematics: the rounding bound of the positions' magnitude
    assert np.allclose(starts, starts[0], rtol=0, atol=ROUNDING_FACTOR * EPS * max(1.0, np.abs(starts).max()))


def _coarse(scene, factor):
    """The scene at ``factor`` times its step, over at most 0.5 s (convergence runs)."""
    duration = min(scene.duration, 0.5)
    dt = scene.dt * factor
    return scene.replace(dt=dt, duration=round(duration / dt) * dt)


@pytest.mark.slow
@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_engine_differences_shrink_at_the_integrators_order(path):
    """Each engine's successive differences |x(8h) - x(4h)| / |x(4h) - x(2h)| shrink at its scheme's order: >= 3.5
    for RK4 (4) and Drake's RK5 (5), >= 0.9 for semi-implicit Euler (1).

    Self-convergence needs no reference: a reference run (relacc at h/4, before) was less accurate than Drake's
    fifth-order runs, whose distance to it then measured the reference's own error.
    """
    scene = scenes.load(path)
    runs = {f: simulate.run(_coarse(scene, f)) for f in (8, 4, 2)}
    least = 0.9 if scene.integrator == "euler" else 3.5
    for engine in scene.engines:
        x = {f: runs[f].trajectories[engine].position[-1] for f in (8, 4, 2)}
        d = [np.linalg.norm(x[8] - x[4]), np.linalg.norm(x[4] - x[2])]
        if d[1] < 16 * FLOOR:
            continue  # already at rounding: no order to read
        order = np.log2(d[0] / d[1])
        assert order >= least, f"{scene.name} {engine}: differences {d}, observed order {order:.2f}"


@pytest.mark.slow
@pytest.mark.parametrize("path", [p for p in SHIPPED if scenes.load(p).effects.conserves_energy],
                         ids=lambda p: p.stem)
def test_conservative_scenes_conserve_energy_and_momentum(path):
    """Energy and momentum drifts shrink with the step at RK4's order (or sit at rounding)."""
    scene = scenes.load(path)
    runs = {f: simulate.run(_coarse(scene, f)) for f in (8, 4)}
    for engine in ENGINES:
        drifts = [runs[f].trajectories[engine].energy_drift() for f in (8, 4)]
        if drifts[0] > 16 * FLOOR:
            assert np.log2(drifts[0] / drifts[1]) >= 3.5, f"{scene.name} {engine}: energy drifts {drifts}"
        if scene.effects.conserves_momentum:
            p = [runs[f].trajectories[engine].momentum_drift()[0] for f in (8, 4)]
            if p[0] > 16 * FLOOR:
                assert np.log2(p[0] / p[1]) >= 3.5, f"{scene.name} {engine}: momentum drifts {p}"


def test_mujoco_applies_only_the_listed_effects():
    """Torque-free tumbling disables gravity, springs and dampers in MuJoCo; the spring scene keeps them."""
    free = simulate.run(scenes.load(shipped.scenes_dir() / "tumbling.toml").replace(duration=0.01),
                        engines=["mujoco"])
    assert {"gravity", "spring", "damper", "contact"} <= set(free.trajectories["mujoco"].applied["disabled"])
    spring = simulate.run(scenes.load(shipped.scenes_dir() / "gravity_spring.toml").replace(duration=0.01),
                          engines=["mujoco"])
    disabled = set(spring.trajectories["mujoco"].applied["disabled"])
    assert "contact" in disabled and not {"gravity", "spring", "damper"} & disabled


SCENE = """title = "t"
[model]
fixture = "two_body"
[initial]
case = 2
q = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]
u = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]
[effects]
gravity = [0.0, 0.0, -9.81]
[simulate]
duration = 0.01
dt = 0.001
"""


def _scene_file(tmp_path, text):
    models = tmp_path / "models"
    (models / "scenes").mkdir(parents=True)
    src = shipped.scenes_dir().parent
    for name in ("two_body.toml", "two_body.xml", "two_body_euler.xml", "two_body_euler.urdf"):
        (models / name).write_text((src / name).read_text())
    path = models / "scenes" / "s.toml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("edit,match", [
    (("dt = 0.001", "dt = -1"), r"line 12, field \[simulate\]\.dt: expected a positive"),
    (("gravity = [0.0, 0.0, -9.81]", "gravty = 1"), r"field \[effects\]\.gravty: unknown effect"),
    (("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, -9.81]"), r"line 9, field \[effects\]\.gravity"),
    (("case = 2", "case = 7"), r"line 5, field \[initial\]\.case: unknown case"),
    (("q = [0.0, 0.0, 0.0, 1.0", "q = [0.0, 0.0, 0.0, 2.0"), r"field \[initial\]\.q: .*does not normalize"),
    (('fixture = "two_body"', 'fixture = "nope"'), r"field \[model\]\.fixture: no model file"),
    (("duration = 0.01", 'duration = 0.01\nintegrator = "implicit"'), r"exists in MuJoCo only"),
    (("[simulate]", "[simulat]"), r"unknown top-level keys \['simulat'\]"),
])
def test_malformed_scene_files(tmp_path, edit, match):
    """A bad scene raises FixtureError naming the file, the line and the field."""
    path = _scene_file(tmp_path, SCENE.replace(*edit))
    with pytest.raises(FixtureError, match=match):
        scenes.load(path)


def test_inline_model_writes_its_own_engine_files(tmp_path):
    """[model] with inline geometry builds fixtures in a temporary directory and runs on every engine."""
    text = SCENE.replace('fixture = "two_body"', "q2 = [0.2, 0.0, 0.1]\nr2 = [0.1, 0.1, 0.0]\nm1 = 1.5")
    scene = scenes.load(_scene_file(tmp_path, text))
    pos, _, _ = simulate.run(scene).differences()
    assert scene.fixture.chain.m1 == 1.5 and pos < 1e-9


def test_scene_overrides_are_validated():
    """Scene.replace checks dt, integrator and engines like the file loader does."""
    scene = scenes.load(CHAIN[0])
    with pytest.raises(InputError, match="dt"):
        scene.replace(dt=0.0)
    with pytest.raises(InputError, match="engines"):
        scene.replace(engines=("bullet",))


def test_a_scene_that_lists_no_engines_runs_relacc_pinocchio_and_mujoco(tmp_path):
    """The file format's default, as the guide's table says it: an absent ``[simulate] engines`` is relacc, Pinocchio
    and MuJoCo (the engines whose traits say ``in_scenes``), in report order; a listed one is taken as written."""
    assert scenes.load(_scene_file(tmp_path, SCENE)).engines == ("relacc", "pinocchio", "mujoco")
    listed = _scene_file(tmp_path / "b", SCENE + 'engines = ["mujoco", "relacc"]\n')
    assert scenes.load(listed).engines == ("mujoco", "relacc")


def test_cli_simulate_json_and_csv(tmp_path, capsys):
    """relacc simulate --json prints the documented keys; --out writes one CSV per engine, Drake's included."""
    path = _scene_file(tmp_path, SCENE + 'engines = ["relacc", "pinocchio", "mujoco", "drake"]\n'
                                         '[simulate.drake]\nintegrator = "runge_kutta5"\n')
    assert main(["simulate", str(path), "--json", "--quiet", "--out", str(tmp_path / "out")]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert {"engines", "max_point_position_difference", "max_point_velocity_difference"} <= set(summary)
    assert (summary["point"], summary["reference"]) == ("G2", "the note's")  # the same keys as a model's scene
    for name in ENGINES:
        assert set(summary["engines"][name]) >= {"point_position_final", "energy_drift", "seconds"}
        csv = Path(tmp_path / "out" / f"s-{name}.csv").read_text().splitlines()
        assert csv[0].startswith("# relacc simulate") and csv[1].startswith("t_s,") and len(csv) == 2 + 11


def test_an_integrator_drake_lacks_is_named_at_its_table(tmp_path, capsys):
    """[simulate.drake]'s integrator is checked against Drake's traits when the scene is read: one line, exit 2, at
    that table's line, naming Drake's integrators."""
    text = SCENE + 'engines = ["relacc", "drake"]\n[simulate.drake]\nintegrator = "bogus"\n'
    path = _scene_file(tmp_path, text)
    assert main(["simulate", str(path), "--quiet"]) == 2
    err = capsys.readouterr().err
    line = 1 + text.splitlines().index('integrator = "bogus"')
    assert err.count("\n") == 1 and f"line {line}, field [simulate.drake].integrator" in err, err
    assert "Drake has no 'bogus' integrator" in err and "runge_kutta5" in err


def test_the_last_step_is_always_recorded(tmp_path):
    """record_every = 1000 on a 50-step run records t = 0 and t = duration, and the end is the state there."""
    scene = scenes.load(_scene_file(tmp_path, SCENE.replace("dt = 0.001", "dt = 0.0002\nrecord_every = 1000")))
    result = simulate.run(scene)
    every = simulate.run(scene.replace(record_every=1))
    for name, tr in result.trajectories.items():
        assert tr.t.tolist() == [0.0, 0.01]
        assert np.array_equal(tr.position[-1], every.trajectories[name].position[-1])
        assert result.summary()["engines"][name]["t_final"] == 0.01


@pytest.mark.parametrize("duration,dt", [(0.05, 0.03), (1.0, 0.3)])
def test_durations_must_be_whole_steps(tmp_path, duration, dt):
    """A duration that is not a whole number of steps is an error naming both numbers, never rounded."""
    text = SCENE.replace("duration = 0.01", f"duration = {duration}").replace("dt = 0.001", f"dt = {dt}")
    with pytest.raises(FixtureError, match=rf"{duration} s is not a whole number of steps of dt = {dt} s"):
        scenes.load(_scene_file(tmp_path, text))
    with pytest.raises(InputError, match="not a whole number of steps"):
        scenes.load(CHAIN[0]).replace(duration=duration, dt=dt)


def test_energy_drift_of_a_chain_falling_from_rest(tmp_path):
    """At rest with its mass center at zero height, E(0) = 0: the drift is RK4's tiny one, not |dE| / |E(0)|."""
    chain = scenes.load(CHAIN[0]).fixture.chain
    z = (chain.m1 * chain.r1[2] + chain.m2 * (chain.q2[2] + chain.r2[2])) / (chain.m1 + chain.m2)
    text = SCENE.replace("q = [0.0, 0.0, 0.0, 1.0", f"q = [0.0, 0.0, {float(-z)!r}, 1.0").replace(
        "u = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]", "u = [" + ", ".join(["0.0"] * 12) + "]")
    result = simulate.run(scenes.load(_scene_file(tmp_path, text)).replace(duration=0.2))
    for name, tr in result.trajectories.items():
        assert abs(tr.energy[0]) < 1e-14 and np.max(tr.energy_scale) > 0.1  # E(0) = 0; T and V_g grow
        change = np.max(np.abs(tr.energy - tr.energy[0]))
        assert change / max(abs(tr.energy[0]), 1e-300) > 1  # normalizing by |E(0)| would report nonsense
        assert tr.energy_drift() < 1e-9, (name, tr.energy_drift())
        assert result.tracks[name].energy_drift() == pytest.approx(tr.energy_drift(), rel=1e-12)


@pytest.mark.slow
def test_long_runs_keep_only_a_block(tmp_path):
    """With keep=False and CSVs streamed, memory is set by the block: 5x the steps, about the same peak."""
    import tracemalloc

    from relacc.simulate.runs import RECORD_BLOCK

    def peak(duration):
        scene = scenes.load(shipped.scene_path("tumbling")).replace(duration=duration, dt=1e-3, engines=("mujoco",))
        tracemalloc.start()
        result = simulate.run(scene, keep=False, out=tmp_path / f"d{duration}")
        _, top = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        assert result.trajectories == {}
        rows = (tmp_path / f"d{duration}" / f"{scene.name}-mujoco.csv").read_text().count("\n") - 2
        assert rows == scene.n_steps + 1
        return top

    short, long_ = peak(2 * RECORD_BLOCK * 1e-3), peak(10 * RECORD_BLOCK * 1e-3)
    assert long_ < 1.5 * short + 2e6, (short, long_)


def test_inline_models_leave_no_temporary_directory(tmp_path, monkeypatch):
    """A scene with an inline chain loads and runs without leaving a relacc-* directory in the temp dir."""
    import tempfile

    monkeypatch.setenv("TMPDIR", str(tmp_path / "tmp"))
    (tmp_path / "tmp").mkdir()
    monkeypatch.setattr(tempfile, "tempdir", None)
    text = SCENE.replace('fixture = "two_body"', "q2 = [0.2, 0.0, 0.1]\nr2 = [0.1, 0.1, 0.0]")
    simulate.run(scenes.load(_scene_file(tmp_path, text)))
    with pytest.raises(FixtureError):
        scenes.load(_scene_file(tmp_path / "bad", text.replace("r2 = [0.1, 0.1, 0.0]", "r2 = [0.1, 0.1]")))
    assert list((tmp_path / "tmp").iterdir()) == []


@pytest.mark.slow
def test_model_engines_apply_only_the_scenes_effects():
    """gymnasium's ant carries joint damping (1), limits (+-30 to 70 deg), contacts with a floor, armature and
    motors. Its default scene names none of them: started inside the floor with speeds that cross every limit, the
    engines agree with relacc's tree (which knows none of them) to rounding, while MuJoCo's own step of the file
    (gravity off, the scene's integrator and step) moves the torso otherwise (measured 0.93 m, the floor pushing
    it out): a run that applied any of them would differ."""
    import gymnasium
    import mujoco

    path = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "ant.xml"
    scene = scenes.model_scene(path, seed=3, duration=0.1, dt=1e-3)
    q, u = scene.q.copy(), 5.0 * scene.u
    q[2] = 0.0  # the torso's centre in the floor's plane
    scene = scene.replace(q=q, u=u, engines=("relacc", "mujoco", "pinocchio", "drake"))
    result = simulate.run(scene)
    pos, _, pairs = result.differences()
    assert pos <= 1e-9, pairs  # measured 3.6e-11: Drake's error-controlled RK5 against the RK4 of the others
    model = mujoco.MjModel.from_xml_path(str(path))
    model.opt.gravity[:] = 0.0
    model.opt.timestep, model.opt.integrator = 1e-3, mujoco.mjtIntegrator.mjINT_RK4
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = q, u
    for _ in range(100):
        mujoco.mj_step(model, data)
    mine = result.trajectories["relacc"].position[-1]
    assert np.abs(data.xipos[1] - mine).max() > 1e-3


def test_a_symmetric_state_is_not_called_a_disagreement():
    """gymnasium's ant with mirrored leg speeds and no load on its torso: the legs' reactions on the torso cancel, its
    acceleration is zero, and each engine's rounding of them is not. relacc's acceleration check judges it against
    the scale the forward dynamics contributes (the point's partial velocities times the solve's: relacc.simulate.
    subjects._solve_scale), not the kinematic terms alone, which vanish there: the two agree (before: MuJoCo was
    called wrong by 1.01 of the scale, in every case)."""
    from relacc import simulate
    from relacc.dynamics.tree_effects import JointEffect, TreeEffects
    from relacc.fixtures.shipped import scene_path
    from relacc.simulate import scenes

    base = scenes.load(scene_path("ant_tumbling"))
    for case in (1, 2, 3):
        from relacc.core.tree import convert

        q, u, _ = convert(base.tree, base.q[None], base.u[None], source=2, target=case)
        scene = base.replace(case=case, q=q[0], u=u[0], duration=0.02, engines=("relacc", "mujoco"),
                             effects=TreeEffects(gravity=np.zeros(3), joints={"hip_1": JointEffect(2.0)}))
        run = simulate.run(scene)
        check = run.note_check["mujoco"]
        assert run.agree and check["error"] <= check["bound"], (case, check)


def test_a_model_scene_in_every_case_is_one_motion():
    """gymnasium's ant with leg springs and a torso torque, integrated by relacc's RK4 at 1 ms for 0.05 s in each
    case's own coordinates (relacc's compiled stepper in each): the three runs, converted to case 2, are one motion.
    Each is fourth order, so they differ by the truncation of 50 steps, about N h^5 |x^(5)| (speeds about 2 rad/s:
    |x^(5)| ~ 2^5, so 50 x 1e-15 x 32 ~ 2e-12), well under 1e-9; integrating 1-2-3 angles with the body angular
    velocity instead of their rates (the Python stepper's case 3 before) moved them 1e-3 rad apart."""
    from relacc.core.tree import convert
    from relacc.fixtures.shipped import scene_path
    from relacc.simulate.subjects import tree_stepper

    base = scenes.load(scene_path("ant_tumbling"))
    end = {}
    for case in (1, 2, 3):
        q, u, _ = convert(base.tree, base.q[None], base.u[None], source=2, target=case)
        x, v = tree_stepper(base.tree, case, base.effects, 1e-3, "rk4").advance(q[0], u[0], 50)
        end[case] = convert(base.tree, np.asarray(x)[None], np.asarray(v)[None], source=case, target=2)
    for case in (1, 3):
        for a, b in zip(end[case][:2], end[2][:2]):  # coordinates (m, unit quaternions), speeds (m/s, rad/s)
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-9, err_msg=f"case {case}")


UNSTABLE = """title = "A stiff spring MuJoCo's Euler cannot hold"
[model]
fixture = "two_body"
[initial]
case = 2
q = [0.0, 0.0, 0.0,  1.0, 0.0, 0.0, 0.0,  0.1, 0.0, 0.0,  1.0, 0.0, 0.0, 0.0]
u = [0.0, 0.0, 0.0,  0.0, 0.0, 0.0,  0.0, 0.0, 0.0,  0.0, 0.0, 0.0]
[effects.spring]
stiffness = 1e9
[simulate]
duration = 5.0
dt = 0.01
integrator = "euler"
engines = ["mujoco"]
"""


@pytest.mark.slow
def test_an_unstable_engine_run_is_a_diverged_run(tmp_path):
    scene = tmp_path / "unstable.toml"
    scene.write_text(UNSTABLE)
    work = tmp_path / "work"
    work.mkdir()
    line = one_line(run_relacc("simulate", str(scene), cwd=work))
    assert "mujoco" in line and "diverged" in line
    assert list(work.iterdir()) == []
