"""A URDF read by relacc itself, by the URDF specification (wiki.ros.org/urdf/XML), into a :class:`Reading`.

* ``<link>``: a body. Its ``<inertial>`` gives its mass (``<mass value>``), its mass centre (``<origin xyz>``) and its
  inertia about that centre (``<inertia ixx ixy ixz iyy iyz izz>``) in the frame of the inertial's ``<origin rpy>``,
  turned here into the link's components: ``I_link = R I R^T``. No ``<inertial>``: a massless link. ``<visual>`` and
  ``<collision>`` are geometry for drawing and contact and have no part in the dynamics.
* ``<joint>``: the child link's frame is the parent link's moved by the joint's ``<origin xyz rpy>`` (rpy: fixed-axis
  roll, pitch, yaw), then by the joint: ``revolute`` and ``continuous`` a hinge, ``prismatic`` a slide, along
  ``<axis xyz>`` (joint frame, default ``1 0 0``; a direction: normalized as the engines do, and noted);
  ``floating`` a free joint; ``fixed`` welds the child to the parent (relacc keeps it a body of its own, without
  joints); ``spherical`` (not in the specification; MuJoCo's URDF reader and pybullet read it) a ball joint about the
  joint frame's origin, noted. ``<limit lower upper>`` bounds revolute and prismatic joints (random states are drawn
  inside); ``<dynamics damping>`` is a damper. ``planar`` joints are refused (relacc has no planar joint).
* The root link (the one that is no joint's child) is welded to the world, as MuJoCo, Pinocchio and Drake read a
  URDF by default; a root link named ``world`` is the world itself, and a joint may name ``world`` as its parent
  without a link of that name (the world, as Gazebo and Drake read it).
* Bodies are ordered depth first from the root, children in the order of their joints in the file.
* A link's ``<inertial>`` with more than one ``<inertia>`` (deep_robotics' Lite3: two, their products of inertia of
  opposite signs), or a link with more than one ``<inertial>`` (mani_skill's TriFinger Pro: its fingertips), is read
  by the first, as urdfdom (Pinocchio's and ROS's parser), Drake and PyBullet read it, and noted; MuJoCo refuses such
  a file ("repeated element"), iDynTree reads the last (:data:`VARIANTS`).
* ``<mimic>`` couples a joint to another: a constraint, which relacc's comparisons (the tree without constraints,
  every joint free) leave out: said in ``unevaluated``. ``<transmission>`` and ``<gazebo>`` have no part in the
  dynamics compared.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from relacc.core.tree.model import Body, Joint, Tree
from relacc.errors import ModelError, NotARobot
from relacc.files import note_input
from relacc.reading import frames, physical
from relacc.reading.model import Coupling, Reading
from relacc.reading.packages import package_folders
from relacc.reading.xacro import is_xacro
from relacc.reading.xml import Node, number, numbers, parse_file, parse_text, rounding

VARIANTS = ("last_inertia",)
"""Engines' ways of reading a URDF that relacc's reader can follow (``read(path, variant)``, the audit's known
readings): ``last_inertia``, the last of a link's repeated ``<inertial>`` and ``<inertia>`` elements instead of the
first (iDynTree)."""

GRAVITY = (0.0, 0.0, -9.81)
"""m/s^2: the gravity relacc gives a URDF, which has none (as MuJoCo, Pinocchio and Drake read one)."""

JOINTS = {"revolute": "hinge", "continuous": "hinge", "prismatic": "slide", "floating": "free", "fixed": None,
          "spherical": "ball"}
"""URDF joint types and relacc's joint of each (``fixed``: none, the child is welded; ``spherical``: not the
specification's, MuJoCo's and pybullet's extension, a ball about the joint frame's origin as MuJoCo reads it)."""


def resolve_uri(uri: str, path: Path) -> Path | None:
    """The file a URDF at ``path`` names by ``uri`` (a ``<mesh filename>``), where it can be found: a relative name
    from the URDF's directory, ``file://`` as it says, ``package://PKG/REST`` in the nearest of ``PKG``'s
    folders that has it (:func:`relacc.reading.packages.package_folders`: ROS's
    layout, without ROS); None when it is not found."""
    if uri.startswith("file://"):
        target = Path(uri[len("file://"):])
        return target if target.is_file() else None
    if uri.startswith("package://"):
        package, _, rest = uri[len("package://"):].partition("/")
        return next((folder / rest for folder in package_folders(package, path) if (folder / rest).is_file()), None)
    if "://" in uri:
        return None
    target = path.parent / uri
    return target if target.is_file() else None


def note_files(path: Path) -> None:
    """The files the URDF at ``path`` names, noted as inputs (:func:`relacc.reading.read.note_files`); a xacro's are
    its expansion's, and the files it includes (noted by :func:`relacc.reading.xacro.expand`)."""
    from relacc.reading.xacro import expand, is_xacro

    if is_xacro(path):
        _note_geometry(parse_text(expand(path), str(path), []), path)
        return
    _note_geometry(parse_file(path), path)


def _xacro_root(path: Path, notes: list) -> Node:
    """The root of a xacro file's expansion (:mod:`relacc.reading.xacro`), each link and joint placed in the source
    by its ``name`` (:func:`relacc.reading.xacro.source_places`: in the xacro file or one it includes), the elements
    inside it with it; one that cannot be placed in the xacro file without a line (said once in ``notes``)."""
    from relacc.reading.xacro import expansion, source_places

    note_input(path)
    text, included = expansion(path)
    root = parse_text(text, str(path), notes)
    find = source_places([path, *included])
    unplaced = 0

    def place(node: Node, at: tuple[str, int]) -> None:  # an element inside a link or joint goes with it
        node.file, node.line = at
        for child in node.children:
            place(child, at)

    root.file, root.line = find("robot", root.get("name") or "") or (str(path), 0)
    for node in root.children:  # a robot's links and joints (a <transmission>'s <joint> goes with it)
        at = find(node.tag, node.get("name") or "", node.get("type")) if node.tag in ("link", "joint") else None
        unplaced += at is None and node.tag in ("link", "joint")
        place(node, at or (str(path), 0))
    which = "1 link or joint" if unplaced == 1 else f"{unplaced} links and joints"
    notes.append(f"{path}: expanded by xacro" + (f"; {which} could not be placed in its source by name: placed in the "
                                                  "file without a line" if unplaced else ""))
    return root


def _note_geometry(root: Node, path: Path) -> None:
    """The files the geometry names (``<mesh filename>``, ``<texture filename>``) that can be found: inputs of the
    running command, which no output may replace."""
    for node in root.iter():
        if node.tag in ("mesh", "texture") and node.get("filename"):
            target = resolve_uri(node.get("filename"), path)
            if target is not None:
                note_input(target)


def read(path, variant: frozenset = frozenset()) -> Reading:
    """relacc's reading of the URDF at ``path`` (module docstring), the way ``variant`` says (:data:`VARIANTS`).

    Raises:
        ModelError: the file cannot be read, is not a URDF, or describes no tree (a link twice a child, a joint
            naming a missing link, a loop, a planar joint): the message names the element and its line.
    """
    path = Path(path)
    notes: list[str] = []
    root = _xacro_root(path, notes) if is_xacro(path) else parse_file(path, notes)
    if root.tag != "robot":
        raise ModelError(f"{root.place}: the root element is <{root.tag}>; a URDF's is <robot>")
    _note_geometry(root, path)
    normalized = frames.Normalized()
    links = {}
    for link in root.findall("link"):
        name = link.get("name")
        if not name:
            raise ModelError(f"{link.place}: a <link> without a name")
        if name in links:
            raise ModelError(f"{link.place}: a second link named {name!r} (the first: {links[name].place})")
        links[name] = link
    if not links:
        raise NotARobot(f"{root.place}: the URDF has no <link>" + (" (a xacro file of macros for others to include)"
                                                                   if is_xacro(path) else ""))
    joints, parent_of, children = {}, {}, {name: [] for name in links}
    for joint in root.findall("joint"):
        name, kind = joint.get("name"), joint.get("type")
        if not name:
            raise ModelError(f"{joint.place}: a <joint> without a name")
        if name in joints:
            raise ModelError(f"{joint.place}: a second joint named {name!r}")
        if kind == "planar":
            raise ModelError(f"{joint.place}: joint {name!r} is planar; relacc reads revolute, continuous, prismatic, "
                             "floating and fixed joints")
        if kind not in JOINTS:
            raise ModelError(f"{joint.place}: joint {name!r} has type {kind!r}; accepted: {', '.join(JOINTS)}")
        parent, child = _link_of(joint, "parent"), _link_of(joint, "child")
        if parent == "world" and "world" not in links:  # the world named without a link (Gazebo's, Drake's usage)
            links["world"] = Node("link", {"name": "world"}, joint.file, joint.line)
            children["world"] = []
        for end in (parent, child):
            if end not in links:  # in a xacro, a piece of a robot: the xacro that includes it defines the link
                fragment = is_xacro(path)
                raise (NotARobot if fragment else ModelError)(
                    f"{joint.place}: joint {name!r} names link {end!r}, which the file does not define"
                    + (" (a xacro fragment for another xacro to include)" if fragment else ""))
        if child in parent_of:
            raise ModelError(f"{joint.place}: link {child!r} is the child of two joints ({parent_of[child][0]!r} "
                             f"and {name!r}): a URDF is a tree")
        joints[name] = joint
        parent_of[child] = (name, parent)
        children[parent].append(child)
    roots = [name for name in links if name not in parent_of]
    if len(roots) != 1:
        raise ModelError(f"{path}: a URDF has one root link (no joint's child); this one has "
                         f"{len(roots)}: {', '.join(roots) or 'none (a loop)'}")
    order = _depth_first(roots[0], children)
    if len(order) != len(links):
        lost = sorted(set(links) - set(order))
        raise ModelError(f"{path}: links {', '.join(lost)} are not reachable from the root {roots[0]!r} (a loop)")
    world = roots[0] == "world"
    index: dict[str, int] = {}
    bodies, places, ranges, damping, findings, turned, friction = [], {}, {}, {}, [], {}, {}
    geometry = {name: link_geometry(links[name], path, normalized) for name in order}
    unevaluated, kinds = [], []
    mimics = [j.get("name") for j in joints.values() if j.find("mimic") is not None and j.get("type") != "fixed"]
    couplings = tuple(Coupling(name, mimic.get("joint"), number(mimic, "offset", 0.0), number(mimic, "multiplier", 1.0),
                               place=joints[name].place)
                      for name in mimics for mimic in [joints[name].find("mimic")])
    if mimics:
        unevaluated.append(f"{len(mimics)} mimic joint{'s' if len(mimics) > 1 else ''} ({', '.join(mimics)}): "
                           "a constraint coupling joints; the comparisons are the tree's without constraints, every "
                           "joint free")
        kinds.append("coupling")
    fixed_mimics = [j.get("name") for j in joints.values() if j.find("mimic") is not None and j.get("type") == "fixed"]
    if fixed_mimics:  # a fixed joint has no coordinate to couple: nothing is freed
        notes.append(f"{len(fixed_mimics)} fixed joint{'s' if len(fixed_mimics) > 1 else ''} with a <mimic> "
                     f"({', '.join(fixed_mimics[:3])}{' ...' if len(fixed_mimics) > 3 else ''}): a fixed joint has no "
                     "coordinate to couple; the mimic is read as nothing")
    loops = root.findall("loop_joint")
    if loops:  # a closed chain's extra joint (an extension of the format some robots use): a constraint
        names = [lj.get("name") or "(unnamed)" for lj in loops]
        unevaluated.append(f"{len(loops)} loop joint{'s' if len(loops) > 1 else ''} ({', '.join(names[:5])}"
                           f"{', ...' if len(loops) > 5 else ''}): a constraint closing a loop; the comparisons are "
                           "the tree's without constraints")
        kinds.append("constraint")
    spherical = [j.get("name") for j in joints.values() if j.get("type") == "spherical"]
    if spherical:
        notes.append(f"{len(spherical)} spherical joint{'s' if len(spherical) > 1 else ''} ({', '.join(spherical[:3])}"
                     f"{' ...' if len(spherical) > 3 else ''}): not a URDF joint type; read as a ball about the joint "
                     "frame's origin, as MuJoCo's URDF reader does (urdfdom and Drake refuse it)")
    repeats: list[str] = []  # links with more than one <inertial>, or an <inertial> with more than one <inertia>
    for name in order:
        if world and name == roots[0]:
            continue  # a root link named world is the world
        link = links[name]
        places[("body", name)] = link.place
        pos, R, parent_index = np.zeros(3), np.eye(3), -1
        joint_list: tuple[Joint, ...] = ()
        if name in parent_of:
            jname, pname = parent_of[name]
            node = joints[jname]
            parent_index = index.get(pname, -1)  # the world's children: parent -1
            pos, R = _origin(node, normalized)
            places[("joint", jname)] = node.place
            kind = JOINTS[node.get("type")]
            if kind is not None:
                joint_list = (_joint(jname, kind, node, normalized),)
                lim = node.find("limit")
                if node.get("type") in ("revolute", "prismatic") and lim is not None:
                    lo, hi = number(lim, "lower", 0.0), number(lim, "upper", 0.0)
                    if lo < hi:
                        ranges[jname] = (lo, hi)
                dyn = node.find("dynamics")
                d = number(dyn, "damping", 0.0) if dyn is not None else 0.0
                if d:
                    damping[jname] = np.full(joint_list[0].nv, d)
                dry = number(dyn, "friction", 0.0) if dyn is not None else 0.0
                if dry:
                    friction[jname] = dry
        inertials = link.findall("inertial")
        if len(inertials) > 1 or any(len(x.findall("inertia")) > 1 for x in inertials):
            repeats.append(name)
        mass, com, inertia, where, written, digits = _inertial(link, normalized, "last_inertia" in variant)
        if written is not None:
            turned[name] = written
        if where:
            places[("inertial", name)] = where
        found = physical.check(name, mass, inertia, where or link.place, written=digits)
        findings += found
        index[name] = len(bodies)
        is_physical = not any(f.condition != "no mass but an inertia" for f in found)
        bodies.append(Body(name, parent_index, pos=pos, quat=frames.quaternion_of(R), joints=joint_list, mass=mass,
                           com=com, inertia=inertia, physical=is_physical, written=digits))
    if not bodies:
        raise ModelError(f"{path}: the URDF has no link besides the world")
    tree = Tree(root.get("name") or path.stem, tuple(bodies), gravity=np.array(GRAVITY), source=str(path))
    notes += normalized.notes("URDF")
    if repeats:
        notes.append(f"{len(repeats)} link{'s' if len(repeats) > 1 else ''} with more than one <inertial>, or "
                     f"<inertia> in its <inertial> ({', '.join(repeats[:5])}{', ...' if len(repeats) > 5 else ''}): "
                     "relacc reads the first, as urdfdom (Pinocchio, ROS) and Drake do; MuJoCo refuses the file, "
                     "iDynTree reads the last")
    return Reading(tree, "urdf", str(path), places, ranges, damping, {}, {}, tuple(unevaluated), tuple(notes),
                   tuple(findings), turned, facts={"geometry": geometry, "repeated_inertia": tuple(repeats)},
                   friction=friction, couplings=couplings, unevaluated_kinds=tuple(kinds), variant=frozenset(variant))


@dataclass(frozen=True)
class Shape:
    """One ``<collision>`` of a link: ``kind`` (``box``, ``sphere``, ``cylinder``, ``capsule``, ``mesh``), its
    ``<origin>`` in the link's frame (``xyz (3,)`` m, ``R (3, 3)``, ``rpy (3,)`` as written), ``size`` (box: its three
    edges; sphere: ``(r,)``; cylinder, capsule: ``(r, length)``; m), a mesh's file (None where it is not found) and
    ``scale (3,)``."""

    kind: str
    xyz: np.ndarray
    R: np.ndarray
    rpy: tuple
    size: tuple
    mesh: Path | None = None
    scale: tuple = (1.0, 1.0, 1.0)
    place: str = ""


@dataclass(frozen=True)
class LinkGeometry:
    """What a link's dynamics do not use but an engine may (``Reading.facts["geometry"]``): whether it has an
    ``<inertial>``, that inertial's origin (``xyz``, ``rpy`` as written, ``R``), and its collision shapes."""

    inertial: bool
    xyz: np.ndarray
    rpy: tuple
    R: np.ndarray
    shapes: tuple[Shape, ...]


def link_geometry(link: Node, path: Path, normalized) -> LinkGeometry:
    """A link's :class:`LinkGeometry` (its shapes of a kind not listed in :class:`Shape` left out)."""
    inertial = link.find("inertial")
    origin = inertial.find("origin") if inertial is not None else None
    rpy = tuple(numbers(origin, "rpy", 3, [0.0] * 3)) if origin is not None else (0.0, 0.0, 0.0)
    xyz, R = _origin(inertial, normalized) if inertial is not None else (np.zeros(3), np.eye(3))
    shapes = []
    for collision in link.findall("collision"):
        geometry = collision.find("geometry")
        if geometry is None or not geometry.children:
            continue
        g = geometry.children[0]
        o = collision.find("origin")
        c_xyz, c_R = _origin(collision, normalized)
        c_rpy = tuple(numbers(o, "rpy", 3, [0.0] * 3)) if o is not None else (0.0, 0.0, 0.0)
        if g.tag == "box":
            size: tuple = tuple(numbers(g, "size", 3, [0.0] * 3))
        elif g.tag == "sphere":
            size = (number(g, "radius", 0.0),)
        elif g.tag in ("cylinder", "capsule"):
            size = (number(g, "radius", 0.0), number(g, "length", 0.0))
        elif g.tag == "mesh":
            size = ()
            target = resolve_uri(g.get("filename") or "", path)
            shapes.append(Shape("mesh", c_xyz, c_R, c_rpy, size, target, tuple(numbers(g, "scale", 3, [1.0] * 3)),
                                g.place))
            continue
        else:
            continue
        shapes.append(Shape(g.tag, c_xyz, c_R, c_rpy, size, place=g.place))
    return LinkGeometry(inertial is not None, xyz, rpy, R, tuple(shapes))


def _link_of(joint: Node, end: str) -> str:
    node = joint.find(end)
    if node is None or not node.get("link"):
        raise ModelError(f"{joint.place}: joint {joint.get('name')!r} has no <{end} link=...>")
    return node.get("link")


def _depth_first(root: str, children: dict) -> list[str]:
    out, stack = [], [root]
    while stack:
        name = stack.pop()
        out.append(name)
        stack.extend(reversed(children[name]))
    return out


def _origin(node: Node, normalized) -> tuple[np.ndarray, np.ndarray]:
    """``(xyz (3,), R (3, 3))`` of an element's ``<origin>`` (zeros and the identity when absent)."""
    origin = node.find("origin")
    if origin is None:
        return np.zeros(3), np.eye(3)
    return np.array(numbers(origin, "xyz", 3, [0.0, 0.0, 0.0])), frames.rpy(*numbers(origin, "rpy", 3, [0.0] * 3))


def _joint(name: str, kind: str, node: Node, normalized) -> Joint:
    if kind == "free":
        return Joint.free(name)
    if kind == "ball":
        return Joint.ball(name)
    axis = node.find("axis")
    xyz = numbers(axis, "xyz", 3, [1.0, 0.0, 0.0]) if axis is not None else [1.0, 0.0, 0.0]
    unit = normalized.unit("joint axis", xyz, node.place)
    return Joint.hinge(name, unit) if kind == "hinge" else Joint.slide(name, unit)


def _inertial(link: Node, normalized, last: bool = False) -> tuple:
    """``(mass, mass centre (3,), inertia about it in the link's components (3, 3), place, the inertia as written
    when its origin turns it, else None, the Frobenius norm of the rounding its written digits allow (kg m^2))``;
    ``last``: of repeated ``<inertial>`` and ``<inertia>`` elements the last (variant ``last_inertia``), else the
    first."""
    inertials = link.findall("inertial")
    inertial = inertials[-1 if last else 0] if inertials else None
    if inertial is None:
        return 0.0, np.zeros(3), np.zeros((3, 3)), "", None, 0.0
    pos, R = _origin(inertial, normalized)
    tensors = inertial.findall("inertia")
    mass_node, tensor = inertial.find("mass"), (tensors[-1 if last else 0] if tensors else None)
    mass = number(mass_node, "value", 0.0) if mass_node is not None else 0.0
    I, digits = np.zeros((3, 3)), 0.0
    if tensor is not None:
        v = {k: number(tensor, k, 0.0) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        digits = float(np.sqrt(sum(d * d * (2 if k in ("ixy", "ixz", "iyz") else 1)
                                   for k in v for d in rounding(tensor, k))))
        I = np.array([[v["ixx"], v["ixy"], v["ixz"]], [v["ixy"], v["iyy"], v["iyz"]], [v["ixz"], v["iyz"], v["izz"]]])
    written = None if np.array_equal(R, np.eye(3)) else I
    I = R @ I @ R.T
    return mass, pos, 0.5 * (I + I.T), inertial.place, written, digits


