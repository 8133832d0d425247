"""A mesh geom's mass properties are relacc's own (issue 53 item 6, :mod:`relacc.reading.mesh`).

Each mode of MuJoCo's mesh ``inertia`` is held to a closed form where one exists and to MuJoCo's compiled model, on
minimal meshes written here: an L-shaped prism (not convex: ``legacy`` overcounts it, ``convex`` fills it) and an OBJ
file of two cubes (MuJoCo reads only its first object, mujoco#911; Drake computes the exact volume of both).
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from relacc.core.tolerances import EPS, MUJOCO_EIG_EPS, ROUNDING_FACTOR, VERTEX_ROUNDING
from relacc.errors import ModelError
from relacc.reading import read

# the L's outline in the xy-plane (counterclockwise), extruded from z = 0 to z = H
L_OUTLINE = [(0.0, 0.0), (0.3, 0.0), (0.3, 0.1), (0.1, 0.1), (0.1, 0.2), (0.0, 0.2)]
H = 0.05


@pytest.fixture(autouse=True)
def _in_a_scratch_directory(tmp_path, monkeypatch):
    """MuJoCo, called directly here as the reference, appends its warnings to MUJOCO_LOG.TXT in the working
    directory: that directory is the test's own."""
    monkeypatch.chdir(tmp_path)


def l_prism_stl(path):
    """A binary STL of the L prism, every face turned outwards (the caps fanned from a vertex where the fan stays
    inside the L: from (0.1, 0.1), the reflex corner)."""
    bottom = [(x, y, 0.0) for x, y in L_OUTLINE]
    top = [(x, y, H) for x, y in L_OUTLINE]
    n = len(L_OUTLINE)
    tris = []
    k = 3  # the reflex corner
    for i in range(n):
        a, b = (k + 1 + i) % n, (k + 2 + i) % n
        if k in (a, b):
            continue
        tris.append((top[k], top[a], top[b]))
        tris.append((bottom[k], bottom[b], bottom[a]))
    for i in range(n):
        j = (i + 1) % n
        tris.append((bottom[i], bottom[j], top[j]))
        tris.append((bottom[i], top[j], top[i]))
    data = bytearray(80) + struct.pack("<I", len(tris))
    for t in tris:
        data += struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v) for v in t) + b"\0\0"
    path.write_bytes(bytes(data))


def box(lo, hi, rho):
    """``(mass, centre, inertia about it)`` of a solid box of density ``rho`` (kg/m^3) from corner ``lo`` to ``hi``."""
    lo, hi = np.asarray(lo), np.asarray(hi)
    d = hi - lo
    m = rho * d.prod()
    return m, (lo + hi) / 2, m / 12 * np.diag([d[1] ** 2 + d[2] ** 2, d[0] ** 2 + d[2] ** 2, d[0] ** 2 + d[1] ** 2])


def combined(parts):
    m = sum(p[0] for p in parts)
    c = sum(p[0] * p[1] for p in parts) / m
    inertia = sum(p[2] + p[0] * ((p[1] - c) @ (p[1] - c) * np.eye(3) - np.outer(p[1] - c, p[1] - c)) for p in parts)
    return m, c, inertia


def model(tmp_path, mesh_file, mode):
    path = tmp_path / f"{mode}.xml"
    path.write_text(f'<mujoco><asset><mesh name="m" file="{mesh_file}" inertia="{mode}"/></asset><worldbody>'
                    '<body name="a"><joint name="ja" axis="0 1 0"/><geom type="mesh" mesh="m" density="1000"/>'
                    '</body></worldbody></mujoco>')
    return path


def mujoco_body(path):
    import mujoco  # a declared dependency: never skipped

    from relacc.core.rotations import matrix_from_quaternion

    m = mujoco.MjModel.from_xml_path(str(path))
    R = matrix_from_quaternion(m.body_iquat[1])
    return m.body_mass[1], m.body_ipos[1], R @ np.diag(m.body_inertia[1]) @ R.T


@pytest.mark.parametrize("mode", ["legacy", "exact", "convex", "shell"])
def test_each_mode_is_mujoco_s(tmp_path, mode):
    """relacc's reading of the L prism in each mode against MuJoCo's compiled body: mass and mass centre to c eps;
    the inertia to MuJoCo's eigen tolerance (twice MUJOCO_EIG_EPS times the density: mjuu_eig3 stops at an absolute
    off-diagonal of 1e-12 on the unit-density tensor). The exact mode is also the two boxes' closed form (to the
    single precision vertices' rounding); legacy overcounts the L, and convex fills its notch, so both weigh more."""
    l_prism_stl(tmp_path / "l.stl")
    path = model(tmp_path, "l.stl", mode)
    body = read(path).tree.bodies[0]
    assert read(path).taken == {}
    mass, com, inertia = mujoco_body(path)
    np.testing.assert_allclose(body.mass, mass, rtol=0, atol=ROUNDING_FACTOR * EPS * mass)
    np.testing.assert_allclose(body.com, com, rtol=0, atol=ROUNDING_FACTOR * EPS * 0.3)  # 0.3 m: the mesh's extent
    np.testing.assert_allclose(body.inertia, inertia, rtol=0, atol=2 * MUJOCO_EIG_EPS * 1000.0)
    exact = combined([box((0, 0, 0), (0.3, 0.1, H), 1000.0), box((0, 0.1, 0), (0.1, 0.2, H), 1000.0)])
    if mode == "exact":
        # the vertices are single precision (0.3f, 0.1f): their relative rounding, 3e-8, bounds the closed form's
        np.testing.assert_allclose(body.mass, exact[0], rtol=0, atol=4 * VERTEX_ROUNDING * exact[0])
        np.testing.assert_allclose(body.com, exact[1], rtol=0, atol=4 * VERTEX_ROUNDING * 0.3)
        np.testing.assert_allclose(body.inertia, exact[2], rtol=0, atol=8 * VERTEX_ROUNDING * np.abs(exact[2]).max())
    elif mode in ("legacy", "convex"):
        assert body.mass > exact[0] * 1.01


def test_an_obj_of_two_objects_is_read_whole_and_mujoco_s_reading_is_named(tmp_path):
    """Two 0.1 m cubes in one OBJ (objects "first" and "second"): relacc's exact reading is both (2 kg, the mass
    centre midway); MuJoCo's, the first cube only (1 kg at its centre), which relacc reproduces as MuJoCo's reading
    (variant mesh_obj_first_object) and ``compare`` names as the cause."""
    cube = ["v {} {} {}".format(*c) for c in
            [(0, 0, 0), (.1, 0, 0), (.1, .1, 0), (0, .1, 0), (0, 0, .1), (.1, 0, .1), (.1, .1, .1), (0, .1, .1)]]
    faces = ["1 4 3 2", "5 6 7 8", "1 2 6 5", "2 3 7 6", "3 4 8 7", "4 1 5 8"]
    lines = ["o first"] + cube + [f"f {f}" for f in faces] + ["o second"]
    lines += ["v {} {} {}".format(float(x) + 0.3, y, z) for x, y, z in (c.split()[1:] for c in cube)]
    lines += ["f " + " ".join(str(int(i) + 8) for i in f.split()) for f in faces]
    (tmp_path / "two.obj").write_text("\n".join(lines) + "\n")
    path = model(tmp_path, "two.obj", "exact")
    ours = read(path)
    assert ours.facts["multi_object_meshes"] == ("two.obj",)
    two = combined([box((0, 0, 0), (.1, .1, .1), 1000.0), box((.3, 0, 0), (.4, .1, .1), 1000.0)])
    body = ours.tree.bodies[0]
    np.testing.assert_allclose(body.mass, two[0], rtol=0, atol=4 * VERTEX_ROUNDING * two[0])  # 0.1f, 0.3f, 0.4f
    np.testing.assert_allclose(body.com, two[1], rtol=0, atol=4 * VERTEX_ROUNDING * 0.4)
    first = read(path, variant=frozenset(["mesh_obj_first_object"])).tree.bodies[0]
    mass, com, inertia = mujoco_body(path)
    np.testing.assert_allclose(first.mass, mass, rtol=0, atol=ROUNDING_FACTOR * EPS * mass)
    np.testing.assert_allclose(first.com, com, rtol=0, atol=ROUNDING_FACTOR * EPS * 0.4)
    np.testing.assert_allclose(mass, 1.0, rtol=0, atol=4 * VERTEX_ROUNDING)  # the first cube alone, 1 kg
    from relacc.validation.robots import compare

    result = compare(path, engines=["mujoco"], n_states=2, seed=0)
    text = " ".join(str(row) for row in result.as_json()["audit"])
    assert "mujoco#911" in text and "not explained" not in text


def test_meshes_mujoco_refuses_are_refused(tmp_path):
    """An ASCII STL (MuJoCo reads binary STL only) and ``shellinertia`` on a mesh geom (a mesh's mode is its asset's)
    are refused with the element's place, as MuJoCo's compiler refuses them."""
    (tmp_path / "a.stl").write_text("solid x\nendsolid x\n")
    with pytest.raises(ModelError, match="not a binary STL"):
        read(model(tmp_path, "a.stl", "legacy"))
    l_prism_stl(tmp_path / "l.stl")
    path = tmp_path / "shell.xml"
    path.write_text('<mujoco><asset><mesh name="m" file="l.stl"/></asset><worldbody><body name="a"><joint name="j"/>'
                    '<geom type="mesh" mesh="m" shellinertia="true"/></body></worldbody></mujoco>')
    with pytest.raises(ModelError, match="shellinertia on a mesh geom"):
        read(path)


def test_mujoco_s_mesh_inertia_is_within_its_eigen_tolerance_and_compare_agrees(tmp_path):
    """MuJoCo diagonalizes a mesh's unit-density inertia with mjuu_eig3, stopped at an absolute off-diagonal of
    MUJOCO_EIG_EPS (m^5): its inertia differs from relacc's by at most twice that times the density
    (MujocoAdapter.inertia_allowance), and ``compare`` holds MuJoCo to relacc's reading within it. A small L (scaled
    to 5 cm) of 0.5 kg: an effective density of 5.6e5 kg/m^3, where the allowance matters."""
    from relacc.engines import load
    from relacc.validation.robots import compare

    l_prism_stl(tmp_path / "l.stl")
    path = tmp_path / "small.xml"
    path.write_text('<mujoco><asset><mesh name="m" file="l.stl" scale="0.2 0.2 0.2"/></asset><worldbody>'
                    '<body name="a"><joint name="ja" axis="0 1 0"/><geom type="mesh" mesh="m" mass="0.5"/>'
                    '<body name="b" pos="0.1 0 0"><joint name="jb" axis="1 0 0"/>'
                    '<geom type="mesh" mesh="m" mass="0.5" euler="10 20 30"/></body></body></worldbody></mujoco>')
    reading = read(path)
    allowance = load("mujoco", path).inertia_allowance(reading)
    expected = 2 * 1e-12 * sum(reading.facts["mesh_density"].values())
    expected += 2 * np.sqrt(2e-12) * sum(reading.facts["mesh_inertia"].values())
    np.testing.assert_allclose(allowance, expected, rtol=1e-15, atol=0)  # a sum of four terms: its rounding
    for body in reading.tree.bodies:
        _, _, inertia = mujoco_body_named(path, body.name)
        assert np.abs(body.inertia - inertia).max() <= allowance, body.name
    result = compare(path, engines=["mujoco"], n_states=4, seed=2)
    assert result.exit_code == 0, result.as_json()["dynamics"]


def mujoco_body_named(path, name):
    import mujoco  # a declared dependency: never skipped

    from relacc.core.rotations import matrix_from_quaternion

    m = mujoco.MjModel.from_xml_path(str(path))
    i = m.body(name).id
    R = matrix_from_quaternion(m.body_iquat[i])
    return m.body_mass[i], m.body_ipos[i], R @ np.diag(m.body_inertia[i]) @ R.T


@pytest.mark.slow
def test_the_reading_imports_no_engine(tmp_path):
    """Issue 53: relacc's reading of a mesh model imports no engine (not MuJoCo, not relacc.engines), in a fresh
    process; a primitive fitted to a mesh, which relacc does not compute, is refused there with the reason, and
    read once relacc.engines has offered MuJoCo's computation."""
    import subprocess
    import sys

    l_prism_stl(tmp_path / "l.stl")
    mesh = model(tmp_path, "l.stl", "legacy")
    fitted = tmp_path / "fitted.xml"
    fitted.write_text('<mujoco><asset><mesh name="m" file="l.stl"/></asset><worldbody><body name="a">'
                      '<joint name="j"/><geom type="box" mesh="m"/></body></worldbody></mujoco>')
    code = f"""
import sys
from relacc.reading import read
from relacc.errors import ModelError
read({str(mesh)!r})
assert not any(m == "mujoco" or m.startswith(("relacc.engines", "pinocchio", "pydrake")) for m in sys.modules), \\
    sorted(m for m in sys.modules if "engines" in m or m == "mujoco")
try:
    read({str(fitted)!r})
except ModelError as exc:
    assert "import relacc.engines" in str(exc), exc
else:
    raise AssertionError("a fitted primitive was read without an engine")
import relacc.engines
assert read({str(fitted)!r}).taken
print("ok")
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert done.stdout.strip() == "ok", done.stderr


@pytest.mark.slow
def test_meshes_of_other_people_s_models_are_mujoco_s(tmp_path_factory, request):
    """Issue 53 item 6 on meshes nobody here wrote: 25 mesh files drawn (seed 7) from the pinned wheels of
    scripts/corpus.py, each in MuJoCo's four modes (scripts/meshes.py runs all of them): where both compute it,
    relacc's mass and mass centre are MuJoCo's to c eps per face summed (both sum the faces' pyramids in float64, in
    the same order), and its inertia within MuJoCo's eigen tolerance (MujocoAdapter.inertia_allowance: 2 eps_eig
    times the density, 1000, and 2 sqrt(2 eps_eig) of the largest entry)."""
    import importlib.util

    script = Path(__file__).resolve().parents[1] / "scripts" / "meshes.py"
    spec = importlib.util.spec_from_file_location("meshes", script)
    meshes = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(meshes)
    found = meshes.files(Path(request.config.cache.mkdir("relacc-corpus")))
    rng = np.random.default_rng(7)
    compared = 0
    for path in [found[i] for i in sorted(rng.choice(len(found), 25, replace=False))]:
        for mode in meshes.MODES:
            row = meshes.compare(path, mode)
            if "mass" not in row:
                assert row["mujoco"] is not None, (path.name, mode, row)  # relacc refuses only what MuJoCo does
                continue
            compared += 1
            allowed = ROUNDING_FACTOR * EPS * max(row["faces"], 1)
            assert row["mass"] <= allowed and row["com"] <= allowed, (path.name, mode, row)
            eig = 2 * MUJOCO_EIG_EPS * 1000.0 + 2 * np.sqrt(2 * MUJOCO_EIG_EPS) * row["inertia_max"]
            assert row["inertia_abs"] <= eig, (path.name, mode, row)
    assert compared >= 80


def test_an_inconsistently_turned_mesh_is_refused_in_the_exact_mode_only(tmp_path):
    """MuJoCo's compiler refuses inertia="exact" for a mesh whose neighbouring faces are turned differently (the
    signed volumes would mean nothing), and computes the other modes; relacc's reading does the same, naming two
    vertices of the edge."""
    l_prism_stl(tmp_path / "l.stl")
    data = bytearray((tmp_path / "l.stl").read_bytes())
    first = 84 + 12  # the first triangle's corners: swap the second and third
    data[first + 12:first + 24], data[first + 24:first + 36] = data[first + 24:first + 36], data[first + 12:first + 24]
    (tmp_path / "l.stl").write_bytes(bytes(data))
    with pytest.raises(ModelError, match="not turned consistently"):
        read(model(tmp_path, "l.stl", "exact"))
    import mujoco  # a declared dependency: never skipped
    with pytest.raises(ValueError, match="inconsistent orientation"):
        mujoco.MjModel.from_xml_path(str(model(tmp_path, "l.stl", "exact")))
    read(model(tmp_path, "l.stl", "legacy"))  # the other modes are read
