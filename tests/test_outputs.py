"""No input file is ever an output: ``--out`` that resolves to an input (the same path, a symbolic link to it, or
a hard link) is refused before any work, in every command, and the input stays byte for byte."""

import os
import shutil
from pathlib import Path

import pytest

from relacc import files
from relacc.cli import main
from relacc.errors import InputError
from tests.cli import one_line, run_relacc

ROOT = Path(__file__).resolve().parents[1]
BALL = """<mujoco model="ball"><worldbody><body name="bob" pos="0 0 1"><joint name="j" type="ball"/>
<geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05"/></body></worldbody></mujoco>
"""


@pytest.fixture
def model(tmp_path):
    path = tmp_path / "ball.xml"
    path.write_text(BALL)
    return path


def _refused(capsys, argv, kept: Path, before: bytes):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "an input of this command" in err[0], err
    assert kept.read_bytes() == before


@pytest.mark.parametrize("how", ["same", "relative", "symlink", "hardlink"])
def test_compare_out_is_never_the_model(tmp_path, model, capsys, monkeypatch, how):
    before = model.read_bytes()
    out = {"same": str(model), "relative": "./ball.xml", "symlink": str(tmp_path / "page.html"),
           "hardlink": str(tmp_path / "hard.html")}[how]
    if how == "symlink":
        os.symlink(model, out)
    if how == "hardlink":
        os.link(model, out)
    monkeypatch.chdir(tmp_path)
    _refused(capsys, ["compare", str(model), "--out", out, "--states", "1"], model, before)


def test_compare_out_is_never_a_file_of_the_directory_given(tmp_path, model, capsys):
    other = tmp_path / "sub" / "other.xml"
    other.parent.mkdir()
    other.write_text(BALL)
    before = other.read_bytes()
    _refused(capsys, ["compare", str(tmp_path), "--out", str(other), "--states", "1"], other, before)


def test_report_out_is_never_the_model(tmp_path, model, capsys):
    _refused(capsys, ["report", "--model", str(model), "--out", str(model), "--quick"], model, model.read_bytes())


def test_fixtures_never_rewrites_its_source(tmp_path, capsys):
    """``fixtures --model DIR/two_body.toml --out DIR`` would replace the source TOML (and the engine files made from
    it) with the changed chain's: refused, every file of DIR unchanged."""
    for name in ("two_body.toml", "two_body.xml", "two_body_euler.xml", "two_body_euler.urdf"):
        shutil.copy(ROOT / "models" / name, tmp_path / name)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    _refused(capsys, ["fixtures", "--model", str(tmp_path / "two_body.toml"), "--out", str(tmp_path), "--m2", "3"],
             tmp_path / "two_body.toml", before["two_body.toml"])
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


def test_every_writer_refuses_an_input(tmp_path):
    """The writers themselves check (the last guard, whatever a command forgot to check first)."""
    kept = tmp_path / "model.xml"
    kept.write_text("x")
    with files.inputs([kept]):
        for write in (lambda: files.write_text(kept, "y"), lambda: files.replace_all({kept: "y"}),
                      lambda: files.check_output_file(tmp_path / "." / "model.xml"),
                      lambda: files.check_new_directory(tmp_path, names=["model.xml"])):
            with pytest.raises(InputError, match="an input of this command"):
                write()
        with files.streams([tmp_path / "other.csv"]) as handles:  # another file is fine
            handles[tmp_path / "other.csv"].write("1\n")
    assert kept.read_text() == "x"
    files.write_text(kept, "y")  # outside the block it is an ordinary file
    assert kept.read_text() == "y"


@pytest.mark.slow
@pytest.mark.parametrize("argv", [["compare", "MODEL", "--out", ""], ["simulate", "tumbling", "--out", ""],
                                  ["fixtures", "--out", ""], ["report", "--out", ""]])
def test_an_empty_out_is_refused(tmp_path, argv):
    argv = [str(ROOT / "models" / "two_body.xml") if a == "MODEL" else a for a in argv]
    assert "--out" in one_line(run_relacc(*argv, cwd=tmp_path))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_compare_out_creates_its_parents(tmp_path):
    page = tmp_path / "missing" / "dir" / "page.html"
    out = run_relacc("compare", str(ROOT / "models" / "two_body.xml"), "--states", "2", "--engines", "drake",
                  "--out", str(page), cwd=tmp_path)
    assert out.returncode in (0, 1), out.stderr
    assert page.is_file() and "relacc compare" in out.stdout


@pytest.mark.slow
def test_fixtures_refuses_an_empty_name(tmp_path):
    assert "--name" in one_line(run_relacc("fixtures", "--out", str(tmp_path / "x"), "--name", "", cwd=tmp_path))
    assert not (tmp_path / "x").exists()


HOST = """<mujoco model="host"><include file="frag.xml"/></mujoco>
"""
FRAG = """<mujoco><worldbody><body name="bob" pos="0 0 1"><joint name="j" type="ball"/>
<geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05"/></body></worldbody></mujoco>
"""
TET = "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
MESHED = """<mujoco model="meshed"><compiler meshdir="assets"/>
<asset><mesh name="tet" file="tet.obj"/></asset>
<worldbody><body name="bob" pos="0 0 1"><joint name="j" type="ball"/><geom type="mesh" mesh="tet"/>
</body></worldbody></mujoco>
"""
URDF_WITH_MESH = """<robot name="r">
  <link name="base"/>
  <link name="arm"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
  </inertial><visual><geometry><mesh filename="package://robot_description/meshes/arm.stl"/></geometry></visual></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


@pytest.mark.parametrize("command", [["compare"], ["report", "--quick", "--model"]])
def test_an_included_file_is_an_input(tmp_path, capsys, command):
    """Issue 50 item 2: ``compare host.xml --out frag.xml`` replaced frag.xml, which host.xml includes, with HTML
    (``report --model`` too). Every file the reading opens is an input: refused, one line, frag.xml byte for byte."""
    (tmp_path / "host.xml").write_text(HOST)
    (tmp_path / "frag.xml").write_text(FRAG)
    before = (tmp_path / "frag.xml").read_bytes()
    argv = command + [str(tmp_path / "host.xml"), "--out", str(tmp_path / "frag.xml")]
    _refused(capsys, argv + (["--states", "1"] if command == ["compare"] else []), tmp_path / "frag.xml", before)


def test_a_mesh_the_model_uses_is_an_input(tmp_path, capsys):
    """Issue 50 item 2: ``--out assets/tet.obj`` for a mesh the model reads through ``<compiler meshdir>``."""
    (tmp_path / "assets").mkdir()
    (tmp_path / "assets" / "tet.obj").write_text(TET)
    (tmp_path / "meshed.xml").write_text(MESHED)
    mesh = tmp_path / "assets" / "tet.obj"
    _refused(capsys, ["compare", str(tmp_path / "meshed.xml"), "--out", str(mesh), "--states", "1"], mesh, TET.encode())


def test_a_urdfs_package_target_is_an_input(tmp_path, capsys):
    """Issue 50 item 2: a URDF's ``package://`` mesh, found in the package directory above the URDF (ROS's layout)."""
    pkg = tmp_path / "robot_description"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "meshes").mkdir()
    (pkg / "meshes" / "arm.stl").write_bytes(b"solid arm\nendsolid arm\n")
    (pkg / "urdf" / "r.urdf").write_text(URDF_WITH_MESH)
    mesh = pkg / "meshes" / "arm.stl"
    _refused(capsys, ["compare", str(pkg / "urdf" / "r.urdf"), "--out", str(mesh), "--states", "1"], mesh,
             mesh.read_bytes())
