"""The one entry: a description file, by its suffix, to relacc's reading of it."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from relacc.errors import ModelError, NotARobot
from relacc.reading.model import Reading

if TYPE_CHECKING:
    from relacc.core.tree import Tree

SUFFIXES = {".xml": "mjcf", ".urdf": "urdf", ".xacro": "urdf"}
"""Description formats by file suffix (lower case; ``BALL.XML`` is an MJCF too; a ``.xacro`` expands to a URDF,
:mod:`relacc.reading.xacro`)."""


def format_of(path) -> str | None:
    """``"mjcf"``, ``"urdf"`` (a ``.xacro`` too) or None, by the file's suffix."""
    return SUFFIXES.get(Path(path).suffix.lower())


def read(path: str | os.PathLike, meshes: str | Callable | None = "engine", variant: frozenset = frozenset()
         ) -> Reading:
    """relacc's reading of an MJCF (``.xml``) or URDF (``.urdf``) file; ``variant``: an engine's way of reading the
    file (:data:`relacc.reading.mjcf.VARIANTS`, :data:`relacc.reading.urdf.VARIANTS`), for reproducing that engine.

    ``meshes``: where the mass properties of the mesh geoms relacc does not compute itself come from (a primitive
    fitted to a mesh, :func:`relacc.reading.mjcf.read`; relacc computes a ``type="mesh"`` geom's,
    :mod:`relacc.reading.mesh`): ``"engine"`` (default) an engine registered in :data:`MESH_ENGINES` (the bodies
    concerned are named in ``taken``); a callable; or None, which refuses such a body.

    Raises:
        ModelError: not a path, another suffix, or a file that cannot be read (the message names the file, the
            element and its line).
    """
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise ModelError(f"a model file: expected a path (str or pathlib.Path), got {type(path).__name__} "
                         f"{path!r:.60}")
    path = Path(path)
    kind = format_of(path)
    if kind is None:
        raise ModelError(f"{path}: a model file ends in .xml (MJCF), .urdf (URDF) or .xacro (a URDF's source)")
    with _deep_enough():
        if kind == "urdf":
            from relacc.reading import urdf

            return urdf.read(path, variant)
        from relacc.reading import mjcf

        return mjcf.read(path, _mesh_reader if meshes == "engine" else meshes, variant)


@contextlib.contextmanager
def _deep_enough():
    """Python's recursion limit raised for the reading: the reader walks bodies recursively, a few frames a level,
    and a document may nest up to :data:`relacc.reading.xml.MAX_DEPTH` elements (deeper ones are refused)."""
    import sys

    from relacc.reading.xml import MAX_DEPTH

    before = sys.getrecursionlimit()
    sys.setrecursionlimit(max(before, 20 * MAX_DEPTH))
    try:
        yield
    finally:
        sys.setrecursionlimit(before)


DESCRIPTION_ROOTS = ("mujoco", "robot")
"""The root elements of the descriptions relacc reads: an MJCF's ``<mujoco>``, a URDF's ``<robot>`` (a xacro's too)."""


def is_description(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a robot description relacc reads (its root element one of :data:`DESCRIPTION_ROOTS`),
    judged from its first element only; False for a file that cannot be read or parsed that far (a ROS
    ``package.xml``, a launch file, an MJCF fragment of ``<mujocoinclude>``)."""
    from xml.parsers import expat

    class Found(Exception):
        pass

    found: list[str] = []

    def start(tag, attrib):
        found.append(tag)
        raise Found

    parser = expat.ParserCreate()
    parser.StartElementHandler = start
    try:
        with open(path, "rb") as fh:
            parser.ParseFile(fh)
    except Found:
        pass
    except (OSError, expat.ExpatError):
        return False
    return bool(found) and found[0].split(":")[-1] in DESCRIPTION_ROOTS


def note_files(path: str | os.PathLike) -> None:
    """Every file the description at ``path`` reads (its ``<include>``s, its meshes, a URDF's ``package://`` targets)
    noted as an input of the running command (:func:`relacc.files.note_input`), before any work: an output that is
    one of them is refused up front. Only the XML is read here (no tree is built); a file that cannot be read is left
    to the command, which says why."""
    path = Path(path)
    kind = format_of(path)
    try:
        if kind == "urdf":
            from relacc.reading import urdf

            urdf.note_files(path)
        elif kind == "mjcf":
            from relacc.reading import mjcf

            mjcf.note_files(path)
    except (ModelError, OSError, RecursionError):
        pass


MESH_ENGINES: list[Callable] = []
"""Where a mesh geom's mass properties come from when relacc does not compute them itself (a primitive fitted to a
mesh, a builtin mesh, a hull limited by ``maxhullvert``): callables ``MeshGeom -> (mass, centre, inertia)`` an
engine package registers when it is imported (:mod:`relacc.engines` registers MuJoCo's). The reading imports no
engine: without one registered, such a body is refused, and the message says why."""


def _mesh_reader(mesh):
    """An engine's mass properties of one mesh geom relacc does not compute (declared per body in ``taken``)."""
    from relacc.errors import EngineError

    if not MESH_ENGINES:
        raise ModelError(f"{mesh.geom.place}: a body takes mass properties from a primitive fitted to a mesh (or a "
                         "builtin mesh), which relacc does not compute: give the body an <inertial>, or import "
                         "relacc.engines so that MuJoCo computes it")
    try:
        return MESH_ENGINES[-1](mesh)
    except EngineError as exc:
        raise ModelError(f"{mesh.geom.place}: a body takes mass properties from a primitive fitted to a mesh, which "
                         f"relacc asks MuJoCo for: {exc}; or give the body an <inertial>") from None


def read_moving(path: str | os.PathLike, purpose: str) -> Reading:
    """:func:`read`, refusing a file in which nothing moves (no joint): ``purpose`` ends the message ("there is nothing
    to check").

    Raises:
        ModelError: as :func:`read`, or the file has no joint.
    """
    reading = read(path)
    if reading.tree.nv == 0:
        fixed = sum(1 for kind, _ in reading.places if kind == "joint")
        which = f"its {fixed} joint{'s are' if fixed > 1 else ' is'} fixed" if fixed else "no joint in it"
        raise NotARobot(f"{path}: nothing moves in relacc's reading ({which}), so {purpose}")
    return reading


def read_tree(path: str | os.PathLike, meshes: str | Callable | None = "engine") -> Tree:
    """The :class:`relacc.Tree` of relacc's reading of a file (:func:`read`)."""
    return read(path, meshes).tree
