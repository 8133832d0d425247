"""Model fixtures: generated files up to date, engines read the TOML's values, bad files named."""

import shutil

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from relacc import fixtures
from relacc.core.rotations import matrix_from_quaternion
from relacc.core.tolerances import EPS, MUJOCO_EIG_EPS
from relacc.errors import FixtureError


def test_checked_in_model_files_match_the_generator(fixture):
    """models/*.xml and *.urdf are exactly what `relacc fixtures` writes from the TOML."""
    assert fixtures.write(fixture, check=True) == []


def test_generator_writes_identical_files_twice(fixture, tmp_path):
    """Regenerating into a fresh directory reproduces the checked-in files byte for byte."""
    src = tmp_path / "two_body.toml"
    shutil.copy(fixture.source, src)
    copy = fixtures.load(src)
    assert sorted(fixtures.write(copy)) == sorted(fixtures.MODEL_FILES)
    for name in fixtures.MODEL_FILES:
        assert (tmp_path / name).read_text() == fixture.path(name).read_text()


def _mujoco_inertia(model, body):
    """Full inertia tensor about the mass center in body components, from MuJoCo's principal form."""
    R = matrix_from_quaternion(model.body_iquat[body])
    return R @ np.diag(model.body_inertia[body]) @ R.T


@pytest.mark.parametrize("filename", ["two_body.xml", "two_body_euler.xml"])
def test_mujoco_reads_the_toml_masses_and_inertias(fixture, filename):
    """MuJoCo's masses, mass centers and inertia tensors equal the TOML's (to rounding)."""
    m = mujoco.MjModel.from_xml_path(str(fixture.path(filename)))
    c = fixture.chain
    for name, mass, com, inertia in (("B1", c.m1, c.r1, c.I1), ("B2", c.m2, c.r2, c.I2)):
        b = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, name)
        assert m.body_mass[b] == pytest.approx(mass, rel=1e-15)
        # read as written (a decimal's rounding); the tensor rebuilt from MuJoCo's principal axes: its eigen-solver's
        # stopping threshold
        assert np.allclose(m.body_ipos[b], com, rtol=0, atol=4 * EPS * np.abs(com).max())
        assert np.allclose(_mujoco_inertia(m, b), inertia, rtol=0, atol=MUJOCO_EIG_EPS)


def test_pinocchio_reads_the_toml_masses_and_inertias(fixture):
    """Pinocchio's inertias from the MJCF and from the URDF equal the TOML's."""
    c = fixture.chain
    mj = pin.buildModelFromMJCF(str(fixture.path("two_body.xml")))
    urdf = pin.buildModelFromUrdf(str(fixture.path("two_body_euler.urdf")))
    for model in (mj, urdf):
        for name, mass, com, inertia in (("B1", c.m1, c.r1, c.I1), ("B2", c.m2, c.r2, c.I2)):
            frame = model.frames[model.getFrameId(name)]
            inert = model.inertias[frame.parentJoint]
            assert inert.mass == pytest.approx(mass, rel=1e-15)
            # read as written; the tensor turned from the file's frame: a few roundings of its largest entry
            assert np.allclose(inert.lever, com, rtol=0, atol=4 * EPS * np.abs(com).max())
            assert np.allclose(inert.inertia, inertia, rtol=0, atol=8 * EPS * np.abs(inertia).max())


def test_every_mjcf_element_is_named(fixture):
    """Bodies, joints and sites all carry names (Pinocchio's MJCF loader needs them)."""
    for filename in ("two_body.xml", "two_body_euler.xml"):
        m = mujoco.MjModel.from_xml_path(str(fixture.path(filename)))
        for kind, count in ((mujoco.mjtObj.mjOBJ_BODY, m.nbody), (mujoco.mjtObj.mjOBJ_JOINT, m.njnt),
                            (mujoco.mjtObj.mjOBJ_SITE, m.nsite)):
            names = [mujoco.mj_id2name(m, kind, i) for i in range(count)]
            assert all(names[1 if kind == mujoco.mjtObj.mjOBJ_BODY else 0:]), f"{filename}: unnamed {kind}"


def _write(tmp_path, text):
    path = tmp_path / "chain.toml"
    path.write_text(text)
    return path


GOOD = """name = "x"
[B1]
mass = 2.0
r1 = [0.0, 0.0, 0.0]
inertia = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
[B2]
mass = 1.0
q2 = [0.1, 0.2, 0.3]
r2 = [0.3, 0.2, 0.1]
inertia = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
"""


@pytest.mark.parametrize(
    "text,match",
    [
        (GOOD.replace("mass = 2.0", "mass = -2.0"), r"line 3, field \[B1\]\.mass: .*positive"),
        (GOOD.replace("q2 = [0.1, 0.2, 0.3]", "q2 = [0.1, 0.2]"), r"line 8, field \[B2\]\.q2: .*3 numbers"),
        (GOOD.replace("r2 = [0.3, 0.2, 0.1]\n", ""), r"missing field \[B2\]\.r2"),
        (GOOD.replace("[B1]", "[B1"), r"not valid TOML.*line 2"),
        (GOOD.replace("[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n[B2]",
                      "[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]]\n[B2]"),
         r"line 5.*not physically realizable"),
        (GOOD.replace('name = "x"', "name = 3"), r"name must be a non-empty string"),
    ],
)
def test_malformed_model_files_name_path_line_and_field(tmp_path, text, match):
    """A bad TOML raises FixtureError naming the file, the line and the field."""
    path = _write(tmp_path, text)
    with pytest.raises(FixtureError, match=match) as info:
        fixtures.load(path)
    assert str(path) in str(info.value)


def test_missing_model_file_is_a_fixture_error(tmp_path):
    """A path that does not exist raises FixtureError with the path."""
    with pytest.raises(FixtureError, match="no such file"):
        fixtures.load(tmp_path / "nope.toml")


def test_stale_engine_files_are_refused(fixture, tmp_path):
    """Engine files made from another version of a chain are refused (one line: run relacc fixtures)."""
    from relacc.engines import load_engine

    src = tmp_path / "two_body.toml"
    shutil.copy(fixture.source, src)
    fixtures.write(fixtures.load(src))
    src.write_text(src.read_text().replace("mass = 0.8", "mass = 0.9"))
    changed = fixtures.load(src)
    assert sorted(changed.stale()) == sorted(fixtures.MODEL_FILES)
    for engine in ("pinocchio", "mujoco", "drake"):
        with pytest.raises(FixtureError, match=r"made from another version of this chain; run `relacc fixtures"):
            load_engine(engine, changed)
    fixtures.write(changed)
    assert changed.stale() == [] and load_engine("mujoco", changed).routes["quaternion"].model.body_mass[2] == 0.9


def test_a_set_of_engine_files_is_written_all_or_nothing(fixture, tmp_path, monkeypatch):
    """When one engine file cannot be written, none of the set is replaced."""
    import os

    from relacc.errors import OutputError

    src = tmp_path / "two_body.toml"
    shutil.copy(fixture.source, src)
    fixtures.write(fixtures.load(src))
    before = {n: (tmp_path / n).read_bytes() for n in fixtures.MODEL_FILES}
    src.write_text(src.read_text().replace("mass = 0.8", "mass = 0.9"))
    real = os.replace

    def fail_on_urdf(a, b):
        if str(b).endswith(".urdf"):
            raise OSError(13, "Permission denied")
        return real(a, b)

    monkeypatch.setattr(os, "replace", fail_on_urdf)
    with pytest.raises(OutputError, match="urdf: cannot write the file"):
        fixtures.write(fixtures.load(src))
    assert {n: (tmp_path / n).read_bytes() for n in fixtures.MODEL_FILES} == before
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []


def test_table_headers_with_comments_still_name_the_line(tmp_path):
    """An error's line is found when table headers carry trailing comments."""
    path = _write(tmp_path, GOOD.replace("[B2]", "[B2]   # the second body").replace("mass = 1.0", "mass = -1.0"))
    with pytest.raises(FixtureError, match=r"line 7, field \[B2\]\.mass"):
        fixtures.load(path)


@pytest.mark.parametrize("edit,match", [
    (("mass = 2.0", "mas = 2.0"), r"line 3, field \[B1\]\.mas: unknown key; accepted: mass, r1, inertia"),
    (("mass = 2.0", "mass = true"), r"field \[B1\]\.mass: mass must be a number"),
    (("q2 = [0.1, 0.2, 0.3]", "q2 = [0.1, true, 0.3]"), r"field \[B2\]\.q2: .*entry 1"),
    (('name = "x"', 'name = "x"\nextra = 1'), r"unknown top-level keys \['extra'\]"),
])
def test_unknown_keys_and_booleans_are_refused(tmp_path, edit, match):
    """Typos like `mas = 3.0` and booleans where numbers belong are errors naming the line and the field."""
    with pytest.raises(FixtureError, match=match):
        fixtures.load(_write(tmp_path, GOOD.replace(*edit)))
