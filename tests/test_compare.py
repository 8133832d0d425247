"""relacc compare: the audit finds and attributes planted faults; dynamics agree where the engines read alike."""

import json
import os
from pathlib import Path

import pytest

from relacc.cli import main
from relacc.core.tolerances import robot_tolerance
from relacc.errors import ModelError
from relacc.fixtures.shipped import models_dir
from relacc.validation.robots import URDF_CAUSE, compare

ARM_MJCF = """<mujoco model="arm">
  <compiler angle="radian"/>{compiler}
  <worldbody>
    <body name="link1" pos="0 0 0.1">
      <joint name="j1" type="hinge" axis="0 0 1"{armature}/>
      <inertial pos="0.1 0 0" mass="1.0" diaginertia="0.01 0.02 0.03"/>
      <body name="link2" pos="0.2 0 0">
        <joint name="j2" type="hinge" axis="0 1 0"/>
        <inertial pos="0.15 0 0" mass="0.8" diaginertia="0.004 0.005 0.006"/>
        <body name="link3" pos="0.3 0 0">
          <joint name="j3" type="hinge" axis="1 0 0"/>
          <geom type="box" size="0.05 0.02 0.01" pos="0.05 0.02 0" mass="0.5"{visual}/>
        </body>
      </body>
    </body>{extra}
  </worldbody>
</mujoco>
"""

ARM_URDF = """<robot name="arm">
  <link name="base"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="link1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-4" upper="4" effort="1" velocity="1"/></joint>
  <link name="link1"><inertial><origin xyz="0.1 0 0"/><mass value="1.0"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/>
    <origin xyz="0.2 0 0"/><axis xyz="{axis2}"/><limit lower="-4" upper="4" effort="1" velocity="1"/></joint>
  <link name="link2"><inertial><origin xyz="0.15 0 0"/><mass value="{mass2}"/>
    <inertia ixx="0.004" iyy="0.005" izz="0.006" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j3" type="revolute"><parent link="link2"/><child link="link3"/>
    <origin xyz="0.3 0 0"/><axis xyz="1 0 0"/><limit lower="-4" upper="4" effort="1" velocity="1"/></joint>
  <link name="link3"><inertial><origin xyz="0.05 0.02 0"/><mass value="0.5"/>
    <inertia ixx="{ixx3}" iyy="{iyy3}" izz="{izz3}" ixy="0" ixz="0" iyz="0"/></inertial></link>
</robot>
"""
BOX = (0.05, 0.02, 0.01)  # link3's box half-sizes: its inertia, by hand, for the URDF
IXX3, IYY3, IZZ3 = (0.5 / 3 * (BOX[1] ** 2 + BOX[2] ** 2), 0.5 / 3 * (BOX[0] ** 2 + BOX[2] ** 2),
                    0.5 / 3 * (BOX[0] ** 2 + BOX[1] ** 2))


def arm(tmp_path, *, compiler="", armature="", visual="", extra="", axis2="0 1 0", mass2="0.8"):
    """An MJCF arm and a URDF of it written side by side; keyword arguments plant faults in one of them."""
    xml = tmp_path / "arm.xml"
    xml.write_text(ARM_MJCF.format(compiler=compiler, armature=armature, visual=visual, extra=extra))
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(ARM_URDF.format(axis2=axis2, mass2=mass2, ixx3=IXX3, iyy3=IYY3, izz3=IZZ3))
    return xml, urdf


def rows(result, engine):
    return {(a.item, a.where): a for a in result.audit if engine in a.values}


def failing(result, engine):
    return {q: r[engine] for q, r in result.dynamics.items() if engine in r and not r[engine].passed}


def test_arm_and_its_urdf_agree_to_a_few_eps(tmp_path):
    """The control: an MJCF arm and a URDF written from the same numbers agree in every audit item and quantity."""
    xml, urdf = arm(tmp_path)
    result = compare(xml, urdf=urdf, engines=["pinocchio"], n_states=10, seed=3)
    assert result.audit == [], [a.as_json() for a in result.audit]
    assert failing(result, "pinocchio") == {}, f"seed {result.seed}"
    assert result.exit_code == 0 and len(result.dynamics) == 8


@pytest.mark.parametrize("fault,item,where,values", [
    ({"mass2": "0.9"}, "mass (kg)", "link link2", {"relacc": 0.8, "pinocchio": 0.9}),
    ({"axis2": "0 0.6 0.8"}, "joint axis (world, at the reference configuration)", "joint j2 (hinge, body link2)",
     {"relacc": [0.0, 1.0, 0.0], "pinocchio": [0.0, 0.6, 0.8]}),
    ({"armature": ' armature="0.05"'}, "armature", "joint j1 (hinge, body link1)",
     {"relacc": [0.05], "pinocchio": [0.0]}),
])
def test_planted_faults_are_found_and_attributed(tmp_path, fault, item, where, values):
    """A changed mass, a moved joint axis, a missing armature: each one audit row, at its element, with the cause."""
    xml, urdf = arm(tmp_path, **fault)
    result = compare(xml, urdf=urdf, engines=["pinocchio"], n_states=4, seed=1)
    found = rows(result, "pinocchio")
    consequences = {("total mass (kg)", "model")} if item == "mass (kg)" else set()
    assert (item, where) in found and set(found) <= {(item, where)} | consequences, [a.as_json() for a in result.audit]
    row = found[(item, where)]
    for engine, value in values.items():
        assert row.values[engine] == pytest.approx(value, abs=1e-12)
    assert row.cause == f"pinocchio: {URDF_CAUSE}"
    assert failing(result, "pinocchio"), "the fault must show in the dynamics too"
    assert all("URDF" in r.cause for r in failing(result, "pinocchio").values())
    assert result.exit_code == 1


@pytest.mark.parametrize("plant,engines,where,cause", [
    ({"compiler": '\n  <compiler settotalmass="5"/>'}, ("pinocchio", "drake"), "model", "settotalmass"),
    ({"extra": '\n    <body name="puck" pos="1 0 0"><joint name="px" type="slide" axis="1 0 0"/>'
               '<geom type="sphere" size="0.05"/></body>'}, ("pinocchio",), "joint px (slide, body puck)",
     "reads only the first <body> written directly in the main file"),
    ({"visual": ' contype="0" conaffinity="0"', "armature": ""}, ("pinocchio",), "link link3",
     "contype=0 and conaffinity=0"),
])
def test_known_parser_readings_are_reproduced(tmp_path, plant, engines, where, cause):
    """MJCF features an engine's parser reads otherwise are attributed by recompiling MuJoCo that engine's way."""
    xml, _ = arm(tmp_path, **plant)
    result = compare(xml, n_states=4, seed=2)
    for engine in engines:
        attributed = [a for a in rows(result, engine).values() if a.where == where]
        assert attributed, (engine, [a.as_json() for a in result.audit])
        assert all(cause in a.cause for a in attributed), [a.cause for a in attributed]
        assert not [a for a in result.audit if "not explained" in a.cause], [a.as_json() for a in result.audit]
        assert all(not r.cause.startswith("not explained") for r in failing(result, engine).values())


def test_relaccs_own_chain_agrees_with_drake_to_a_few_eps():
    """The control: two_body.xml in Drake (free joint, slides, ball through speed maps) agrees in everything."""
    result = compare(models_dir() / "two_body.xml", engines=["drake"], n_states=10, seed=0)
    assert result.audit == [] and failing(result, "drake") == {}
    tol = robot_tolerance(2)
    assert all(r["drake"].max_error <= tol for r in result.dynamics.values())


def test_relaccs_own_chain_in_pinocchio_differs_by_known_causes_only():
    """Pinocchio on two_body.xml: only its gravity reading and its composite-joint J_dot differ, both attributed."""
    result = compare(models_dir() / "two_body.xml", engines=["pinocchio"], n_states=10, seed=0)
    assert [(a.item, a.where) for a in result.audit] == [("gravity (m/s^2)", "model")]
    assert "ignores <option gravity>" in result.audit[0].cause
    bad = failing(result, "pinocchio")
    assert set(bad) == {"bias forces", "gravity forces", "forward dynamics", "J_dot v"}
    assert all("<option gravity>" in bad[q].cause for q in ("bias forces", "gravity forces", "forward dynamics"))
    assert "JointModelComposite" in bad["J_dot v"].cause
    for quantity in ("mass matrix", "COM position", "COM Jacobian", "classical acceleration"):
        assert result.dynamics[quantity]["pinocchio"].passed


def gym_assets():
    import gymnasium  # a test dependency (pip install -e .[test]): if it is missing these tests fail
    return Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"


GYM = {  # file: facts the audit must state (item, where, engine, mujoco's value, the engine's)
    "half_cheetah.xml": [("total mass (kg)", "model", "pinocchio", 14.0, 21.18371737525)],
    "swimmer.xml": [("total mass (kg)", "model", "pinocchio", 106.81415022205, 0.0)],
    "pusher.xml": [("degrees of freedom", "model", "pinocchio", 11, 7)],
    "reacher.xml": [("degrees of freedom", "model", "pinocchio", 4, 2)],
}


@pytest.mark.slow
@pytest.mark.parametrize("name", ["ant.xml", "half_cheetah.xml", "hopper.xml", "humanoid.xml", "humanoidstandup.xml",
                                  "inverted_double_pendulum.xml", "inverted_pendulum.xml", "point.xml", "pusher.xml",
                                  "pusher_v5.xml", "reacher.xml", "swimmer.xml", "walker2d.xml", "walker2d_v5.xml"])
def test_gymnasium_assets_are_compared_and_every_difference_explained(name):
    """Each gymnasium MuJoCo asset: compared (exit 0 or 1), the known facts stated, no difference without a cause."""
    path = gym_assets() / name
    result = compare(path, n_states=4, seed=0)
    assert result.exit_code in (0, 1)
    assert result.engines["pinocchio"].loaded
    unexplained = [a.as_json() for a in result.audit if "not explained" in a.cause]
    unexplained += [(q, e, r.cause) for q, rs in result.dynamics.items() for e, r in rs.items()
                    if not r.passed and r.cause.startswith("not explained")]
    assert unexplained == []
    for item, where, engine, mine, theirs in GYM.get(name, []):
        row = rows(result, engine)[(item, where)]
        assert row.values["relacc"] == pytest.approx(mine, rel=1e-10)
        assert row.values[engine] == pytest.approx(theirs, rel=1e-10, abs=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["ant.xml", "humanoid.xml"])
def test_free_root_models_are_compared_through_the_speed_maps(name):
    """ant and humanoid (free root joint): every quantity is compared for both engines, none left out."""
    result = compare(gym_assets() / name, n_states=4, seed=5)
    for engine in ("pinocchio", "drake"):
        assert all(engine in rs for rs in result.dynamics.values())
        assert result.dynamics["forward dynamics"][engine].passed or result.dynamics["forward dynamics"][engine].cause
    assert result.dynamics["COM Jacobian"]["pinocchio"].passed and result.dynamics["mass matrix"]["pinocchio"].passed
    if name == "ant.xml":
        assert result.agree


def test_json_summary_has_the_documented_fields(tmp_path, capsys):
    """--json prints model, engines (loaded, nq, nv, error), audit rows and dynamics (max_error, tolerance, ok)."""
    xml, _ = arm(tmp_path, armature=' armature="0.05"')
    code = main(["compare", str(xml), "--json", "--states", "3", "--out", str(tmp_path / "page.html")])
    data = json.loads(capsys.readouterr().out)
    # Drake's MJCF parser drops an armature without an actuator on its joint: a known difference, so exit 1
    assert code == 1 and data["agree"] is False
    assert [(a["item"], a["where"]) for a in data["audit"]] == [("armature", "joint j1 (hinge, body link1)")]
    assert set(data) >= {"model", "engines", "audit", "dynamics", "agree"}
    assert set(data["engines"]["pinocchio"]) >= {"loaded", "nq", "nv", "error"}
    assert all(set(a) >= {"item", "where", "relacc", "cause", "cause_kind", "place"} for a in data["audit"])
    assert all(set(r) >= {"max_error", "tolerance", "ok"} for r in data["dynamics"].values())
    html = (tmp_path / "page.html").read_text()
    assert "<script" not in html and "armature" in html and 'src="http' not in html


@pytest.mark.parametrize("content,name,message", [
    (None, "missing.xml", "no such file"),
    ("<mujoco><worldbody><body name='a'><joint type='hinge'/></body></worldbody>", "broken.xml", "at line 1"),
    ('<mujoco><asset><mesh name="m" file="absent_mesh.stl"/></asset><worldbody><body name="b">'
     '<joint type="hinge"/><geom type="mesh" mesh="m"/></body></worldbody></mujoco>', "mesh.xml", "absent_mesh.stl"),
])
def test_models_that_cannot_be_compared_exit_2_with_one_line(tmp_path, capsys, content, name, message):
    """A missing file, a parser failure, a missing mesh: one line on stderr naming it, exit 2, no traceback."""
    path = tmp_path / name
    if content is not None:
        path.write_text(content)
    assert main(["compare", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err
    with pytest.raises(ModelError):
        compare(path)


def test_no_file_is_left_when_the_page_cannot_be_written(tmp_path, capsys):
    """--out under a file (a place no directory can be made) is refused before any work, with one line and exit 2;
    a missing directory is made, as `relacc report` makes it."""
    xml, _ = arm(tmp_path)
    (tmp_path / "a_file").write_text("x")
    assert main(["compare", str(xml), "--out", str(tmp_path / "a_file" / "page.html")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "a_file" in err
    assert sorted(os.listdir(tmp_path)) == ["a_file", "arm.urdf", "arm.xml"]
    assert main(["compare", str(xml), "--engines", "pinocchio", "--states", "1", "--out",
                 str(tmp_path / "new" / "page.html")]) == 0
    assert os.listdir(tmp_path / "new") == ["page.html"]


def other_model(package: str, inside: str) -> Path:
    """A model file shipped inside an installed engine's pip package."""
    import importlib.util

    return Path(importlib.util.find_spec(package).origin).parent / inside


def strict(text: str):
    """JSON as the standard has it: no Infinity or NaN."""
    def refuse(constant):
        raise ValueError(f"{constant} is not JSON")
    return json.loads(text, parse_constant=refuse)


def test_drake_names_a_model_without_a_name_and_says_so():
    """gymnasium's point.xml has no model name: Drake loads it through a directive naming it, says so, and agrees."""
    result = compare(gym_assets() / "point.xml", engines=["drake"], n_states=4, seed=0)
    report = result.engines["drake"]
    assert report.loaded and any("no model name" in w and "'point'" in w for w in report.warnings)
    assert result.audit == [] and all(rs["drake"].passed for rs in result.dynamics.values())


def test_a_urdf_model_is_read_by_every_engines_urdf_parser():
    """Drake's acrobot URDF: its root link, which no joint carries, is welded to the world in Drake as MuJoCo and
    Pinocchio read it (Drake's parser alone would float it), and the warnings say so; everything agrees."""
    result = compare(other_model("pydrake", "share/drake/examples/acrobot/Acrobot_no_collision.urdf"),
                     n_states=4, seed=1)
    assert (result.engines["pinocchio"].nv, result.engines["drake"].nv) == (2, 2)
    assert any("welded the URDF's root link 'base_link'" in w for w in result.engines["drake"].warnings)
    assert result.audit == []
    assert all(rs[e].passed for rs in result.dynamics.values() for e in ("pinocchio", "drake")), f"seed {result.seed}"


ROBOT_URDF = """<?xml version="1.0"?>
<robot name="gripper_arm">
  <link name="base"><inertial><mass value="3.0"/><origin xyz="0 0 0.05"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="package://no_such_package/meshes/base.dae"/></geometry></visual>
    <collision><geometry><mesh filename="package://no_such_package/meshes/base.stl"/></geometry></collision></link>
  <link name="arm"><inertial><mass value="1.2"/><origin xyz="0.2 0 0" rpy="0.1 0.2 0.3"/>
    <inertia ixx="0.004" iyy="0.03" izz="0.031" ixy="0.001" ixz="0" iyz="0.0005"/></inertial>
    <collision><geometry><mesh filename="meshes/arm.obj"/></geometry></collision></link>
  <link name="left"><inertial><mass value="0.1"/><origin xyz="0.02 0.01 0"/>
    <inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="right"><inertial><mass value="0.1"/><origin xyz="0.02 -0.01 0"/>
    <inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0 0 0.1" rpy="0 0.3 0"/><axis xyz="0 0.6 0.8"/><limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <joint name="left_finger" type="prismatic"><parent link="arm"/><child link="left"/>
    <origin xyz="0.4 0.01 0"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="10" velocity="1"/></joint>
  <joint name="right_finger" type="prismatic"><parent link="arm"/><child link="right"/>
    <origin xyz="0.4 -0.01 0"/><axis xyz="0 -1 0"/><limit lower="0" upper="0.04" effort="10" velocity="1"/>
    <mimic joint="left_finger" multiplier="1" offset="0"/></joint>
</robot>
"""


def test_a_real_style_urdf_with_meshes_mimic_and_a_free_root_link_is_compared(tmp_path):
    """A URDF as robots ship them: package:// meshes from a package that is not here, a .dae visual, a relative mesh
    that does not exist, a mimic joint (Drake reads it as a constraint its continuous plant cannot evaluate: a
    traceback before) and a root link no joint carries. Every engine reads its kinematics and inertials, the
    warnings say what was dropped and welded, and the dynamics agree within the error model; nothing is written."""
    path = tmp_path / "gripper_arm.urdf"
    path.write_text(ROBOT_URDF)
    result = compare(path, n_states=6, seed=2)
    # PyBullet refuses a URDF whose mesh files are missing (a visual's too) and says which, in one line
    assert {n: r.loaded for n, r in result.engines.items()} == {"relacc": True, "pinocchio": True, "mujoco": True,
                                                                 "drake": True, "pybullet_file": False,
                                                                 "idyntree": True}
    assert "cannot find 'no_such_package/meshes/base.dae'" in result.engines["pybullet_file"].error
    assert "\n" not in result.engines["pybullet_file"].error
    assert {n: r.nv for n, r in result.engines.items() if r.loaded} == {"relacc": 3, "pinocchio": 3, "mujoco": 3,
                                                                         "drake": 3, "idyntree": 3}
    for name in ("mujoco", "pinocchio", "drake"):
        assert any("dropped the URDF's 1 visual and 2 collision elements" in w and "1 mimic element" in w
                   for w in result.engines[name].warnings), result.engines[name].warnings
    assert result.audit == [], [a.as_json() for a in result.audit]
    assert result.agree, f"seed {result.seed}"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gripper_arm.urdf"]


def test_an_engine_failing_to_evaluate_is_that_engine_not_taking_part(tmp_path, monkeypatch):
    """Whatever an engine raises while it evaluates (here a RuntimeError planted in Drake's forward dynamics, as
    Drake raises for constraints) is that engine not taking part, with its message on one line; the others are
    still compared."""
    from relacc.engines.drake_.adapter import DrakeAdapter

    def fails(self, *args, **kwargs):
        raise RuntimeError("Continuous time does not support constraints.\n(planted)")

    monkeypatch.setattr(DrakeAdapter, "forward", fails)
    path = tmp_path / "gripper_arm.urdf"
    path.write_text(ROBOT_URDF)
    result = compare(path, n_states=2, seed=0)
    drake = result.engines["drake"]
    assert not drake.loaded and drake.error == ("drake fails to evaluate it: RuntimeError: Continuous time does not "
                                                "support constraints. (planted)")
    assert "drake" not in {e for rows in result.dynamics.values() for e in rows}
    assert all(rows["pinocchio"].passed for rows in result.dynamics.values())


@pytest.mark.slow
def test_a_singular_mass_matrix_is_named_not_a_traceback(tmp_path, capsys):
    """MuJoCo's testdata/model.xml: Drake's M over the shared speeds is singular; its forward dynamics is undefined,
    written null in strict JSON and said on the page, with the joint named, and the run exits 1."""
    import numpy as np

    from relacc.engines import load

    path = other_model("mujoco", "testdata/model.xml")
    reference = load("mujoco", path)
    M = load("drake", path, reference.reference).dynamics(reference.model.qpos0, np.zeros(reference.model.nv)).M
    assert np.linalg.matrix_rank(M) < M.shape[0]  # the independent fact: Drake's own M is singular
    assert main(["compare", str(path), "--states", "3", "--json", "--out", str(tmp_path / "page.html")]) == 1
    row = strict(capsys.readouterr().out)["dynamics"]["forward dynamics"]["engines"]["drake"]
    assert row["max_error"] is None and row["ok"] is False
    assert "singular" in row["cause"] and "slider" in row["cause"]
    assert "forward dynamics undefined" in (tmp_path / "page.html").read_text()


def test_a_model_without_a_body_exits_2_with_one_line(capsys):
    """MuJoCo's own mesh test model has no body: relacc cannot read a robot in it, one line, exit 2."""
    assert main(["compare", str(other_model("mujoco", "testdata/msh.xml"))]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "has no <body>" in err and "Traceback" not in err


@pytest.mark.parametrize("inside,refusing", [
    ("share/drake/examples/acrobot/Acrobot.urdf", {"mujoco": "URDF joint parent or child missing",
                                                   "pinocchio": "parent link [world] of joint [base_weld] not found"}),
    ("share/drake/examples/pendulum/Pendulum.urdf", {"mujoco": "inertia must have positive eigenvalues"}),
])
def test_where_engines_refuse_a_file_the_others_are_compared_with_relacc(capsys, inside, refusing):
    """Drake's own URDFs, which MuJoCo (and, for the acrobot, Pinocchio) refuse: before, exit 2 with MuJoCo's words;
    now relacc reads them, the engines that read them are compared with relacc's reading and agree, and each refusal
    is one line of the result (nothing on stderr: urdfdom's own error print is in Pinocchio's line)."""
    assert main(["compare", str(other_model("pydrake", inside)), "--states", "3", "--json"]) == 0
    out = capsys.readouterr()
    data = json.loads(out.out)
    assert out.err == ""
    for engine, said in refusing.items():
        assert not data["engines"][engine]["loaded"] and said in data["engines"][engine]["error"]
    assert "drake" in data["compared"] and data["agree"]


STACKED_MJCF = """<mujoco model="stacked">
  <worldbody>
    <body name="base" pos="0 0 1">
      <joint name="root" type="hinge" axis="1 0 0"/>
      <geom type="sphere" size="0.1" mass="2"/>
      <body name="hip" pos="0.3 0.1 0" euler="0 0 90">
        <joint name="hip_z" type="hinge" axis="0 0 1"/>
        <joint name="hip_y" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.05" mass="1"/>
      </body>
    </body>
  </worldbody>
  <actuator>{actuators}</actuator>
</mujoco>
"""


def test_stacked_joints_of_a_body_oriented_by_euler_angles_are_attributed(tmp_path):
    """A body rotated by euler="0 0 90" with two joints: Drake puts the first at the parent's origin (its numbers
    read in the parent's frame), and the audit attributes it to that reading, not to an unknown cause."""
    xml = tmp_path / "stacked.xml"
    xml.write_text(STACKED_MJCF.format(actuators=""))
    result = compare(xml, engines=["drake"], n_states=3, seed=0)
    row = rows(result, "drake")[("joint position (world, m)", "joint hip_z (hinge, body hip)")]
    # a hinge's position is the point of its axis (here vertical) nearest the world origin (docs/compare.md)
    assert row.values["relacc"] == pytest.approx([0.3, 0.1, 0.0], abs=1e-12)  # the XML: hip at 0.3 0.1 on base
    assert row.values["drake"] == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)  # through the parent's origin
    assert "several joints in the parent" in row.cause


@pytest.mark.parametrize("actuator,kept", [("motor", True), ("position", True), ("velocity", False),
                                           ("general", False)])
def test_drake_keeps_armature_only_with_the_actuators_it_reads(tmp_path, actuator, kept):
    """Armature on a joint driven by <motor> or <position> survives in Drake; by <velocity> or <general> it is lost,
    and the audit says why."""
    gains = {"motor": 'gear="2"', "position": 'kp="10"', "velocity": 'kv="1"', "general": 'gear="2"'}[actuator]
    xml = tmp_path / "armature.xml"
    xml.write_text(STACKED_MJCF.replace('name="root" type="hinge"', 'name="root" type="hinge" armature="0.3"')
                   .format(actuators=f'<{actuator} joint="root" {gains}/>'))
    result = compare(xml, engines=["drake"], n_states=3, seed=0)
    found = rows(result, "drake").get(("armature", "joint root (hinge, body base)"))
    if kept:
        assert found is None
    else:
        assert found.values == {"relacc": [0.3], "drake": [0.0]} and "<motor> or <position>" in found.cause


@pytest.mark.slow
def test_docs_table_is_current():
    """docs/compare.md's tables (gymnasium's assets, models outside it) are what scripts/compare_table.py writes."""
    import importlib.util
    import re

    gym_assets()
    path = Path(__file__).resolve().parents[1] / "scripts" / "compare_table.py"
    spec = importlib.util.spec_from_file_location("compare_table", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    doc = module.DOC.read_text()
    for marker, models in (("gymnasium", None), ("others", module.other_models())):
        shown = re.search(rf"<!-- compare:{marker} -->\n(.*?)\n<!-- /compare:{marker} -->", doc, re.S).group(1)
        assert shown == module.table(models), f"{marker}: run python scripts/compare_table.py"


@pytest.mark.parametrize("name", ["two_body.xml", "ant.xml"])
def test_speed_maps_are_the_engines_velocities_along_mujocos_motion(name):
    """T(q) v equals each engine's own velocity of the configuration MuJoCo moves along v (central differences).

    The engine's velocity of the motion is ``g(t) = N (q_e(t) - q_e(0))`` (Drake: ``N`` its map from coordinate rates
    to velocities at ``q_e(0)``) or ``log(q_e(0)^-1 q_e(t))`` (Pinocchio's ``difference``), differenced at ``+-h``.
    Its error is the central difference's, ``h^2/6 |g3| + eps/h |g|`` (``g3`` the third derivative;
    :func:`relacc.core.tolerances.central_difference_bound`), ``|g3|`` measured by the five-point third difference
    of the same ``g`` at a coarser ``H = 1e-3`` (its own truncation ``H^2 |g5| / 4`` is negligible there), doubled
    for that estimate's error. The engine's coordinates are not MuJoCo's (Drake's balls are roll-pitch-yaw angles,
    whose third derivative grows as the pitch nears +-pi/2): a bound from ``|v|^3`` alone held only for lucky states
    (it failed 4 of 29 seeds of the states compare draws)."""
    import mujoco
    import numpy as np
    import pinocchio as pin

    from relacc.core.tolerances import central_difference_bound
    from relacc.engines import load
    from relacc.reading import read
    from relacc.validation.robots.tree import TreeRobot

    path = models_dir() / name if name == "two_body.xml" else gym_assets() / name
    reference = load("mujoco", path)  # MuJoCo moves the configuration; relacc's reading orders it as MuJoCo does
    engines = [load("pinocchio", path, reference.reference), load("drake", path, reference.reference)]
    states, h, H = TreeRobot(read(path)).states(4, seed=11), 1e-5, 1e-3
    m = reference.model

    def moved(q, v, t):
        x = q.copy()
        mujoco.mj_integratePos(m, x, v, t)
        return x

    for q, v in zip(states.q[1:], states.u[1:]):
        for robot in engines:
            T, _ = robot.speed_map(q, v)
            expected = T[0] @ v[robot.dofs]
            q0 = robot.engine_q(q)[0]
            if robot.engine == "pinocchio":
                def g(t, robot=robot, q0=q0, q=q, v=v):
                    return pin.difference(robot.model, q0, robot.engine_q(moved(q, v, t))[0])
            else:
                robot.plant.SetPositions(robot.context, q0)

                def g(t, robot=robot, q0=q0, q=q, v=v):
                    return robot.plant.MapQDotToVelocity(robot.context, robot.engine_q(moved(q, v, t))[0] - q0)
            measured = (g(h) - g(-h)) / (2 * h)
            third = np.abs(g(2 * H) - 2 * g(H) + 2 * g(-H) - g(-2 * H)).max() / (2 * H**3)
            bound = central_difference_bound(h, 2 * third, np.abs(q0).max() + 1)
            assert np.abs(measured - expected).max() <= bound, (robot.engine, np.abs(measured - expected).max(), bound)
