"""An MJCF read by relacc itself, by MuJoCo's XML reference (mujoco.readthedocs.io/en/stable/XMLreference.html), into
a :class:`relacc.reading.model.Reading`. What is read and how, element by element, is tabled in docs/reading.md; in
short:

* **The text**: ``<include file>`` replaced by the included file's top-level children (names from the main file's
  directory, nested); the sections ``<compiler>``, ``<option>``, ``<default>`` and ``<worldbody>`` may come several
  times and are taken together, in order.
* **Defaults**: a ``<joint>``, ``<geom>`` or ``<site>`` takes the attributes of its class (its ``class``, else the
  nearest ``childclass`` of the bodies and frames around it, else ``main``), each class those of the classes it is
  nested in, then its own. ``<freejoint>`` takes none (MuJoCo's parser gives it no class).
* **Frames**: a body's, a geom's, an inertial's and a ``<frame>``'s ``pos`` and orientation (``quat``, ``axisangle``,
  ``euler`` by ``<compiler eulerseq>``, ``xyaxes``, ``zaxis``; angles in degrees unless ``<compiler angle="radian">``):
  :mod:`relacc.reading.frames`. A ``<frame>`` moves what it holds, with its ``childclass``.
* **Inertia**: an ``<inertial>`` (``mass``, ``pos``, orientation, ``diaginertia`` or ``fullinertia`` in the order
  Ixx Iyy Izz Ixy Ixz Iyz) where ``<compiler inertiafromgeom>`` is ``auto`` (its default) or ``false``; else the
  geoms whose ``group`` lies in ``inertiagrouprange`` (and, with ``discardvisual``, that collide): each a primitive
  (:mod:`relacc.reading.inertia`; ``fromto`` for capsules, cylinders, boxes and ellipsoids, a box's or ellipsoid's
  cross-section then of half-sizes both its first size; ``shellinertia`` for
  shells) of its ``mass``, else ``density`` times its volume; a mesh's mass properties come from the caller
  (``meshes``, MuJoCo's by default through the adapter), and the body says so in ``taken``. Then, as the compiler
  does: ``boundmass`` and ``boundinertia`` (every body but the world: its mass, its principal moments, from below),
  ``balanceinertia`` (moments that break the triangle inequality replaced by their mean) and ``settotalmass`` (every
  mass and inertia scaled so that the bodies' masses sum to it).
* **Joints**: ``type`` (hinge by default), ``pos``, ``axis`` (normalized), ``ref`` (a hinge's in the compiler's
  angle unit), ``armature``, ``damping``, ``stiffness`` with ``springref``, ``range`` where limited (``limited``, or
  ``autolimits``: a range given), ``springdamper`` (stiffness and damping set from the joint's inertia at the
  reference configuration, as MuJoCo's compiler does); ``<freejoint>``; a ``mocap`` body is welded to the world.
* **Gravity**: ``<option gravity>``, zero with ``<flag gravity="disable"/>``. **Points**: every ``<site>``.
* Left out, and said (``unevaluated``): ``<equality>`` constraints, ``<tendon>`` elements, actuators with activation
  dynamics. Refused: ``<composite>``, ``<flexcomp>``, ``<compiler coordinate="global">`` (relacc cannot read them
  yet: the message says so).
* **Attach**: ``<attach model body prefix>`` is the ``<model>`` asset's body ``body`` (or its world's bodies), read
  with that model's own compiler, defaults and assets, placed where the element is, names prefixed
  (:meth:`_Reader._attach`).
* **Replicate**: ``<replicate count offset euler sep>`` is ``count`` copies of what it holds, copy ``k`` turned by the
  Euler angles ``k euler`` and placed at ``sum_{i<k} R(i euler) offset``, each name in it suffixed with ``sep`` and
  ``k`` in as many digits as ``count`` has (nested: the inner suffix first), as MuJoCo 4.0 compiles it (measured).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from relacc.core.tolerances import MJMINVAL, VERTEX_ROUNDING
from relacc.core.tree.model import Body, Joint, Point, Tree
from relacc.errors import ModelError, NotARobot
from relacc.files import note_input, regular_file
from relacc.reading import frames, inertia, physical
from relacc.reading.model import Coupling, Reading
from relacc.reading.xml import Node, number, numbers, parse_file, real, required_numbers, rounding

MAX_INCLUDE_DEPTH = 20
"""Includes nested deeper than this are refused (a file that includes itself)."""

REFUSED = ("composite", "flexcomp")
"""Elements that build bodies procedurally: relacc does not read them yet."""

DYNAMIC_ACTUATORS = ("cylinder", "muscle", "adhesion")
"""Actuator shortcuts with activation dynamics (``<general dyntype>`` other than ``none`` too)."""

POSE_KEYS = ("pos", "quat", "axisangle", "euler", "xyaxes", "zaxis")
"""The attributes that place an element in its body's frame."""

GEOM_TYPES = ("plane", "hfield", "sphere", "capsule", "ellipsoid", "cylinder", "box", "mesh", "sdf")


@dataclass(frozen=True)
class MeshGeom:
    """A mesh geom whose mass properties relacc asks the caller for: the file, the geom's element, its mesh asset's
    element (or None), the compiler's ``meshdir`` and angle unit, the geom's density or mass (kg/m^3 or kg, None:
    not given) and whether it is a shell."""

    file: str
    geom: Node
    mesh: Node | None
    meshdir: str
    degree: bool
    attributes: dict


VARIANTS = ("first_body_only", "first_body_unplaced", "default_geom_mass_ignored", "visual_geoms_ignored",
            "mesh_unit_inertia", "gravity_default", "settotalmass_ignored", "gravity_flag_ignored",
            "stacked_joints_in_parent", "armature_without_actuator", "free_damping_dropped", "default_chain_broken",
            "unnamed_siblings_dropped", "default_joint_pos_ignored", "default_geom_pose_ignored",
            "springdamper_ignored", "ball_damping_dropped", "mesh_obj_first_object", "mesh_inertia_exact",
            "replicate_skipped", "attach_skipped", "inertial_unit_inertia", "inertiagrouprange_ignored",
            "bare_bodies_dropped")
"""How an engine's MJCF parser reads a file differently, as relacc's reader can read it too (``variant``).
Pinocchio's:

* ``first_body_only``: only the first ``<body>`` written directly in the main file's ``<worldbody>``, and of it only
  what the main file writes (it expands no ``<include>``: metaworld's sawyer files include the mug's geoms into their
  first body, which Pinocchio reads as 0 kg);
* ``first_body_unplaced``: that first body, when it has no joint, at the world frame (its pos and orientation
  dropped);
* ``default_geom_mass_ignored``: a geom's ``mass`` inherited from a ``<default>`` class ignored, its density used (a
  mass written on the geom is honoured);
* ``visual_geoms_ignored``: geoms with ``contype = conaffinity = 0`` out of the inertia;
* ``mesh_unit_inertia``: in a body with a colliding mesh geom (not ``contype = conaffinity = 0``), the colliding
  geoms alone, each mesh 1 kg with a unit inertia at its frame (neither the mesh nor the geom's mass read:
  Pinocchio's ``MjcfGeom::computeInertia`` leaves a mesh's default, the identity inertia), the others as they are
  (measured on pin 4.1: dm_control's Jaco arm, each link a mesh of its own mass beside a cylinder, read as 1 kg plus
  the cylinder);
* ``gravity_default``: gravity ``(0, 0, -9.81)`` whatever ``<option>`` says;
* ``bare_bodies_dropped``: a ``<body>`` written with no attribute at all left out, with everything in it (Pinocchio's
  parser takes a body's name, parent and place from the element's attributes, and with none it never records the
  body; measured on pin 4.1: safety_gymnasium's racecar, whose differentials hang on such a body);
* ``unnamed_siblings_dropped``: of several unnamed ``<body>`` children of one body only the first, with its subtree
  (Pinocchio names an unnamed body after its parent, ``<parent>Bis``, so the later ones collide and are dropped;
  measured on pin 4.1: three unnamed children of 10, 100 and 1000 kg read as 10 kg);
* ``default_geom_pose_ignored``: a geom's ``pos`` and orientation (``quat``, ``axisangle``, ``euler``, ``xyaxes``,
  ``zaxis``) inherited from a ``<default>`` ignored, the geom at its body's frame (measured on pin 4.1: the whole of an
  Allegro hand's eight rows no known reading explained, issue 49);
* ``default_joint_pos_ignored``: a joint's ``pos`` inherited from a ``<default>`` (a class or the main default)
  ignored, the joint at the body's origin (one written on the joint is honoured; measured on pin 4.1, and the
  ``axis`` and ``armature`` of a class are read: dm_control's dog moves its lumbar joints by their class's
  ``pos="0.012 0 0.01"``);
* ``ball_damping_dropped`` (with ``free_damping_dropped``: Pinocchio's): a ball joint's damping dropped (measured
  on pin 4.1: its model's damping is 0 on a ball's and a free joint's speeds, the written value on a hinge's);
* ``springdamper_ignored`` (Pinocchio's and Drake's): a joint's ``springdamper`` ignored, the stiffness and damping
  written kept;
* ``inertial_unit_inertia``: an ``<inertial>`` with neither ``diaginertia`` nor ``fullinertia`` read with the unit
  inertia, 1 kg m^2 about each axis (MuJoCo's compiler reads it as zero; Pinocchio's ``convertInertiaFromMjcf``
  starts from the identity; measured on pin 4.1);
* ``settotalmass_ignored`` (Pinocchio's and Drake's): no scaling by ``<compiler settotalmass>``.
* ``inertiagrouprange_ignored`` (Pinocchio's and Drake's): ``<compiler inertiagrouprange>`` ignored, every geom's
  mass counted whatever its ``group`` (measured on pin 4.1 and Drake 1.51, which warns so: a body of a group-4 box
  of 8 kg beside a group-1 box and sphere read as 10.52 kg, MuJoCo's 8; found on metaworld's Sawyer gripper).
* ``replicate_skipped`` (Pinocchio's and Drake's): a ``<replicate>`` and everything in it left out (measured on
  pin 4.1 and Drake 1.51: a body with two replicated arms read without them, Drake without a word).
* ``attach_skipped`` (Pinocchio's and Drake's): an ``<attach>`` left out (measured on pin 4.1 and Drake 1.51: a mount
  with two attached arms read as the mount alone; Drake warns that the tag is unsupported).

Drake's:

* ``gravity_flag_ignored``: ``<flag gravity="disable"/>`` ignored;
* ``stacked_joints_in_parent``: in a body with several joints placed away from its parent, every joint but the last
  read with its ``pos`` and ``axis`` in the parent's frame;
* ``armature_without_actuator``: a joint's armature kept only where a ``<motor>`` or ``<position>`` actuator drives
  it;
* ``free_damping_dropped``: a free joint's damping dropped;
* ``mesh_inertia_exact``: a mesh's exact volume, mass centre and inertia whatever its ``inertia`` mode (measured on
  Drake 1.51: two disjoint 0.1 m cubes in one OBJ read as 2 kg at density 1000, where the default legacy mode gives
  3.33 kg), its convex hull's where that is not a physical inertia (a volume below 1e-14 m^3, an open or inside-out
  mesh: Drake's ``CalcSpatialInertia`` fallback, which it warns of; robosuite's omron base, issue 53);
* ``default_chain_broken``: a ``<default>`` class's attributes for an element (``<joint>``, ``<geom>``, ...) are
  its own merged over its parent class's only where the parent has that element too: a class without a ``<joint>``
  (or ``<geom>``) default gives its joints (geoms) nothing, not even what its ancestors set, and breaks the chain
  for the classes under it (measured on Drake 1.51: damping 30 set in a class two levels up reads 0; dm_control's
  quadruped loses its hips' damping so).

MuJoCo's:

* ``mesh_obj_first_object``: of an OBJ mesh file with several objects (``o`` or ``g``), the first object's faces only
  (google-deepmind/mujoco#911; the convex hull, which takes every vertex, is the whole file's): the volume, mass
  centre and inertia of the legacy, exact and shell modes are the first object's.
"""


def read(path, meshes=None, variant=frozenset()) -> Reading:
    """relacc's reading of the MJCF at ``path`` (module docstring). ``meshes``: a callable ``MeshGeom ->
    (mass kg, centre (3,), inertia about it (3, 3))`` in the frame the geom is placed in (its body's, or the
    ``<frame>`` holding it), its own ``pos`` and orientation included; without one, a body whose inertia needs a mesh
    is refused (the message names it). ``variant``: names of :data:`VARIANTS`, an engine's way of reading the file.

    Raises:
        ModelError: the file (or one it includes) cannot be read, holds an element relacc does not read yet, or a
            value that is not one (the message names the element and its line).
    """
    path = Path(path)
    notes: list[str] = []
    root = _model_root(path, notes)
    unknown = set(variant) - set(VARIANTS)
    if unknown:
        raise ModelError(f"unknown reading variants {sorted(unknown)}: accepted are {', '.join(VARIANTS)}")
    reader = _Reader(path, root, notes, meshes, frozenset(variant))
    return reader.reading()


def _model_root(path: Path, notes: list) -> Node:
    """The root of the MJCF at ``path`` (the main file, or a model an ``<attach>`` names), its includes inlined.

    Raises:
        ModelError: not a model (a ``<mujocoinclude>`` fragment, another root), or an element relacc does not read.
    """
    root = parse_file(path, notes)
    if root.tag == "mujocoinclude":
        raise ModelError(f"{root.place}: <mujocoinclude>: a fragment for other files to <include>, not a model "
                         "(compare the file that includes it)")
    if root.tag != "mujoco":
        raise ModelError(f"{root.place}: the root element is <{root.tag}>; an MJCF's is <mujoco>")
    _inline(root, path.parent, 0)
    for node in root.iter():
        if node.tag in REFUSED:
            raise ModelError(f"{node.place}: <{node.tag}> builds bodies procedurally; relacc does not read it yet "
                             "(compare the file MuJoCo writes out, mujoco.MjSpec.to_xml, instead)")
    return root


def mesh_file(path: Path, meshdir: str, asset: Node) -> Path:
    """The file a ``<mesh file>`` asset of the MJCF at ``path`` is read from, by MuJoCo's rule (measured on MuJoCo
    3.14.0 and 4.0.0 alike): ``meshdir`` (or ``assetdir``) under the main file's directory; where no such file exists
    and the asset is written in an ``<include>``d file, the name from that file's own directory (without
    ``meshdir``). Both present: the main file's. Qualot/Open_ball_joint_mjcf keeps its meshes beside the included
    files that name them, which MuJoCo reads and relacc refused."""
    first = path.parent / meshdir / asset.get("file")
    own = Path(asset.file).parent / asset.get("file")
    if not first.is_file() and Path(asset.file).resolve() != path.resolve() and own.is_file():
        return own
    return first


def note_files(path: Path, depth: int = 0) -> None:
    """The files the MJCF at ``path`` reads, noted as inputs (:func:`relacc.reading.read.note_files`): the file and
    its includes (each noted as it is parsed), each mesh asset's file under ``meshdir`` (or ``assetdir``), and each
    ``<model>`` asset's file with its own (an ``<attach>``ed model)."""
    root = parse_file(path)
    _inline(root, path.parent, 0)
    compiler: dict = {}
    for node in root.findall("compiler"):
        compiler.update(node.attrib)
    meshdir = compiler.get("meshdir", compiler.get("assetdir", ""))
    for asset in root.findall("asset"):
        for mesh in asset.findall("mesh"):
            if mesh.get("file"):
                note_input(mesh_file(path, meshdir, mesh))
        for model in asset.findall("model"):
            if model.get("file") and depth < MAX_INCLUDE_DEPTH:
                note_files(path.parent / model.get("file"), depth + 1)


def _inline(node: Node, directory: Path, depth: int, seen: set | None = None) -> None:
    """Every ``<include file>`` below ``node`` replaced by the included file's top-level children, recursively, by
    MuJoCo's rule: a relative name from the main file's directory, and each file included once in the whole model
    (MuJoCo refuses a second ``<include>`` of a file, "already included": a file including the next several times,
    level after level, would otherwise be read exponentially many times)."""
    seen = set() if seen is None else seen
    k = 0
    while k < len(node.children):
        child = node.children[k]
        if child.tag != "include":
            _inline(child, directory, depth, seen)
            k += 1
            continue
        if depth >= MAX_INCLUDE_DEPTH:
            raise ModelError(f"{child.place}: includes nested more than {MAX_INCLUDE_DEPTH} deep (a file that "
                             "includes itself?)")
        name = child.get("file")
        if not name:
            raise ModelError(f"{child.place}: an <include> without a file")
        target = (directory / name).resolve()
        if target in seen:
            raise ModelError(f"{child.place}: <include file={name!r}>: that file is already included; MuJoCo "
                             "includes a file once per model and refuses it again")
        seen.add(target)
        try:
            included = parse_file(directory / name)
        except ModelError as exc:
            raise ModelError(f"{child.place}: <include file={name!r}>: {exc}") from None
        _inline(included, directory, depth + 1, seen)
        node.children[k:k + 1] = included.children
        k += len(included.children)


SIZES = {"sphere": 1, "capsule": 2, "cylinder": 2, "ellipsoid": 3, "box": 3}
"""The sizes a primitive geom needs, each positive (MuJoCo's compiler: "size N must be positive in geom"); with
``fromto`` the first (the length comes from the two ends)."""


def _check_geom(g: Node, kind: str) -> None:
    """What MuJoCo's compiler refuses of a geom, refused here too: a primitive's sizes missing or not positive, a
    negative mass or density.

    Raises:
        ModelError: naming the geom, its place and what MuJoCo says.
    """
    for key in ("mass", "density"):
        value = number(g, key)
        if value is not None and value < 0:
            raise ModelError(f"{g.place}: geom {key}={value:g} is negative; MuJoCo refuses it (\"mass, inertia or "
                             "density are negative in geom\")")
    if kind not in SIZES or g.get("mesh"):
        return
    need = 1 if g.get("fromto") is not None else SIZES[kind]
    size = numbers(g, "size", None, [])
    for i in range(need):
        if i >= len(size) or not size[i] > 0:
            raise ModelError(f"{g.place}: a {kind} geom needs {need} positive size{'s' if need > 1 else ''}, and "
                             f"size {i} is {'missing' if i >= len(size) else f'{size[i]:g}'} (size={g.get('size')!r}); "
                             f"MuJoCo refuses it (\"size {i} must be positive in geom\")")


def _written_in(node: Node, file: str) -> Node:
    """``node`` with only the descendants written in ``file`` (an ``<include>``'s elements left out)."""
    return Node(node.tag, node.attrib, node.file, node.line,
                [_written_in(c, file) for c in node.children if c.file == file])


_COUNTERS = ("njoints", "mesh_geoms", "legacy_meshes", "default_masses", "visual_geoms", "stacked", "unactuated",
             "damped_free", "damped_balls", "broken_defaults", "default_joint_pos", "default_geom_pose",
             "unnamed_dropped", "replicates", "attaches", "inertia_less", "group_excluded", "bare_bodies")
"""The reading's counts that an attached model's reading adds to (:meth:`_Reader._attach`)."""


def _renamed(node: Node, rename) -> Node:
    """A copy of ``node`` and everything below it, each ``name`` given as ``rename(name)`` (an ``<attach>``'s prefix, a
    ``<replicate>`` copy's suffix)."""
    attrib = dict(node.attrib)
    if "name" in attrib:
        attrib["name"] = rename(attrib["name"])
    return Node(node.tag, attrib, node.file, node.line, [_renamed(c, rename) for c in node.children])


def _references(node: Node, names) -> set:
    """The values of ``node``'s attributes and those of the elements below it, but names and classes, that are among
    ``names``: the elements an ``<equality>`` or ``<tendon>`` refers to."""
    return {v for n in node.iter() for k, v in n.attrib.items() if k not in ("name", "class") and v in names}


def _referring(node: Node, names: set, affix: str, before: bool = False) -> Node:
    """A copy of ``node`` and everything below it whose ``name`` and references to ``names`` end with ``affix`` (a
    ``<replicate>`` copy's suffix), or begin with it (``before``: an ``<attach>``'s prefix)."""
    def renamed(k: str, v: str) -> str:
        if k == "class" or (k != "name" and v not in names):
            return v
        return affix + v if before else v + affix

    return Node(node.tag, {k: renamed(k, v) for k, v in node.attrib.items()}, node.file, node.line,
                [_referring(c, names, affix, before) for c in node.children])


class _Reader:
    """One file's reading in progress (the module docstring, step by step)."""

    def __init__(self, path: Path, root: Node, notes: list, meshes, variant=frozenset()):
        self.notes, self.meshes = notes, meshes
        self.variant = variant
        self.normalized = frames.Normalized()
        self.replica_of: dict[str, str] = {}  # each name a <replicate> made: the name written
        self.renamed_again: set[str] = set()  # names an inner <replicate> made that an outer one copied
        self.replicates = 0  # <replicate> elements in the file
        self.attaches = 0  # <attach> elements in the file (and the models it attaches)
        self._settings(path, root)
        self._accumulators()

    def _settings(self, path: Path, root: Node) -> None:
        """What one model file sets for the elements written in it: its compiler, defaults, mesh and model assets and
        actuated joints (an ``<attach>``ed model's own, :meth:`_attach`)."""
        self.path, self.root = path, root
        self.compiler = {}
        for node in root.findall("compiler"):
            self.compiler.update(node.attrib)
        if self.compiler.get("coordinate", "local") != "local":
            raise ModelError(f"{path}: <compiler coordinate={self.compiler['coordinate']!r}>: relacc reads local "
                             "coordinates only (MuJoCo 2.3.3 and later do too)")
        self.degree = self.compiler.get("angle", "degree") == "degree"
        self.eulerseq = self.compiler.get("eulerseq", "xyz")
        if len(self.eulerseq) != 3 or any(c not in "xyzXYZ" for c in self.eulerseq):
            raise ModelError(f"{path}: <compiler eulerseq={self.eulerseq!r}>: expected three of x, y, z, X, Y, Z")
        self._replicate(root)
        self._replicate_references(root)
        self.fromgeom = self.compiler.get("inertiafromgeom", "auto")
        groups = self._compiler_numbers("inertiagrouprange", [0, 5])
        self.groups = (int(groups[0]), int(groups[1]))
        self.discardvisual = self.compiler.get("discardvisual", "false") == "true"
        self.autolimits = self.compiler.get("autolimits", "true") == "true"
        # assetdir is meshdir and texturedir both, where those are not given (MuJoCo's reading)
        self.meshdir = self.compiler.get("meshdir", self.compiler.get("assetdir", ""))
        self.classes = self._classes()
        self.broken_classes = self._classes(broken=True)
        self.broken_defaults = 0  # elements whose defaults default_chain_broken reads otherwise
        self.default_joint_pos = 0  # joints whose pos comes from a <default>
        self.default_geom_pose = 0  # geoms whose pos or orientation comes from a <default>
        self.unnamed_dropped = 0  # unnamed bodies after the first among one parent's children
        self.bare_bodies = 0  # bodies written with no attribute
        self.inertia_less = 0  # <inertial> elements with neither diaginertia nor fullinertia
        self.group_excluded = 0  # geoms left out of the inertia by inertiagrouprange
        self.springdamper: dict[str, tuple] = {}  # joint: (timeconst, dampratio, springref) of a springdamper
        self.assets = {m.get("name") or Path(m.get("file", "")).stem: m
                       for a in root.findall("asset") for m in a.findall("mesh")}
        self.models = {m.get("name") or Path(m.get("file", "")).stem: m
                       for a in root.findall("asset") for m in a.findall("model")}
        self.driven = {a.get("joint") for s in root.findall("actuator") for a in s.children
                       if a.tag in ("motor", "position") and a.get("joint")}
        # an actuator naming a joint a <replicate> copied drives every copy (MuJoCo replicates the actuator too)
        self.driven |= {name for name, written in self.replica_of.items() if written in self.driven}

    def _accumulators(self) -> None:
        """What the reading gathers over every body it reads, the attached models' included."""
        self.bodies: list[Body] = []
        self.points: list[Point] = []
        self.places, self.ranges, self.damping, self.stiffness, self.taken = {}, {}, {}, {}, {}
        self.sensitivity: dict[str, float] = {}  # springdamper joints' (Reading.sensitivity)
        self.mesh_geoms = 0
        self.legacy_meshes = 0  # mesh geoms in MuJoCo's default legacy mode (Drake computes them exactly)
        self.mesh_density: dict[str, float] = {}  # each body's mesh geoms' densities, summed (kg/m^3)
        self.mesh_inertia: dict[str, float] = {}  # each body's mesh geoms' largest inertia entries, summed (kg m^2)
        self.mesh_body_names: set[str] = set()  # bodies with a mesh geom (whoever computed it)
        self.multi_object_meshes: list[str] = []  # OBJ files of several objects (MuJoCo reads the first)
        self.written: dict[str, float] = {}  # body: the Frobenius norm of its written inertia's rounding (kg m^2)
        self.findings = []
        self.njoints = 0
        self.default_masses = 0
        self.first_body: Node | None = None  # the first <body> of the main file's <worldbody>, as read
        self.visual_geoms = self.stacked = self.unactuated = self.damped_free = self.damped_balls = 0
        self.friction: list[str] = []  # joints with a frictionloss (dry friction, a constraint in MuJoCo)
        self.frictionloss: dict[str, float] = {}  # their frictionloss (N m or N)
        self.gravcomp: dict[str, float] = {}  # bodies with gravity compensation: the fraction of their weight

    def _compiler_numbers(self, key, default):
        text = self.compiler.get(key)
        if text is None:
            return default
        try:
            return [real(x) for x in text.split()]
        except ValueError:
            raise ModelError(f"{self.path}: <compiler {key}={text!r}> is not numbers") from None

    # ---- defaults --------------------------------------------------------------------------------------------
    def _classes(self, broken: bool = False) -> dict:
        """``{class: {tag: attrib}}``, each class with everything it inherits (``broken``: as
        ``default_chain_broken`` reads it, an element's defaults inherited only through classes that have it)."""
        classes = {"main": {}}

        def visit(node: Node, name: str, inherited: dict):
            own = {} if broken else {tag: dict(attrib) for tag, attrib in inherited.items()}
            for child in node.children:
                if child.tag != "default":
                    own.setdefault(child.tag, dict(inherited.get(child.tag, {})) if broken else {}).update(
                        child.attrib)
            classes[name] = own
            for child in node.findall("default"):
                cls = child.get("class")
                if not cls:
                    raise ModelError(f"{child.place}: a nested <default> needs a class name")
                if cls in classes and cls != "main":
                    raise ModelError(f"{child.place}: a second default class named {cls!r}")
                visit(child, cls, own)

        for top in self.root.findall("default"):
            merged = classes["main"]
            for child in top.children:
                if child.tag != "default":
                    merged.setdefault(child.tag, {}).update(child.attrib)
            for child in top.findall("default"):
                cls = child.get("class")
                if not cls:
                    raise ModelError(f"{child.place}: a nested <default> needs a class name")
                visit(child, cls, merged)
        return classes

    def attrs(self, node: Node, childclass: str) -> Node:
        """The element with its class's attributes under its own (``<freejoint>``: its own only)."""
        if node.tag == "freejoint":
            return node
        cls = node.get("class") or childclass
        if cls not in self.classes:
            raise ModelError(f"{node.place}: <{node.tag}> names class {cls!r}, which no <default> defines")
        merged = dict(self.classes[cls].get(node.tag, {}))
        broken = dict(self.broken_classes[cls].get(node.tag, {}))
        if any(broken.get(k) != v for k, v in merged.items() if k not in node.attrib):
            self.broken_defaults += 1
            if "default_chain_broken" in self.variant:
                merged = broken
        if node.tag == "joint" and "pos" in merged and "pos" not in node.attrib:  # a joint's pos from its class
            self.default_joint_pos += 1
            if "default_joint_pos_ignored" in self.variant:
                del merged["pos"]
        if node.tag == "geom" and any(k in merged and k not in node.attrib for k in POSE_KEYS):  # a pose from its class
            self.default_geom_pose += 1
            if "default_geom_pose_ignored" in self.variant:
                for k in POSE_KEYS:
                    merged.pop(k, None)
        if node.tag == "geom" and "mass" in merged and "mass" not in node.attrib:  # a mass from its class
            merged["_default_mass"] = "1"  # a mark, never an MJCF attribute (they have no leading underscore)
            if "default_geom_mass_ignored" in self.variant:
                del merged["mass"]
        merged.update(node.attrib)
        return Node(node.tag, merged, node.file, node.line, node.children)

    # ---- frames ----------------------------------------------------------------------------------------------
    def _replicate(self, node: Node) -> None:
        """Every ``<replicate>`` below ``node`` replaced by its copies, innermost first (module docstring): copy ``k``
        is a ``<frame>`` turned by ``R(k euler)`` at ``sum_{i<k} R(i euler) offset``, holding the replicate's children
        with every ``name`` suffixed.

        Raises:
            ModelError: a ``count`` that is not a whole number of at least 1.
        """
        k = 0
        while k < len(node.children):
            child = node.children[k]
            self._replicate(child)
            if child.tag != "replicate":
                k += 1
                continue
            self.replicates += 1
            if "replicate_skipped" in self.variant:
                del node.children[k]
                continue
            count = number(child, "count", 0.0)
            if count != int(count) or count < 1:
                raise ModelError(f"{child.place}: <replicate count={child.get('count')!r}>: expected a whole number of "
                                 "copies, at least 1")
            n = int(count)
            offset = np.array(numbers(child, "offset", 3, [0.0, 0.0, 0.0]))
            angles = [self.angle(x) for x in numbers(child, "euler", 3, [0.0, 0.0, 0.0])]
            p, copies = np.zeros(3), []
            for i in range(n):
                R = frames.euler(self.eulerseq, [i * a for a in angles])
                suffix = f"{child.get('sep', '')}{i:0{len(str(n))}d}"
                pose = {"pos": " ".join(repr(float(x)) for x in p),
                        "quat": " ".join(repr(float(x)) for x in frames.quaternion_of(R))}
                copies.append(Node("frame", pose, child.file, child.line,
                                   [_renamed(c, functools.partial(self._replica, suffix)) for c in child.children]))
                p = p + R @ offset
            node.children[k:k + 1] = copies
            k += len(copies)

    def _replica(self, suffix: str, name: str) -> str:
        """``name`` in a ``<replicate>``'s copy, remembered with the name as written (through nested replicates)."""
        if name in self.replica_of:
            self.renamed_again.add(name)
        self.replica_of[name + suffix] = self.replica_of.get(name, name)
        return name + suffix

    def _replicate_references(self, root: Node) -> None:
        """Each ``<equality>`` and ``<tendon>`` element outside the ``<replicate>``s that names replicated elements
        replaced by one copy per copy of them, its name and those references given that copy's suffix, as MuJoCo
        4.0.0 compiles it (measured: an equality of ``j`` and ``k`` in a 3-in-2 nested replicate is six, ``e00`` to
        ``e21``; a tendon of ``j`` in two copies is ``t0`` and ``t1``). An element naming both a replicated and an
        unreplicated element, which MuJoCo refuses ("unknown element"), is copied with the unreplicated name as it is.
        """
        suffixes: dict[str, set[str]] = {}
        for name, written in self.replica_of.items():
            if name not in self.renamed_again:
                suffixes.setdefault(written, set()).add(name[len(written):])
        if not suffixes:
            return
        for section in (s for tag in ("equality", "tendon") for s in root.findall(tag)):
            copies = []
            for e in section.children:
                named = _references(e, suffixes)
                common = set.intersection(*(suffixes[v] for v in named)) if named else set()
                copies += [_referring(e, named, x) for x in sorted(common, key=lambda x: x[::-1])] if common else [e]
            section.children[:] = copies

    def angle(self, x: float) -> float:
        return np.deg2rad(x) if self.degree else x

    def rotation(self, node: Node) -> np.ndarray:
        """The element's orientation (child to parent), from whichever form it gives."""
        given = [k for k in ("quat", "axisangle", "euler", "xyaxes", "zaxis") if node.get(k) is not None]
        if len(given) > 1:
            raise ModelError(f"{node.place}: <{node.tag}> gives its orientation twice ({', '.join(given)})")
        if not given:
            return np.eye(3)
        key = given[0]
        if key == "quat":
            return frames.quaternion(numbers(node, "quat", 4), self.normalized, node.place)
        if key == "axisangle":
            v = required_numbers(node, "axisangle", 4)
            return frames.axis_angle(self.normalized.unit("axisangle axis", v[:3], node.place), self.angle(v[3]))
        if key == "euler":
            return frames.euler(self.eulerseq, [self.angle(x) for x in required_numbers(node, "euler", 3)])
        if key == "xyaxes":
            return frames.xyaxes(numbers(node, "xyaxes", 6), self.normalized, node.place)
        return frames.zaxis(numbers(node, "zaxis", 3), self.normalized, node.place)

    def pose(self, node: Node) -> tuple[np.ndarray, np.ndarray]:
        return np.array(numbers(node, "pos", 3, [0.0, 0.0, 0.0])), self.rotation(node)

    # ---- the tree --------------------------------------------------------------------------------------------
    def _spring_dampers(self, tree: Tree) -> None:
        """The stiffness and damping of the joints with ``springdamper="timeconst dampratio"``, as MuJoCo's compiler
        sets them (``mjCModel::AutoSpringDamper``): the joint's inertia ``n / sum(dof_invweight0)`` over its ``n``
        speeds, ``dof_invweight0`` the diagonal of ``M^-1`` at the reference configuration (case 2, armature
        included; a free joint's three translations and three rotations each averaged, a ball's three), stiffness
        that over ``(timeconst dampratio)^2``, damping twice that over ``timeconst``. ``M`` is Kane's
        ``sum_b m_b V_b^T V_b + Omega_b^T I_b Omega_b`` from the note's partial velocities (the reference walk of
        :mod:`relacc.core.tree.walk`; :func:`relacc.dynamics.tree.equations` sums the same terms a batch at a time,
        with the forces, in the layer above the reading). Where ``M`` is singular the values written stay, and a
        note says so."""
        from relacc.core.tree.coordinates import reference_q
        from relacc.core.tree.kinematics import tree_kinematics

        k = tree_kinematics(tree, 2, reference_q(tree, 2), np.zeros(tree.nv), backend="reference")
        assert k.V is not None and k.Omega is not None  # the partials: asked for (partials=True)
        M = np.diag(np.concatenate([j.armature for _, j in tree.joints]))
        for b, body in enumerate(tree.bodies):
            R, V, W = k.rotation[b], k.V[b], k.Omega[b]
            M += body.mass * V.T @ V + W.T @ (R @ body.inertia @ R.T) @ W
        names = ", ".join(list(self.springdamper)[:3]) + (" ..." if len(self.springdamper) > 3 else "")
        try:
            Minv = np.linalg.inv(M)
        except np.linalg.LinAlgError:
            Minv = np.full(M.shape, np.nan)
        inverse = np.diag(Minv).copy()
        if not np.all(np.isfinite(inverse)):
            self.notes.append(f"springdamper of {names}: the mass matrix at the reference configuration is singular; "
                              "the stiffness and damping written are kept (MuJoCo's compiler divides by its inverse)")
            return
        sensitivity = _sensitivity(tree, k, Minv)
        for (_, joint), d in zip(tree.joints, tree.dofadr):  # dof_invweight0: averaged per block
            blocks = {"free": ((d, d + 3), (d + 3, d + 6)), "ball": ((d, d + 3),)}.get(joint.type, ())
            for lo, hi in blocks:
                inverse[lo:hi] = inverse[lo:hi].mean()
        for (_, joint), d in zip(tree.joints, tree.dofadr):
            if joint.name not in self.springdamper:
                continue
            timeconst, dampratio, springref = self.springdamper[joint.name]
            inertia = joint.nv / max(MJMINVAL, float(inverse[d:d + joint.nv].sum()))
            stiffness = inertia / max(MJMINVAL, timeconst * timeconst * dampratio * dampratio)
            if joint.type != "free":  # relacc keeps no free joint's spring (as for one written)
                self.stiffness[joint.name] = (stiffness, springref)
            self.damping[joint.name] = np.full(joint.nv, 2 * inertia / max(MJMINVAL, timeconst))
            self.sensitivity[joint.name] = float(sensitivity[d:d + joint.nv].max())
        self.notes.append(f"{len(self.springdamper)} joint{'s' if len(self.springdamper) > 1 else ''} with "
                          f"springdamper ({names}): stiffness and damping set from the joint's inertia at the "
                          "reference configuration, as MuJoCo's compiler does")

    def reading(self) -> Reading:
        worlds = self.root.findall("worldbody")
        self.first_body = next((b for w in worlds for b in w.findall("body") if b.file == str(self.path)), None)
        if "first_body_only" in self.variant:  # and, as Pinocchio expands no <include>, none of its included parts
            first = None if self.first_body is None else _written_in(self.first_body, str(self.path))
            worlds = [Node("worldbody", {}, str(self.path), 0, [] if first is None else [first])]
            self.first_body = first  # the copy read is the first body (``first_body_unplaced`` asks by identity)
        for world in worlds:
            self._children(world, -1, np.zeros(3), np.eye(3), "main")
            for site in world.findall("site"):  # the world's sites: points of the world
                self._site(site, -1, np.zeros(3), np.eye(3), "main")
        if not self.bodies:
            raise NotARobot(f"{self.path}: the MJCF has no <body> in its <worldbody>: there is nothing to evaluate")
        self._compiler_masses()
        gravity, disabled = np.array([0.0, 0.0, -9.81]), False
        for option in self.root.findall("option"):
            if option.get("gravity") is not None or option.findall("flag"):
                self.places[("option", "gravity")] = option.place
            gravity = np.array(numbers(option, "gravity", 3, list(gravity)))
            for flag in option.findall("flag"):
                disabled = disabled or flag.get("gravity") == "disable"
        written = gravity
        if "gravity_default" in self.variant:
            gravity = np.array([0.0, 0.0, -9.81])
        elif disabled and "gravity_flag_ignored" not in self.variant:
            gravity = np.zeros(3)
        name = self.root.get("model") or self.path.stem
        tree = Tree(name, tuple(self.bodies), gravity=gravity, points=tuple(self.points), source=str(self.path))
        if self.springdamper and "springdamper_ignored" not in self.variant:
            self._spring_dampers(tree)
        first = self.first_body
        facts = {"world_children": sum(1 for w in self.root.findall("worldbody") for b in w.findall("body")),
                 "default_geom_masses": self.default_masses, "gravity_written": written.tolist(),
                 "gravity_disabled": disabled, "settotalmass": self._compiler_numbers("settotalmass", [-1.0])[0] > 0,
                 "placed_jointless_first": first is not None and not self._has_joint(first)
                 and any(first.get(k) is not None for k in ("pos", "quat", "axisangle", "euler", "xyaxes", "zaxis")),
                 "visual_geoms": self.visual_geoms, "mesh_bodies": bool(self.mesh_body_names),
                 "multi_object_meshes": tuple(self.multi_object_meshes), "legacy_meshes": self.legacy_meshes,
                 "mesh_density": dict(self.mesh_density), "mesh_inertia": dict(self.mesh_inertia),
                 "stacked": self.stacked, "unactuated_armature": self.unactuated, "damped_free": self.damped_free,
                 "damped_balls": self.damped_balls,
                 "broken_defaults": self.broken_defaults, "unnamed_dropped": self.unnamed_dropped,
                 "default_joint_pos": self.default_joint_pos, "default_geom_pose": self.default_geom_pose,
                 "springdamper": tuple(self.springdamper), "replicates": self.replicates,
                 "attaches": self.attaches, "inertia_less": self.inertia_less,
                 "group_excluded": self.group_excluded, "bare_bodies": self.bare_bodies}
        couplings = self._couplings()
        unevaluated = self._unevaluated(len(couplings))
        return Reading(tree, "mjcf", str(self.path), self.places, self.ranges, self.damping, self.stiffness,
                       self.taken, tuple(line for _, line in unevaluated),
                       tuple(self.notes + self.normalized.notes("MJCF")),
                       tuple(self.findings), facts=facts, variant=self.variant, friction=self.frictionloss,
                       gravcomp=self.gravcomp, couplings=couplings,
                       unevaluated_kinds=tuple(kind for kind, _ in unevaluated), sensitivity=self.sensitivity)

    def _children(self, node: Node, parent: int, at: np.ndarray, R: np.ndarray, childclass: str) -> None:
        """Bodies and frames directly in ``node`` (a body, a frame or the world), placed by ``(at, R)`` in the parent
        body's frame (a frame's own pose composed in)."""
        unnamed = False  # Pinocchio names an unnamed body after its parent ("<parent>Bis"): one per parent survives
        for child in node.children:
            if child.tag == "body":
                if not child.attrib:  # Pinocchio never records a body written with no attribute
                    self.bare_bodies += 1
                    if "bare_bodies_dropped" in self.variant:
                        continue
                if not child.get("name"):
                    if unnamed:
                        self.unnamed_dropped += 1
                        if "unnamed_siblings_dropped" in self.variant:
                            continue
                    unnamed = True
                self._body(child, parent, at, R, childclass)
            elif child.tag == "frame":
                pos, Rf = self.pose(child)
                self._children(child, parent, at + R @ pos, R @ Rf, child.get("childclass") or childclass)
            elif child.tag == "attach":
                self.attaches += 1
                if "attach_skipped" not in self.variant:
                    self._attach(child, parent, at, R)

    def _attach(self, node: Node, parent: int, at: np.ndarray, R: np.ndarray) -> None:
        """An ``<attach model body prefix>``: the ``<model>`` asset's file (from this file's directory) read with its
        own compiler, defaults and assets, and its body ``body`` with everything in it (without ``body``: every body
        of its world; ``body="world"``: a body named ``world`` holding its world, geoms included) placed here, at
        that body's own pose, each name prefixed with ``prefix`` (as MuJoCo 4.0 compiles it, measured); the attached
        model's joints that its own actuators drive are driven.

        Raises:
            ModelError: no such model asset, its file unreadable, or no such body in it.
        """
        import copy

        asset = self.models.get(node.get("model"))
        if asset is None:
            raise ModelError(f"{node.place}: <attach model={node.get('model')!r}>: no <model> asset of that name "
                             f"(the file declares {', '.join(sorted(self.models)) or 'none'})")
        if not asset.get("file"):
            raise ModelError(f"{asset.place}: <model name={node.get('model')!r}> names no file to attach")
        file = self.path.parent / asset.get("file")
        root = _model_root(file, self.notes)
        prefix = node.get("prefix", "")
        worlds = root.findall("worldbody")
        wanted = node.get("body")
        if wanted is None:
            held = [c for w in worlds for c in w.children if c.tag in ("body", "frame", "attach")]
        elif wanted == "world":  # a body named world holding the model's world: its geoms give it mass (MuJoCo)
            held = [Node("body", {"name": "world"}, node.file, node.line, [c for w in worlds for c in w.children])]
        else:
            held = [b for w in worlds for b in w.iter("body") if b.get("name") == wanted][:1]
            if not held:
                raise ModelError(f"{node.place}: <attach body={wanted!r}>: {file} has no body of that name")
        sub = copy.copy(self)  # this reading's gatherings, shared; the attached model's own settings
        sub._settings(file, root)
        sub.driven = {prefix + j for j in sub.driven}
        sub._children(Node("attach", {}, node.file, node.line, [_renamed(c, prefix.__add__) for c in held]), parent,
                      at, R, "main")
        for counter in _COUNTERS:
            setattr(self, counter, getattr(sub, counter))
        self.driven |= sub.driven
        self._attach_references(node, root, held, prefix)

    def _attach_references(self, node: Node, root: Node, held: list, prefix: str) -> None:
        """The attached model's ``<equality>`` and ``<tendon>`` elements that name only elements attached, added to
        this file's with ``prefix`` on their names and those references, as MuJoCo 4.0.0 compiles them (measured);
        those naming an element left behind (another body than ``body``) are left out, as MuJoCo leaves them, and
        said."""
        attached = {n.get("name") for h in held for n in h.iter() if n.get("name")}
        known = {n.get("name") for w in root.findall("worldbody") for n in w.iter() if n.get("name")}
        for tag in ("equality", "tendon"):
            for e in (e for s in root.findall(tag) for e in s.children):
                named = _references(e, known)
                if not named <= attached:
                    self.notes.append(f"{e.place}: the attached model's <{e.tag}> names "
                                      f"{', '.join(sorted(named - attached))}, which {node.place} does not attach: "
                                      "left out, as MuJoCo leaves it out")
                    continue
                section = self.root.find(tag)
                if section is None:
                    section = Node(tag, {}, node.file, node.line, [])
                    self.root.children.append(section)
                section.children.append(_referring(e, named, prefix, before=True))

    def _body(self, node: Node, parent: int, at: np.ndarray, R: np.ndarray, childclass: str) -> None:
        name = node.get("name") or f"body {len(self.bodies) + 1}"  # MuJoCo's index: the world is body 0
        if ("body", name) in self.places:
            raise ModelError(f"{node.place}: a second body named {name!r} (the first: {self.places[('body', name)]})")
        self.places[("body", name)] = node.place
        compensated = number(node, "gravcomp", 0.0)
        if compensated:
            self.gravcomp[name] = compensated
        cls = node.get("childclass") or childclass
        pos, Rb = self.pose(node)
        pos, Rb = at + R @ pos, R @ Rb
        index = len(self.bodies)
        joints = self._joints(node, cls, name, pos, Rb)
        if "first_body_unplaced" in self.variant and parent == -1 and not joints and node is self.first_body:
            pos, Rb = np.zeros(3), np.eye(3)
        if node.get("mocap") == "true" and joints:
            raise ModelError(f"{node.place}: mocap body {name!r} has joints; MuJoCo's mocap bodies have none")
        mass, com, I = self._mass(node, cls, name)
        found = physical.check(name, mass, I, self.places.get(("inertial", name), node.place),
                               written=self.written.get(name, 0.0))
        self.findings += found
        self.bodies.append(Body(name, parent, pos=pos, quat=frames.quaternion_of(Rb), joints=tuple(joints), mass=mass,
                                com=com, inertia=I, written=self.written.get(name, 0.0),
                                physical=not any(f.condition != "no mass but an inertia" for f in found)))
        self._sites(node, index, np.zeros(3), np.eye(3), cls)
        self._children(node, index, np.zeros(3), np.eye(3), cls)

    @staticmethod
    def _has_joint(node: Node) -> bool:
        return any(c.tag in ("joint", "freejoint") for c in node.children)

    def _sites(self, node: Node, body: int, at, R, cls) -> None:
        for child in node.children:
            if child.tag == "site":
                self._site(child, body, at, R, cls)
            elif child.tag == "frame":
                pos, Rf = self.pose(child)
                self._sites(child, body, at + R @ pos, R @ Rf, child.get("childclass") or cls)

    def _site(self, node, body, at, R, cls) -> None:
        site = self.attrs(node, cls)
        name = site.get("name")
        if not name or name in {p.name for p in self.points}:
            return  # an unnamed site cannot be asked for; MuJoCo refuses a repeated name
        self.points.append(Point(name, body, at + R @ np.array(numbers(site, "pos", 3, [0.0, 0.0, 0.0]))))

    def _elements(self, node: Node, tag: str, cls: str, at=None, R=None):
        """``(element with defaults, its frame's (at, R) in the body)`` of every ``tag`` in the body, frames
        included."""
        at = np.zeros(3) if at is None else at
        R = np.eye(3) if R is None else R
        for child in node.children:
            if child.tag == tag or (tag == "joint" and child.tag == "freejoint"):
                yield self.attrs(child, cls), at, R
            elif child.tag == "frame":
                pos, Rf = self.pose(child)
                yield from self._elements(child, tag, child.get("childclass") or cls, at + R @ pos, R @ Rf)

    def _joints(self, node: Node, cls: str, body: str, body_pos=None, Rb=None) -> list[Joint]:
        """The body's joints; ``body_pos``, ``Rb``: its frame in its parent's (for Drake's stacked-joint reading)."""
        out = []
        elements = list(self._elements(node, "joint", cls))
        several = len(elements) > 1 and body_pos is not None and bool(np.any(body_pos != 0))
        self.stacked += several
        stacked = "stacked_joints_in_parent" in self.variant and several
        for k, (j, at, R) in enumerate(elements):
            if stacked and k < len(elements) - 1:  # Drake's: pos and axis taken in the parent's frame
                at, R = Rb.T @ (at - body_pos), Rb.T @ R
            kind = "free" if j.tag == "freejoint" else j.get("type", "hinge")
            if kind not in ("free", "ball", "slide", "hinge"):
                raise ModelError(f"{j.place}: joint type {kind!r}; MJCF's are free, ball, slide, hinge")
            name = j.get("name") or f"joint {self.njoints}"  # MuJoCo's index among the model's joints
            if ("joint", name) in self.places:
                first = self.places[("joint", name)]
                raise ModelError(f"{j.place}: a second joint named {name!r} (the first: {first})")
            self.njoints += 1
            self.places[("joint", name)] = j.place
            nv = {"free": 6, "ball": 3}.get(kind, 1)
            frictionloss = number(j, "frictionloss", 0.0)
            if frictionloss:
                self.friction.append(name)
                self.frictionloss[name] = frictionloss
            armature = number(j, "armature", 0.0)
            if armature and name not in self.driven:
                self.unactuated += 1
                if "armature_without_actuator" in self.variant:
                    armature = 0.0
            damping = number(j, "damping", 0.0)
            if j.get("springdamper") is not None and all(x > 0 for x in required_numbers(j, "springdamper", 2)):
                springref = number(j, "springref", 0.0) * (self.angle(1.0) if kind == "hinge" else 1.0)
                self.springdamper[name] = (*required_numbers(j, "springdamper", 2), springref)
            if kind == "free" and damping:
                self.damped_free += 1
                if "free_damping_dropped" in self.variant:
                    damping = 0.0
            if kind == "ball" and damping:
                self.damped_balls += 1
                if "ball_damping_dropped" in self.variant:
                    damping = 0.0
            if damping:
                self.damping[name] = np.full(nv, damping)
            if kind == "free":
                out.append(Joint.free(name, armature=armature))
                continue
            pos = at + R @ np.array(numbers(j, "pos", 3, [0.0, 0.0, 0.0]))
            scale = self.angle(1.0) if kind in ("hinge", "ball") else 1.0
            stiffness = number(j, "stiffness", 0.0)
            if stiffness:
                self.stiffness[name] = (stiffness, number(j, "springref", 0.0) * (scale if kind == "hinge" else 1.0))
            rng = numbers(j, "range", 2)
            limited = j.get("limited", "auto")
            if rng is not None and kind in ("hinge", "slide") and (limited == "true" or (
                    limited == "auto" and self.autolimits)) and rng[0] < rng[1]:
                self.ranges[name] = (rng[0] * scale, rng[1] * scale)
            per_dof = np.full(nv, armature)  # one armature for each of the joint's speeds
            if kind == "ball":
                out.append(Joint.ball(name, pos=pos, armature=per_dof))
                continue
            axis = R @ self.normalized.unit("joint axis", numbers(j, "axis", 3, [0.0, 0.0, 1.0]), j.place)
            ref = number(j, "ref", 0.0) * (scale if kind == "hinge" else 1.0)
            joint = Joint.hinge(name, axis, pos=pos, ref=ref, armature=per_dof) if kind == "hinge" else \
                Joint(name, "slide", pos=pos, axis=axis, ref=ref, armature=per_dof)
            out.append(joint)
        return out

    # ---- mass properties -------------------------------------------------------------------------------------
    def _mass(self, node: Node, cls: str, body: str) -> tuple[float, np.ndarray, np.ndarray]:
        """``(mass, mass centre (3,), inertia about it (3, 3))`` in the body's frame, before the compiler's bounds."""
        inertial = node.find("inertial")
        if inertial is not None and self.fromgeom != "true":
            self.places[("inertial", body)] = inertial.place
            pos, R = self.pose(inertial)
            mass = number(inertial, "mass")
            if mass is None:
                raise ModelError(f"{inertial.place}: <inertial> without a mass")
            full, diag = numbers(inertial, "fullinertia", 6), numbers(inertial, "diaginertia", 3)
            if full is not None and diag is not None:
                raise ModelError(f"{inertial.place}: <inertial> gives diaginertia and fullinertia: one of them "
                                 "(MuJoCo's compiler refuses both)")
            if full is None and diag is None:  # MJCF's reference asks for one; MuJoCo's compiler reads no inertia as 0
                self.notes.append(f"{inertial.place}: <inertial> of {body} gives no inertia (neither diaginertia nor "
                                  "fullinertia): read as zero, as MuJoCo's compiler reads it")
                self.inertia_less += 1
                diag = [1.0, 1.0, 1.0] if "inertial_unit_inertia" in self.variant else [0.0, 0.0, 0.0]
            turned = [k for k in ("quat", "axisangle", "euler", "xyaxes", "zaxis") if inertial.get(k) is not None]
            if full is not None and turned:
                raise ModelError(f"{inertial.place}: <inertial> gives fullinertia and {turned[0]}: the full tensor is "
                                 "in the body's frame, and MJCF allows no orientation with it")
            key = "fullinertia" if full is not None else "diaginertia"
            digits = rounding(inertial, key)  # the file's own rounding of each entry (off-diagonals twice)
            self.written[body] = float(np.sqrt(sum(d * d * (1 if k < 3 else 2) for k, d in enumerate(digits))))
            if full is not None:
                xx, yy, zz, xy, xz, yz = full
                I = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
            else:
                I = np.diag(np.asarray(diag, dtype=float))
            I = R @ I @ R.T
            return mass, pos, 0.5 * (I + I.T)
        if self.fromgeom == "false":
            return 0.0, np.zeros(3), np.zeros((3, 3))
        parts, meshy, solid, solid_mesh = [], [], [], False
        for g, at, R in self._elements(node, "geom", cls):
            part = self._geom(g, at, R, body)
            if part is None:
                continue
            parts.append(part[:3])
            if part[3]:
                self.mesh_body_names.add(body)
            if part[4]:
                meshy.append(part[3])
            if not (number(g, "contype", 1) == 0 and number(g, "conaffinity", 1) == 0):  # Pinocchio's own sum
                solid_mesh = solid_mesh or bool(part[3])
                solid.append(part[:3] if not part[3] else
                             (1.0, at + R @ np.array(numbers(g, "pos", 3, [0.0, 0.0, 0.0])), np.eye(3)))
        if "mesh_unit_inertia" in self.variant and solid_mesh:
            return inertia.combine(solid)
        if meshy:
            self.taken[body] = f"inertia from {', '.join(meshy)}: computed by MuJoCo, not by relacc"
        return inertia.combine(parts)

    def _geom(self, g: Node, at, R, body: str):
        """``(mass, centre, inertia (3, 3), mesh or "")`` of one geom in the body frame, or None when it adds none."""
        kind = g.get("type", "mesh" if g.get("mesh") else "sphere")
        if kind not in GEOM_TYPES:
            raise ModelError(f"{g.place}: geom type {kind!r}; MJCF's are {', '.join(GEOM_TYPES)}")
        if not self.variant:  # MuJoCo's refusals; a variant reproduces another engine, which may read it (Drake's
            _check_geom(g, kind)  # broken default chain leaves a geom without its class's size)
        group = int(number(g, "group", 0))
        if not self.groups[0] <= group <= self.groups[1]:
            self.group_excluded += 1
            if "inertiagrouprange_ignored" not in self.variant:
                return None
        visual = number(g, "contype", 1) == 0 and number(g, "conaffinity", 1) == 0
        if visual and self.discardvisual:
            return None
        if visual:
            self.visual_geoms += 1
            if "visual_geoms_ignored" in self.variant:
                return None
        if kind in ("plane", "hfield"):
            return None  # no volume: MuJoCo allows them in static bodies only, with no mass
        shell = g.get("shellinertia") == "true"
        mass_given = number(g, "mass")
        if g.get("_default_mass"):
            self.default_masses += 1
        if mass_given == 0 and kind in ("mesh", "sdf"):  # 0 kg: no mass properties to take from anyone
            return None
        if kind in ("mesh", "sdf") or g.get("mesh"):  # a mesh, or a primitive MuJoCo fits to a mesh
            if self.meshes is None:
                raise ModelError(f"{g.place}: body {body!r} takes mass properties from a mesh geom, which relacc does "
                                 "not compute; give the body an <inertial>, or read the file with a mesh reader")
            name = g.get("mesh")
            asset = self.assets.get(name)
            asset = None if asset is None else self.attrs(asset, asset.get("class") or "main")
            if asset is not None and asset.get("file"):  # what the mesh is read from: an input of the command, and a
                found = mesh_file(self.path, self.meshdir, asset)  # a regular file (a FIFO would hang the read)
                note_input(found)
                try:
                    regular_file(found, ModelError, "mesh file")
                except ModelError as exc:
                    raise ModelError(f"{asset.place}: <mesh file={asset.get('file')!r}>: {exc}") from None
            self.mesh_geoms += 1
            own = self._own_mesh(g, kind, asset, mass_given, body)
            if own is not None:
                mass, com, I = own
                return mass, at + R @ com, R @ I @ R.T, f"mesh {name!r}", False
            mass, com, I = self.meshes(MeshGeom(str(self.path), g, asset, self.meshdir, self.degree, dict(g.attrib)))
            return mass, at + R @ np.asarray(com), R @ np.asarray(I) @ R.T, f"mesh {name!r}", True
        size = numbers(g, "size", None, [0.0, 0.0, 0.0])
        size = list(size) + [0.0] * (3 - len(size))
        pos, Rg = self.pose(g)
        fromto = numbers(g, "fromto", 6)
        if fromto is not None:
            if kind not in ("capsule", "cylinder", "box", "ellipsoid"):
                raise ModelError(f"{g.place}: fromto is for capsules, cylinders, boxes and ellipsoids, not {kind}s")
            a, b = np.array(fromto[:3]), np.array(fromto[3:])
            half = float(np.linalg.norm(b - a)) / 2
            if half == 0:
                raise ModelError(f"{g.place}: fromto with both ends at one point")
            pos, Rg = (a + b) / 2, frames.zaxis(b - a, frames.Normalized(), g.place)
            if kind in ("capsule", "cylinder"):
                size[1] = half
            else:  # a box's or ellipsoid's cross-section: both half-sizes are the first size (MuJoCo's reading)
                size[1], size[2] = size[0], half
        try:
            measure, moments = inertia.shape(kind, size, shell)
        except inertia.NoClosedForm as what:
            raise ModelError(f"{g.place}: relacc has no closed form for {what}; give body {body!r} an "
                             "<inertial>") from None
        mass = mass_given if mass_given is not None else number(g, "density", 1000.0) * measure
        Rw = R @ Rg
        return mass, at + R @ pos, Rw @ np.diag(mass * moments) @ Rw.T, "", False

    def _own_mesh(self, g: Node, kind: str, asset, mass_given, body: str):
        """``(mass kg, centre (3,) m, inertia about it (3, 3) kg m^2)`` of a mesh geom of ``body``, in the frame it is
        placed in (its body's, or the ``<frame>`` holding it), computed by relacc
        (:mod:`relacc.reading.mesh`), or None where relacc leaves it to MuJoCo (a primitive fitted to a mesh, a
        builtin mesh, a convex hull limited by ``maxhullvert``).

        Raises:
            ModelError: ``shellinertia`` on a mesh geom (MuJoCo's compiler refuses it: a mesh's inertia mode is its
                asset's), a mesh file that cannot be read, a volume or area MuJoCo refuses.
        """
        from relacc.reading import mesh

        if g.get("shellinertia") is not None:
            raise ModelError(f"{g.place}: shellinertia on a mesh geom: MuJoCo's compiler refuses it (a mesh's inertia "
                             "is its asset's inertia=\"legacy|exact|convex|shell\")")
        mode = "legacy" if asset is None else asset.get("inertia", "legacy")
        if mode == "legacy":
            self.legacy_meshes += 1
        if "mesh_inertia_exact" in self.variant and mode != "shell":
            mode = "exact"
        if kind != "mesh" or asset is None or asset.get("builtin") or (asset.get("maxhullvert") and mode == "convex") \
                or not (asset.get("file") or asset.get("vertex")):
            return None
        place = asset.place
        if asset.get("file"):
            path = mesh_file(self.path, self.meshdir, asset)
            vertices, objects = mesh.cached(path, place, quads="mesh_inertia_exact" not in self.variant)
            if len(objects) > 1:
                self.multi_object_meshes.append(asset.get("file"))
            kept = objects[:1] if "mesh_obj_first_object" in self.variant else objects
            faces = np.concatenate(kept) if kept else np.zeros((0, 3), dtype=np.int64)
        else:
            vertices = np.asarray(numbers(asset, "vertex"), dtype=np.float32).astype(np.float64).reshape(-1, 3)
            faces = np.asarray(numbers(asset, "face", None, []), dtype=np.int64).reshape(-1, 3)
        vertices = mesh.transformed(vertices, numbers(asset, "refpos", 3, [0.0, 0.0, 0.0]),
                                    numbers(asset, "refquat", 4, [1.0, 0.0, 0.0, 0.0]),
                                    numbers(asset, "scale", 3, [1.0, 1.0, 1.0]))
        if "mesh_inertia_exact" in self.variant and mode == "exact":
            props = mesh.exact_or_hull(vertices, faces, place)
        else:
            props = mesh.mass_properties(vertices, faces, mode, place)
        mass = mass_given if mass_given is not None else number(g, "density", 1000.0) * props.measure
        pos, Rg = self.pose(g)
        inertia_geom = mass / props.measure * props.inertia
        largest = float(np.abs(inertia_geom).max())
        # single precision vertices: what they allow the inertia is added to the body's written allowance, as a
        # written inertia's digits are (the physical checks')
        self.written[body] = self.written.get(body, 0.0) + VERTEX_ROUNDING * largest
        # kg/m^3 and kg m^2: what an engine's tolerances on the unit-density tensor scale with
        self.mesh_density[body] = self.mesh_density.get(body, 0.0) + abs(mass / props.measure)
        self.mesh_inertia[body] = self.mesh_inertia.get(body, 0.0) + largest
        return mass, pos + Rg @ props.com, Rg @ inertia_geom @ Rg.T

    def _compiler_masses(self) -> None:
        """``boundmass``, ``boundinertia``, ``balanceinertia``, ``settotalmass`` (module docstring)."""
        boundmass = self._compiler_numbers("boundmass", [0.0])[0]
        boundinertia = self._compiler_numbers("boundinertia", [0.0])[0]
        balance = self.compiler.get("balanceinertia", "false") == "true"
        total = self._compiler_numbers("settotalmass", [-1.0])[0]
        if "settotalmass_ignored" in self.variant:
            total = -1.0
        if not (boundmass > 0 or boundinertia > 0 or balance or total > 0):
            return
        changed = []
        for b in self.bodies:
            mass, I = b.mass, np.array(b.inertia)
            if boundmass > 0:
                mass = max(mass, boundmass)
            if boundinertia > 0 or balance:
                w, V = np.linalg.eigh(I)
                if boundinertia > 0:
                    w = np.maximum(w, boundinertia)
                if balance and w[0] + w[1] < w[2]:
                    w = np.full(3, w.mean())
                I = V @ np.diag(w) @ V.T
            changed.append([mass, 0.5 * (I + I.T)])
        if total > 0:
            scale = total / sum(m for m, _ in changed) if sum(m for m, _ in changed) > 0 else 1.0
            changed = [[m * scale, I * scale] for m, I in changed]
        self.bodies = [Body(b.name, b.parent, pos=b.pos, quat=b.quat, joints=b.joints, mass=m, com=b.com, inertia=I,
                            physical=b.physical) for b, (m, I) in zip(self.bodies, changed)]

    def _couplings(self) -> tuple:
        """A :class:`relacc.reading.model.Coupling` per active ``<equality><joint>``: MuJoCo's ``q1 - q1_0 =
        polycoef(q2 - q2_0)``, ``q_0`` each joint's ``ref``, its constant and linear terms made absolute (``offset =
        q1_0 + c0 - c1 q2_0``, ``multiplier = c1``), the higher ones as written."""
        refs = {j.name: j.ref for b in self.bodies for j in b.joints}
        out = []
        for s in self.root.findall("equality"):
            for e in s.children:
                if e.tag != "joint" or e.get("active", "true") == "false" or e.get("joint1") not in refs:
                    continue
                given = numbers(e, "polycoef", None, [])
                if len(given) > 5:
                    raise ModelError(f"{e.place}: <joint> polycoef={e.get('polycoef')!r} has {len(given)} numbers; "
                                     "at most 5 (MuJoCo refuses more)")
                c = given + [0.0, 1.0, 0.0, 0.0, 0.0][len(given):]  # the ones not written: the default's (MuJoCo)
                leader = e.get("joint2")
                y0, x0 = refs[e.get("joint1")], refs.get(leader, 0.0) if leader else 0.0
                out.append(Coupling(e.get("joint1"), leader, y0 + c[0] - (c[1] * x0 if leader else 0.0),
                                    c[1] if leader else 0.0, tuple(c[2:]) if leader else (0.0, 0.0, 0.0),
                                    "equality", e.place))
        return tuple(out)

    def _unevaluated(self, coupled: int) -> list[tuple[str, str]]:
        """``[(kind, line)]``: what the file has that the comparisons leave out, one line per kind
        (:data:`relacc.reading.model.UNEVALUATED_KINDS`); ``coupled``: how many of its equalities are couplings
        (:meth:`_couplings`): the equalities' kind is ``coupling`` where all of them are."""
        out = []
        equality = [e for s in self.root.findall("equality") for e in s.children]
        if equality:
            kinds = sorted({e.tag for e in equality})
            out.append(("coupling" if coupled == len(equality) else "constraint",
                        f"{len(equality)} equality constraint{'s' if len(equality) > 1 else ''} ({', '.join(kinds)}): "
                        "the comparisons are the tree's without constraints"))
        tendons = [t for s in self.root.findall("tendon") for t in s.children]
        if tendons:
            out.append(("tendon", f"{len(tendons)} tendon{'s' if len(tendons) > 1 else ''}: their lengths, springs "
                        "and dampers are not evaluated"))
        dynamic = [a for s in self.root.findall("actuator") for a in s.children
                   if a.tag in DYNAMIC_ACTUATORS or (a.tag == "general" and a.get("dyntype", "none") != "none")]
        if dynamic:
            out.append(("actuator", f"{len(dynamic)} actuator{'s' if len(dynamic) > 1 else ''} with activation "
                        "dynamics: their states are not evaluated"))
        compensated = list(self.gravcomp)
        if compensated:
            n = len(compensated)
            out.append(("gravcomp", f"gravity compensation (gravcomp) on {n} bod{'ies' if n > 1 else 'y'} "
                        f"({', '.join(compensated[:5])}{', ...' if n > 5 else ''}): a force MuJoCo's "
                        "step applies against gravity, not evaluated (the dynamics compared are the bodies' own)"))
        fluid = [f"{k} {o.get(k)}" for o in self.root.findall("option") for k in ("density", "viscosity", "wind")
                 if any(x != 0 for x in (numbers(o, k) or []))]
        fluid += [f"fluidshape on {g.get('name') or 'a geom'}" for g in self.root.iter("geom")
                  if g.get("fluidshape", "none") != "none"]
        if fluid:
            out.append(("fluid", f"fluid forces ({', '.join(fluid)}): MuJoCo's step applies them, not evaluated"))
        if self.friction:
            n = len(self.friction)
            out.append(("friction", f"dry friction (frictionloss) on {n} joint{'s' if n > 1 else ''} "
                        f"({', '.join(self.friction[:5])}{', ...' if n > 5 else ''}): a constraint in MuJoCo's step, "
                        "not evaluated"))
        return out


def _sensitivity(tree: Tree, k, Minv: np.ndarray) -> np.ndarray:
    """``(nv,)``: :func:`relacc.core.tolerances.inverse_diagonal_sensitivity` of the tree at its reference
    configuration (``k`` its kinematics there): :attr:`relacc.reading.Reading.sensitivity`."""
    from relacc.core.tolerances import inverse_diagonal_sensitivity

    moves = np.zeros((len(tree.bodies), tree.nv), dtype=bool)
    for b, dofs in enumerate(tree.path_dofs):
        moves[b, list(dofs)] = True
    rotational = np.zeros(tree.nv, dtype=bool)
    for (_, joint), d in zip(tree.joints, tree.dofadr):
        rotational[d:d + joint.nv] = {"hinge": [True], "slide": [False], "ball": [True] * 3,
                                      "free": [False] * 3 + [True] * 3}[joint.type]
    return inverse_diagonal_sensitivity(Minv, moves, rotational, np.array([b.mass for b in tree.bodies]),
                                        np.array([np.linalg.norm(b.inertia, 2) for b in tree.bodies]),
                                        max([float(np.linalg.norm(p)) for p in k.position] + [1e-3]))
