"""A mesh's volume (or area), mass centre and inertia, computed by relacc as MuJoCo's compiler specifies them.

MuJoCo's XML reference gives a mesh asset an ``inertia`` mode (``legacy``, the default, ``exact``, ``convex``,
``shell``); its compiler (``user_mesh.cc``, ``mjCMesh::Process``) computes, after the asset's ``refpos``, ``refquat``
and ``scale``:

* the *face centroid* ``c_f``: the area-weighted mean of the triangles' centroids;
* the volume and mass centre as a sum of pyramids from ``c_f`` over each triangle (``exact``: signed volumes, a closed
  surface's; ``legacy``: each pyramid's volume taken positive, which overcounts a non-convex mesh; ``convex``: the
  triangles of the convex hull), or for ``shell`` the area and its centroid (each triangle's weight its area,
  its centroid taken 3/4 of the way from ``c_f``);
* the inertia about that mass centre as the sum of each triangle's tetrahedron with its apex at the mass centre
  (``shell``: each triangle's second moments), the volume summed again over the same tetrahedra (for ``legacy``
  from the mass centre, not ``c_f``: the two sums differ, and the second is the one the geom's mass uses).

A mesh geom of density ``rho`` then has mass ``rho V`` (or its ``mass``) and inertia ``(mass / V) I``, in the mesh's
frame, which the geom's pose places. This module computes that in float64 from the file's vertices (binary STL,
OBJ, MuJoCo's MSH), so that relacc's reading of a mesh body is its own, and MuJoCo's is judged like any other reading.
Meshes are read with trimesh (STL, OBJ); ``scipy.spatial.ConvexHull`` (Qhull, as MuJoCo) gives the hull.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from relacc.core.tolerances import MJMINVAL
from relacc.errors import ModelError

MODES = ("legacy", "exact", "convex", "shell")
"""A mesh asset's ``inertia`` modes (MuJoCo's default: ``legacy``)."""

DRAKE_MIN_VOLUME = 1e-14
"""m^3: the smallest volume Drake's ``CalcSpatialInertia`` takes as a mesh's (below it, or for an inertia no rigid
body has, Drake falls back to the convex hull, :func:`exact_or_hull`)."""


@dataclass(frozen=True)
class MeshMass:
    """A mesh's mass properties per unit density, in the mesh asset's frame (after ``refpos``, ``refquat``,
    ``scale``): ``measure`` (m^3, or m^2 for a shell), ``com`` ``(3,)`` (m) and ``inertia`` ``(3, 3)`` about it per
    unit density (m^5, or m^4 for a shell)."""

    measure: float
    com: np.ndarray
    inertia: np.ndarray


def load(path: Path, place: str) -> tuple[np.ndarray, np.ndarray]:
    """``(vertices (n, 3) float64 of the file's float32 values, faces (m, 3) int)`` of a mesh file: binary STL, OBJ
    or MSH, as MuJoCo reads them (vertex coordinates are single precision in all three).

    Raises:
        ModelError: another format, an ASCII STL (MuJoCo reads binary STL only), or a file that does not parse.
    """
    suffix = path.suffix.lower()
    data = path.read_bytes()
    if suffix == ".msh":
        header = np.frombuffer(data[:16], dtype="<i4") if len(data) >= 16 else np.zeros(0, dtype="<i4")
        if len(header) < 4:
            raise ModelError(f"{place}: {path.name}: an MSH file shorter than its header")
        nv, nn, nt, nf = (int(x) for x in header)
        if 16 + 4 * (3 * nv + 3 * nn + 2 * nt + 3 * nf) != len(data) or nv < 4:
            raise ModelError(f"{place}: {path.name}: an MSH file whose size does not match its header")
        floats = np.frombuffer(data[16:16 + 12 * nv], dtype="<f4").reshape(nv, 3)
        start = 16 + 4 * (3 * nv + 3 * nn + 2 * nt)
        faces = np.frombuffer(data[start:start + 12 * nf], dtype="<i4").reshape(nf, 3)
        return floats.astype(np.float64), faces.astype(np.int64)
    if suffix == ".stl":
        count = int(np.frombuffer(data[80:84], dtype="<u4")[0]) if len(data) >= 84 else -1
        if count < 0 or len(data) != 84 + 50 * count:
            raise ModelError(f"{place}: {path.name}: not a binary STL (MuJoCo reads binary STL only)")
        records = np.frombuffer(data[84:], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
        corners = records["v"].reshape(-1, 3).astype(np.float64)
        # one vertex per position, as MuJoCo's STL reader keeps them (faces then share their edges' vertices)
        vertices, index = np.unique(corners, axis=0, return_inverse=True)
        return vertices, index.reshape(-1, 3).astype(np.int64)
    if suffix == ".obj":
        vertices, objects = read_obj(data, path.name, place)
        return vertices, np.concatenate(objects) if objects else np.zeros((0, 3), dtype=np.int64)
    raise ModelError(f"{place}: {path.name}: a mesh file is .stl, .obj or .msh")


def cached(path: Path, place: str, quads: bool = True) -> tuple[np.ndarray, list[np.ndarray]]:
    """``(vertices (n, 3), [faces (m_k, 3) of each object])`` of a mesh file (one object but in an OBJ), read once per
    file version (its size and modification time); ``quads``: as :func:`triangulate`."""
    stat = path.stat()
    return _cached(path, stat.st_mtime_ns, stat.st_size, place, quads)


@functools.lru_cache(maxsize=64)
def _cached(path: Path, mtime_ns: int, size: int, place: str, quads: bool) -> tuple[np.ndarray, list[np.ndarray]]:
    if path.suffix.lower() == ".obj":
        return read_obj(path.read_bytes(), path.name, place, quads)
    vertices, faces = load(path, place)
    return vertices, [faces]


def read_obj(data: bytes, name: str, place: str, quads: bool = True) -> tuple[np.ndarray, list[np.ndarray]]:
    """``(vertices (n, 3), [faces (m_k, 3) of each object])`` of an OBJ file: its ``v`` lines (single precision, as
    MuJoCo keeps them; double with ``quads=False``, Drake's) and its ``f`` lines (1-based or negative indices,
    ``v/vt/vn`` forms; a polygon cut into triangles by :func:`triangulate`), an object starting at each ``o`` or
    ``g`` line that follows faces.

    Written here rather than taken from trimesh because the reading must keep the file's order and where each object
    starts: MuJoCo reads the first object's faces only (mujoco#911), and relacc names that reading of a multi-object
    file (:data:`OBJ_FIRST_OBJECT`), which trimesh's loader, regrouping faces by object and material, cannot show.

    Raises:
        ModelError: a line that does not parse, or a face naming a vertex that is not there.
    """
    vertices: list[list[float]] = []
    objects: list[list[list[int]]] = [[]]
    for number, raw in enumerate(data.decode("utf-8", errors="replace").splitlines(), start=1):
        fields = raw.split()
        if not fields:
            continue
        try:
            if fields[0] == "v":
                vertices.append([float(x) for x in fields[1:4]])
            elif fields[0] == "f":
                ids = [int(f.split("/")[0]) for f in fields[1:]]
                ids = [i - 1 if i > 0 else len(vertices) + i for i in ids]
                if len(ids) < 3 or min(ids) < 0 or max(ids) >= len(vertices):
                    raise ValueError("a face with fewer than 3 vertices or naming one not there")
                objects[-1].append(ids)
            elif fields[0] in ("o", "g") and objects[-1]:
                objects.append([])
        except ValueError as exc:
            raise ModelError(f"{place}: {name}:{number}: {exc}") from None
    vs = np.asarray(vertices, dtype=np.float32 if quads else np.float64).reshape(-1, 3)
    out = []
    for polygons in objects:
        if polygons:
            triangles = [t for poly in polygons for t in (
                [poly] if len(poly) == 3 else triangulate(poly, vs, quads))]
            out.append(np.asarray(triangles, dtype=np.int64).reshape(-1, 3))
    return vs.astype(np.float64), out


def triangulate(polygon: list[int], v: np.ndarray, quads: bool = True) -> list[list[int]]:
    """The triangles of one OBJ polygon of more than three vertices, as tinyobjloader (the OBJ reader MuJoCo and
    Drake share, its default triangulation, in single precision) cuts it: a quad along its shorter diagonal, a larger
    polygon by clipping ears in the plane of the two axes its first corner spans most, from its first vertex on.

    The OBJ format makes a face a planar polygon; one that is not planar has no one surface, and each triangulation
    gives another volume (robosuite's GR1 meshes: 538 of 903 quads cut along the other diagonal than a fan from the
    first vertex, 0.2 % of the mass). relacc cuts them as the engines' shared reader does, so that a difference in a
    mesh's mass is not a choice of diagonals; ``v``: the file's vertices ``(n, 3)``, float32. ``quads=False``: Drake's
    tinyobjloader (1.51): vertices in double precision, and a quad clipped like any polygon, as tinyobjloader did before
    it cut quads along the shorter diagonal (measured: robosuite's omron base to 1e-15 in Drake's reading)."""
    f32 = v.dtype.type
    eps = np.finfo(v.dtype).eps
    n = len(polygon)
    if n == 4 and quads:  # a quad: cut along its shorter diagonal (0-2 only when strictly shorter)
        d02, d13 = v[polygon[2]] - v[polygon[0]], v[polygon[3]] - v[polygon[1]]
        if (d02 * d02).sum(dtype=v.dtype) < (d13 * d13).sum(dtype=v.dtype):
            return [[polygon[0], polygon[1], polygon[2]], [polygon[0], polygon[2], polygon[3]]]
        return [[polygon[0], polygon[1], polygon[3]], [polygon[1], polygon[2], polygon[3]]]
    axes = [1, 2]
    for k in range(n):
        v0, v1, v2 = v[polygon[k % n]], v[polygon[(k + 1) % n]], v[polygon[(k + 2) % n]]
        e0, e1 = v1 - v0, v2 - v1
        cx = abs(e0[1] * e1[2] - e0[2] * e1[1])
        cy = abs(e0[2] * e1[0] - e0[0] * e1[2])
        cz = abs(e0[0] * e1[1] - e0[1] * e1[0])
        if cx > eps or cy > eps or cz > eps:  # a corner: the plane it spans most
            if not (cx > cy and cx > cz):
                axes[0] = 0
                if cz > cx and cz > cy:
                    axes[1] = 1
            break
    a0, a1 = axes
    remaining = list(polygon)
    guess, iterations, before = 0, n, n
    out = []
    while len(remaining) > 3 and iterations > 0:
        m = len(remaining)
        if guess >= m:
            guess -= m
        if before != m:
            before, iterations = m, m
        else:
            iterations -= 1
        ind = [remaining[(guess + k) % m] for k in range(3)]
        vx = [v[i][a0] for i in ind]
        vy = [v[i][a1] for i in ind]
        cross = (vx[1] - vx[0]) * (vy[2] - vy[1]) - (vy[1] - vy[0]) * (vx[2] - vx[1])
        area = (vx[0] * vy[1] - vy[0] * vx[1]) * f32(0.5)  # tinyobjloader's test, as it is written
        if cross * area < 0:  # a reflex corner, by that test
            guess += 1
            continue
        if any(_inside(vx, vy, v[remaining[(guess + o) % m]][a0], v[remaining[(guess + o) % m]][a1])
               for o in range(3, m)):
            guess += 1
            continue
        out.append(ind)
        del remaining[(guess + 1) % m]
    if len(remaining) == 3:
        out.append(remaining)
    return out


def _inside(vx, vy, tx, ty) -> bool:
    """tinyobjloader's ``pnpoly``: whether the point ``(tx, ty)`` is inside the triangle ``(vx, vy)`` (crossings)."""
    c = False
    j = 2
    for i in range(3):
        if (vy[i] > ty) != (vy[j] > ty) and tx < (vx[j] - vx[i]) * (ty - vy[i]) / (vy[j] - vy[i]) + vx[i]:
            c = not c
        j = i
    return c


OBJ_FIRST_OBJECT = ("MuJoCo reads an OBJ file's first object (o or g) only: its faces, not the others' "
                    "(mujoco#911; the convex hull, which takes every vertex, is the file's)")
"""What MuJoCo does with a multi-object OBJ file, as relacc's reading names it (variant ``mesh_obj_first_object``)."""


def _triangles(vertices: np.ndarray, faces: np.ndarray):
    """``(normals (m, 3) unit, centroids (m, 3), areas (m,))`` of the triangles (MuJoCo's ``triangle``)."""
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    cross = np.cross(b - a, c - a)
    norm = np.linalg.norm(cross, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        normals = np.where(norm[:, None] > 0, cross / np.where(norm > 0, norm, 1.0)[:, None], 0.0)
    return normals, (a + b + c) / 3.0, norm / 2.0


def mass_properties(vertices: np.ndarray, faces: np.ndarray, mode: str, place: str) -> MeshMass:
    """A mesh's :class:`MeshMass` in ``mode`` (:data:`MODES`), as MuJoCo's compiler computes it (module docstring).

    Raises:
        ModelError: a surface or a volume below ``mjMINVAL``, or a negative volume (triangles turned inwards), as
            MuJoCo refuses them.
    """
    if mode not in MODES:
        raise ModelError(f"{place}: mesh inertia={mode!r}; MuJoCo's are {', '.join(MODES)}")
    if len(faces) == 0:  # vertices only: MuJoCo takes the convex hull's faces
        faces = hull_faces(vertices, place)
    if mode == "exact":
        _check_orientation(vertices, faces, place)
    _, centroids, areas = _triangles(vertices, faces)
    total_area = float(areas.sum())
    if total_area < MJMINVAL:
        raise ModelError(f"{place}: the mesh's surface area is too small ({total_area:.3g} m^2), as MuJoCo refuses it")
    facecen = (areas[:, None] * centroids).sum(axis=0) / total_area
    used = hull_faces(vertices, place) if mode == "convex" else faces
    normals, centroids, areas = _triangles(vertices, used)
    if mode == "shell":
        weights = areas
    else:
        weights = np.einsum("ij,ij->i", centroids - facecen, normals) * areas / 3.0
        if mode == "legacy":
            weights = np.abs(weights)
    measure = float(weights.sum())
    if measure < MJMINVAL:
        what = "volume is negative (triangles turned inwards)" if measure < 0 else \
            "volume is too small (MuJoCo suggests inertia=\"shell\")"
        raise ModelError(f"{place}: the mesh's {what}, as MuJoCo refuses it")
    com = (weights[:, None] * (0.75 * centroids + 0.25 * facecen)).sum(axis=0) / measure
    D, E, F = (vertices[used[:, k]] - com for k in range(3))
    normals, centroids, areas = _triangles(vertices - com, used)
    if mode == "shell":
        weights, C = areas, 12.0
    else:
        weights, C = np.einsum("ij,ij->i", centroids, normals) * areas / 3.0, 20.0
        if mode == "legacy":
            weights = np.abs(weights)
    P = np.zeros((3, 3))
    for j in range(3):
        for k in range(j, 3):
            P[j, k] = P[k, j] = float((weights / C * (
                2 * (D[:, j] * D[:, k] + E[:, j] * E[:, k] + F[:, j] * F[:, k])
                + D[:, j] * E[:, k] + D[:, k] * E[:, j] + D[:, j] * F[:, k] + D[:, k] * F[:, j]
                + E[:, j] * F[:, k] + E[:, k] * F[:, j])).sum())
    inertia = np.trace(P) * np.eye(3) - P
    return MeshMass(float(weights.sum()), com, inertia)


def _check_orientation(vertices: np.ndarray, faces: np.ndarray, place: str) -> None:
    """The exact mode's condition (MuJoCo's compiler refuses a mesh without it): no directed edge in two faces of area
    above ``sqrt(mjMINVAL)``, i.e. neighbouring faces turned the same way.

    Raises:
        ModelError: naming two vertices (1-based, as MuJoCo's message) of an edge two faces run the same way.
    """
    _, _, areas = _triangles(vertices, faces)
    kept = faces[areas > np.sqrt(MJMINVAL)]
    edges = np.concatenate([kept[:, [0, 1]], kept[:, [1, 2]], kept[:, [2, 0]]])
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    if (counts > 1).any():
        a, b = unique[np.argmax(counts > 1)]
        raise ModelError(f"{place}: the mesh's faces are not turned consistently (two faces run the edge from vertex "
                         f"{a + 1} to {b + 1} the same way), which inertia=\"exact\" needs, as MuJoCo's compiler "
                         "refuses it; use inertia=\"legacy\", \"convex\" or \"shell\", or fix the mesh")


def exact_or_hull(vertices: np.ndarray, faces: np.ndarray, place: str) -> MeshMass:
    """Drake's reading of a mesh (its ``CalcSpatialInertia`` and the fallback it warns of): the exact volume,
    mass centre and inertia as tetrahedra from the mesh frame's origin (for a closed mesh the exact mode's, from any
    point; for an open one they depend on the point, and Drake's is the origin), or the convex hull's where that is
    not a rigid body's (a volume below :data:`DRAKE_MIN_VOLUME`, principal moments negative or breaking the
    triangle inequality)."""
    from relacc.core.tolerances import triangle_violation

    if len(faces):
        a, b, c = (vertices[faces[:, k]] for k in range(3))
        volumes = np.einsum("ij,ij->i", a, np.cross(b, c)) / 6.0
        measure = float(volumes.sum())
        if measure >= DRAKE_MIN_VOLUME:
            com = (volumes[:, None] * (a + b + c) / 4.0).sum(axis=0) / measure
            D, E, F = a - com, b - com, c - com
            P = np.zeros((3, 3))
            for j in range(3):
                for k in range(j, 3):  # the tetrahedron (com, a, b, c)'s second moments, its volume signed
                    P[j, k] = P[k, j] = float((volumes / 20.0 * (
                        2 * (D[:, j] * D[:, k] + E[:, j] * E[:, k] + F[:, j] * F[:, k])
                        + D[:, j] * E[:, k] + D[:, k] * E[:, j] + D[:, j] * F[:, k] + D[:, k] * F[:, j]
                        + E[:, j] * F[:, k] + E[:, k] * F[:, j])).sum())
            inertia = np.trace(P) * np.eye(3) - P
            moments = np.linalg.eigvalsh(inertia)
            if moments[0] >= 0 and not triangle_violation(moments):
                return MeshMass(measure, com, inertia)
    return mass_properties(vertices, faces, "convex", place)


def hull_faces(vertices: np.ndarray, place: str) -> np.ndarray:
    """``(m, 3)`` the triangles of the vertices' convex hull (Qhull, as MuJoCo's compiler), each turned outwards.

    Raises:
        ModelError: vertices with no hull (fewer than 4, or all in a plane).
    """
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = ConvexHull(vertices)
    except (QhullError, ValueError) as exc:
        raise ModelError(f"{place}: the mesh's vertices have no convex hull ({str(exc).splitlines()[0]})") from None
    used = np.array(hull.simplices, dtype=np.int64)
    normals, centroids, _ = _triangles(vertices, used)
    inward = np.einsum("ij,ij->i", normals, centroids - vertices[hull.vertices].mean(axis=0)) < 0
    used[inward] = used[inward][:, ::-1]
    return used


def transformed(vertices: np.ndarray, refpos, refquat, scale) -> np.ndarray:
    """The vertices after a mesh asset's ``refpos`` (subtracted), ``refquat`` (its inverse applied; normalized, as
    MuJoCo does) and ``scale`` (per axis), in MuJoCo's order."""
    from relacc.core.rotations import matrix_from_quaternion

    v = vertices - np.asarray(refpos, dtype=float)
    q = np.asarray(refquat, dtype=float)
    if not np.array_equal(q, [1.0, 0.0, 0.0, 0.0]):
        v = v @ matrix_from_quaternion(q / np.linalg.norm(q))
    return v * np.asarray(scale, dtype=float)
