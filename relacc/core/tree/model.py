"""relacc's tree: bodies, joints and named points of any kinematic tree, placed as MuJoCo places them.

A :class:`Tree` is a list of :class:`Body` in MuJoCo's body order (parents first, the world left
out: parent ``-1``). Each body is placed in its parent's frame (``pos``, ``quat``) and then moved by
its joints, in order, exactly as MuJoCo's ``mj_kinematics`` moves it:

* ``free``: the body's pose is the coordinates themselves, ``[p (3), quat (4)]`` in the world;
* ``ball``: a rotation about the anchor ``pos`` (body frame), ``quat (4)`` relative to the frame
  the joint turns from;
* ``hinge``: a rotation by ``q - ref`` about ``axis`` through the anchor;
* ``slide``: a translation by ``q - ref`` along ``axis``.

A body without joints is welded to its parent; it keeps its own entry (so that indices are
MuJoCo's) and moves with the body it is welded to. Units: m, kg, kg m^2, rad.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np

from relacc.core.cases import fixed_vector
from relacc.core.tolerances import QUATERNION_NORM_TOLERANCE
from relacc.errors import InputError

JOINT_TYPES = ("free", "ball", "slide", "hinge")
"""Joint types, MuJoCo's names."""

NV = {"free": 6, "ball": 3, "slide": 1, "hinge": 1}
"""Speeds per joint type, in every case."""

NQ = {"free": 7, "ball": 4, "slide": 1, "hinge": 1}
"""Coordinates per joint type in cases 1 and 2 (quaternions); case 3 has :data:`NQ_ANGLES`."""

NQ_ANGLES = {"free": 6, "ball": 3, "slide": 1, "hinge": 1}
"""Coordinates per joint type in case 3 (each quaternion replaced by three 1-2-3 angles)."""

AXIS_TOLERANCE = QUATERNION_NORM_TOLERANCE
"""Largest accepted ``| |axis|^2 - 1 |``: axes are unit as given, never normalized."""



def _number(owner, name, value, minimum=None) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{owner}: {name} must be a real number, got {value!r:.80}")
    x = float(value)
    if not np.isfinite(x) or (minimum is not None and x < minimum):
        raise InputError(f"{owner}: {name} must be a finite number" + (f" >= {minimum}" if minimum is not None else "")
                         + f", got {x}")
    return x


@dataclass(frozen=True)
class Joint:
    """One joint of a body, in the body's frame.

    Attributes:
        name: unique in the tree. type: one of :data:`JOINT_TYPES`.
        pos: ``(3,)`` the anchor, body frame at the joint's zero, m (hinge and ball rotate about it).
        axis: ``(3,)`` unit axis, body frame (hinge, slide; ignored for ball and free).
        ref: the coordinate at which the body sits as placed (hinge rad, slide m; MuJoCo's ``ref``).
        armature: ``(nv,)`` rotor inertia added to the mass matrix's diagonal in MuJoCo's (case 2)
            speeds, kg m^2 or kg.
    """

    name: str
    type: str
    pos: np.ndarray = field(default_factory=lambda: np.zeros(3), repr=False)
    axis: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]), repr=False)
    ref: float = 0.0
    armature: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self):
        who = f"joint {self.name!r}"
        if not isinstance(self.name, str) or not self.name:
            raise InputError(f"joint name: expected a non-empty string, got {self.name!r}")
        if self.type not in JOINT_TYPES:
            raise InputError(f"{who}: unknown type {self.type!r}; accepted: {', '.join(JOINT_TYPES)}")
        object.__setattr__(self, "pos", fixed_vector(who, "pos", self.pos))
        axis = fixed_vector(who, "axis", self.axis)
        if self.type in ("hinge", "slide") and abs(float(axis @ axis) - 1) > AXIS_TOLERANCE:
            raise InputError(f"{who}: axis {axis.tolist()} has squared norm {float(axis @ axis):.17g}; pass a unit "
                             "axis (relacc does not normalize it)")
        object.__setattr__(self, "axis", axis)
        object.__setattr__(self, "ref", _number(who, "ref", self.ref))
        nv = NV[self.type]
        try:
            arm = np.zeros(nv) if self.armature is None else np.array(
                np.broadcast_to(np.asarray(self.armature, dtype=np.float64), (nv,)))
        except (TypeError, ValueError):
            raise InputError(f"{who}: armature must be one number or {nv} numbers, got {self.armature!r:.80}") from None
        if not np.all(np.isfinite(arm)) or np.any(arm < 0):
            raise InputError(f"{who}: armature must be finite and >= 0, got {arm.tolist()}")
        arm.setflags(write=False)
        object.__setattr__(self, "armature", arm)

    @property
    def nv(self) -> int:
        return NV[self.type]

    @classmethod
    def free(cls, name: str, armature=None) -> "Joint":
        """A free joint: ``q = [p, quat]``, the body's origin and orientation in the world."""
        return cls(name, "free", armature=armature)

    @classmethod
    def ball(cls, name: str, pos=(0.0, 0.0, 0.0), armature=None) -> "Joint":
        """A ball joint about the anchor ``pos`` (body frame)."""
        return cls(name, "ball", pos=pos, armature=armature)

    @classmethod
    def hinge(cls, name: str, axis, pos=(0.0, 0.0, 0.0), ref=0.0, armature=None) -> "Joint":
        """A hinge about the unit ``axis`` through ``pos`` (body frame)."""
        return cls(name, "hinge", pos=pos, axis=axis, ref=ref, armature=armature)

    @classmethod
    def slide(cls, name: str, axis, ref=0.0, armature=None) -> "Joint":
        """A slide along the unit ``axis`` (body frame)."""
        return cls(name, "slide", axis=axis, ref=ref, armature=armature)


@dataclass(frozen=True)
class Body:
    """A rigid body placed in its parent's frame and moved by its joints.

    Attributes:
        name: unique in the tree. parent: index of the parent body, ``-1`` for the world (a name is
            accepted when building a :class:`Tree` and resolved there).
        pos: ``(3,)`` the body frame's origin in the parent's frame at the joints' zero, m.
        quat: ``(4,)`` unit quaternion ``(w, x, y, z)``, the body frame in the parent's frame.
        joints: the joints moving it relative to its parent, applied in order.
        mass: kg (0 for a massless body). com: ``(3,)`` mass centre, body frame, m.
        inertia: ``(3, 3)`` about the mass centre, body components, kg m^2: symmetric, positive semidefinite, its
            principal moments meeting the triangle inequality ``A + B >= C`` (to ``c eps`` of the largest, plus
            what ``written`` allows).
        physical: False only for a body read from a file that breaks those conditions (or has a negative mass): the
            reader names it (:mod:`relacc.reading.physical`), and its dynamics are evaluated as written.
        written: kg m^2, the rounding the digits a file writes its inertia with allow (the Frobenius norm of half a
            unit in each entry's last digit, :func:`relacc.reading.xml.rounding`); 0 for an inertia given in Python.
    """

    name: str
    parent: int | str = -1
    pos: np.ndarray = field(default_factory=lambda: np.zeros(3), repr=False)
    quat: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0, 0.0]), repr=False)
    joints: tuple = ()
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3), repr=False)
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)), repr=False)
    physical: bool = field(default=True, repr=False)
    written: float = field(default=0.0, repr=False)

    def __post_init__(self):
        who = f"body {self.name!r}"
        if not isinstance(self.name, str) or not self.name:
            raise InputError(f"body name: expected a non-empty string, got {self.name!r}")
        object.__setattr__(self, "pos", fixed_vector(who, "pos", self.pos))
        quat = fixed_vector(who, "quat", self.quat, 4)
        if abs(float(quat @ quat) - 1) > QUATERNION_NORM_TOLERANCE:
            raise InputError(f"{who}: quat {quat.tolist()} has squared norm {float(quat @ quat):.17g}; pass a unit "
                             "quaternion (w, x, y, z): relacc does not normalize it")
        object.__setattr__(self, "quat", quat)
        joints = tuple(self.joints)
        if not all(isinstance(j, Joint) for j in joints):
            raise InputError(f"{who}: joints must be relacc.Joint objects")
        if any(j.type == "free" for j in joints) and len(joints) > 1:
            raise InputError(f"{who}: a free joint must be the body's only joint (as in MuJoCo)")
        object.__setattr__(self, "joints", joints)
        if not isinstance(self.physical, bool):
            raise InputError(f"{who}: physical must be True or False, got {self.physical!r}")
        object.__setattr__(self, "mass", _number(who, "mass", self.mass, minimum=0.0 if self.physical else None))
        object.__setattr__(self, "com", fixed_vector(who, "com", self.com))
        try:
            inertia = np.array(self.inertia, dtype=np.float64)
        except (TypeError, ValueError):
            raise InputError(f"{who}: inertia must be a 3x3 tensor of real numbers") from None
        if inertia.dtype.kind != "f" or inertia.shape != (3, 3) or not np.all(np.isfinite(inertia)):
            raise InputError(f"{who}: inertia must be a finite 3x3 tensor (kg m^2), got shape {inertia.shape}")
        scale = float(np.abs(inertia).max())
        if np.abs(inertia - inertia.T).max() > 1e-12 * scale:
            raise InputError(f"{who}: inertia must be symmetric, got {inertia.tolist()}")
        object.__setattr__(self, "written", _number(who, "written", self.written, minimum=0.0))
        if self.physical:
            from relacc.core.tolerances import triangle_violation

            moments = np.linalg.eigvalsh(0.5 * (inertia + inertia.T))
            if moments[0] < -1e-12 * scale - 3 * self.written:
                raise InputError(f"{who}: inertia must be positive semidefinite; its principal moments are "
                                 f"{moments.tolist()} kg m^2")
            broken = triangle_violation(moments, self.written)
            if broken:
                raise InputError(f"{who}: inertia's principal moments {moments.tolist()} break the triangle inequality "
                                 f"({broken}): no rigid body has them")
        inertia.setflags(write=False)
        object.__setattr__(self, "inertia", inertia)


@dataclass(frozen=True)
class Point:
    """A named point fixed in a body (an MJCF site, a URDF frame): ``pos (3,)`` in the body's frame, m.

    ``body``: the body's index (a name is accepted when building a :class:`Tree`); ``-1`` the world.
    """

    name: str
    body: int | str
    pos: np.ndarray = field(default_factory=lambda: np.zeros(3), repr=False)

    def __post_init__(self):
        object.__setattr__(self, "pos", fixed_vector(f"point {self.name!r}", "pos", self.pos))


@dataclass(frozen=True, eq=False)
class Tree:
    """A kinematic tree: bodies in MuJoCo's order (parents first), gravity, named points.

    Attributes:
        name: the model's name. bodies: :class:`Body` in order, the world left out.
        gravity: ``(3,)`` m/s^2, world components (the model file's; zero if it has none).
        points: :class:`Point` objects, named points of interest.
        source: where it was read from (a path) or ``"python"``.

    Build one in Python (bodies' ``parent`` may be a name), read one with :meth:`from_file`, or
    make the note's chain with :meth:`from_chain`.
    """

    name: str
    bodies: tuple
    gravity: np.ndarray = field(default_factory=lambda: np.zeros(3), repr=False)
    points: tuple = ()
    source: str = "python"

    def __post_init__(self):
        bodies = tuple(self.bodies)
        if not bodies or not all(isinstance(b, Body) for b in bodies):
            raise InputError("Tree: bodies must be a non-empty list of relacc.Body")
        index = {}
        resolved = []
        for i, b in enumerate(bodies):
            if b.name in index:
                raise InputError(f"Tree: two bodies are named {b.name!r}")
            parent = b.parent
            if isinstance(parent, str):
                if parent not in index:
                    raise InputError(f"Tree: body {b.name!r} names parent {parent!r}, which is not an earlier body "
                                     f"(known: {', '.join(index) or 'none'}); list parents first")
                parent = index[parent]
            elif parent is None:
                parent = -1
            if isinstance(parent, bool) or not isinstance(parent, (int, np.integer)) or not -1 <= parent < i:
                raise InputError(f"Tree: body {b.name!r} has parent {b.parent!r}; expected -1 (the world), an earlier "
                                 "body's index or its name")
            index[b.name] = i
            resolved.append(b if parent == b.parent else replace(b, parent=int(parent)))
        names = [j.name for b in resolved for j in b.joints]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:
            raise InputError(f"Tree: joint names must be unique, repeated: {', '.join(twice)}")
        points = []
        for p in self.points:
            if not isinstance(p, Point):
                raise InputError("Tree: points must be relacc.Point objects")
            body = index.get(p.body, p.body) if isinstance(p.body, str) else p.body
            if isinstance(body, str) or isinstance(body, bool) or not -1 <= int(body) < len(bodies):
                raise InputError(f"Tree: point {p.name!r} is on unknown body {p.body!r}")
            points.append(p if body == p.body else replace(p, body=int(body)))
        pnames = [p.name for p in points]
        if len(set(pnames)) != len(pnames):
            raise InputError("Tree: point names must be unique")
        object.__setattr__(self, "bodies", tuple(resolved))
        object.__setattr__(self, "points", tuple(points))
        object.__setattr__(self, "gravity", fixed_vector("Tree", "gravity", self.gravity))

    def __repr__(self) -> str:
        return f"Tree({self.name!r}: {self.nb} bodies, {len(self.joints)} joints, nv {self.nv}, from {self.source})"

    # ---- sizes and addresses -----------------------------------------------------------------
    @property
    def nb(self) -> int:
        """Number of bodies (the world not counted)."""
        return len(self.bodies)

    @cached_property
    def joints(self) -> tuple:
        """``((body index, Joint), ...)`` every joint in order."""
        return tuple((b, j) for b, body in enumerate(self.bodies) for j in body.joints)

    @cached_property
    def nv(self) -> int:
        """Number of generalized speeds (the same in every case)."""
        return sum(j.nv for _, j in self.joints)

    @property
    def nq(self) -> int:
        """Number of coordinates in cases 1 and 2 (quaternions for balls and free joints), a number as :attr:`nv` is
        (:meth:`nq_in` for a case's)."""
        return self._nq[0]

    def nq_in(self, case: int) -> int:
        """Number of coordinates in a case: quaternions in cases 1-2, 1-2-3 angles in case 3."""
        return self._nq[1 if int(case) == 3 else 0]

    @cached_property
    def _nq(self) -> tuple:
        return tuple(sum(table[j.type] for _, j in self.joints) for table in (NQ, NQ_ANGLES))

    @cached_property
    def dofadr(self) -> tuple:
        """First speed index of each joint (in :attr:`joints` order)."""
        out, at = [], 0
        for _, j in self.joints:
            out.append(at)
            at += j.nv
        return tuple(out)

    def qadr(self, case: int) -> tuple:
        """First coordinate index of each joint in a case's ``q``."""
        table = NQ_ANGLES if int(case) == 3 else NQ
        out, at = [], 0
        for _, j in self.joints:
            out.append(at)
            at += table[j.type]
        return tuple(out)

    @cached_property
    def body_joints(self) -> tuple:
        """Per body, the indices (in :attr:`joints`) of its own joints."""
        out, k = [], 0
        for body in self.bodies:
            out.append(tuple(range(k, k + len(body.joints))))
            k += len(body.joints)
        return tuple(out)

    @cached_property
    def path_dofs(self) -> tuple:
        """Per body, the speeds that move it: its own and its ancestors' (none past a free joint), ascending."""
        out = []
        for b, body in enumerate(self.bodies):
            own = [self.dofadr[k] + i for k in self.body_joints[b] for i in range(self.joints[k][1].nv)]
            free = any(j.type == "free" for j in body.joints)
            inherited = [] if body.parent < 0 or free else list(out[body.parent])
            out.append(tuple(sorted(inherited + own)))
        return tuple(out)

    @cached_property
    def depth(self) -> tuple:
        """Per body, the number of joints between it and the world (at least 1: its placement)."""
        out = []
        for b, body in enumerate(self.bodies):
            up = 0 if body.parent < 0 else out[body.parent]
            out.append(up + max(1, len(body.joints)))
        return tuple(out)

    # ---- names --------------------------------------------------------------------------------
    @cached_property
    def body_names(self) -> tuple:
        return tuple(b.name for b in self.bodies)

    @cached_property
    def joint_names(self) -> tuple:
        return tuple(j.name for _, j in self.joints)

    @cached_property
    def point_names(self) -> tuple:
        return tuple(p.name for p in self.points)

    def body(self, name: str) -> int:
        """A body's index by name (or index)."""
        if isinstance(name, (int, np.integer)) and not isinstance(name, bool) and 0 <= name < self.nb:
            return int(name)
        try:
            return self.body_names.index(name)
        except ValueError:
            raise InputError(f"tree {self.name!r} has no body {name!r}; bodies: {', '.join(self.body_names)}") from None

    def joint(self, name: str) -> int:
        """A joint's index (in :attr:`joints`) by name."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise InputError(f"tree {self.name!r} has no joint {name!r}; joints: "
                             f"{', '.join(self.joint_names) or 'none'}") from None

    def speed_names(self) -> tuple:
        """A label per speed: the joint's name and the component (``x``, ``wx``, ...)."""
        labels = {"free": ("vx", "vy", "vz", "wx", "wy", "wz"), "ball": ("wx", "wy", "wz"), "slide": ("",),
                  "hinge": ("",)}
        return tuple(f"{j.name}{'.' + c if c else ''}" for _, j in self.joints for c in labels[j.type])

    # ---- readers ------------------------------------------------------------------------------
    @classmethod
    def from_file(cls, path) -> "Tree":
        """Read a model file: an MJCF (``.xml``) or a URDF (``.urdf``) by relacc's own reading of the format
        (:func:`relacc.reading.read`, which says what it read, took from elsewhere or left out), or a chain TOML
        (``.toml``).

        Raises:
            ModelError: the file cannot be read (the message names the file, the element and its line).
        """
        import os
        from pathlib import Path

        if isinstance(path, (str, os.PathLike)) and Path(path).suffix.lower() == ".toml":
            from relacc.fixtures import load

            return cls.from_chain(load(path).chain, name=Path(path).stem, source=str(path))
        from relacc.reading import read

        return read(path).tree

    @classmethod
    def from_chain(cls, chain, name: str = "two_body", source: str = "python") -> "Tree":
        """The note's two-body chain as a tree, with the names of ``models/two_body.xml``.

        B1 on a free joint; B2 at ``q2'`` on three slides along B1's axes (``s2'``) and a ball
        (``quat_B2/B1``). Its case-1/2/3 coordinates and speeds are the chain's, in the same order.
        Points: ``B1_origin``, ``Q2`` (B2's joint point at ``s2' = 0``) and ``G2``.
        """
        from relacc.core.chain import TwoBodyChain

        if not isinstance(chain, TwoBodyChain):
            raise InputError(f"chain: expected a relacc.TwoBodyChain, got {type(chain).__name__}")
        eye = np.eye(3)
        b1 = Body("B1", -1, joints=(Joint.free("B1_free"),), mass=chain.m1, com=chain.r1, inertia=chain.I1)
        slides = tuple(Joint.slide(f"s2_{c}", eye[k]) for k, c in enumerate("xyz"))
        b2 = Body("B2", 0, pos=chain.q2, joints=slides + (Joint.ball("B2_ball"),), mass=chain.m2, com=chain.r2,
                  inertia=chain.I2)
        points = (Point("B1_origin", 0), Point("Q2", 0, chain.q2), Point("G2", 1, chain.r2))
        return cls(name, (b1, b2), points=points, source=source)


_CHAIN_TREES: "weakref.WeakKeyDictionary[Any, Tree]" = weakref.WeakKeyDictionary()


def chain_tree(chain) -> Tree:
    """The chain's tree (:meth:`Tree.from_chain`, named ``two_body``), built once per chain and kept while the chain
    lives: the one model every layer above the note's formulas evaluates the chain with."""
    tree = _CHAIN_TREES.get(chain)
    if tree is None:
        tree = _CHAIN_TREES[chain] = Tree.from_chain(chain)
    return tree


_WELDED: "weakref.WeakKeyDictionary[Any, Tree | None]" = weakref.WeakKeyDictionary()


def welded_folded(tree: Tree) -> Tree:
    """The same tree for forward dynamics, with every body that has no joint of its own and a parent body folded
    into that parent (computed once per tree).

    A welded body moves with its parent, so the two are one rigid body: the fold adds its mass, and its inertia
    about the pair's mass centre (Steiner's theorem, in the parent's frame), to the parent's, and places its children
    in the parent's frame (``pos' = P + R pos``, ``quat' = q_P (x) quat``). The joints, their order and the speeds are
    unchanged, so the forward dynamics (``udot``) are the tree's in every case; bodies, their indices and named points
    are not (the kernels that report bodies use :class:`Tree` itself). Bodies welded to the world stay, and so does a
    welded body whose child turns on a ball (in case 1 a ball's speeds are in its parent body's components). Each fold
    rounds the inertias once (a few ulps of the larger term). Returns ``tree`` itself when there is nothing to fold.
    """
    if tree in _WELDED:
        return _WELDED[tree] or tree
    from relacc.core.rotations import matrix_from_quaternion, quaternion_multiply

    host, frame = [], []  # per body: the kept body it belongs to (new index), its frame in that body's (pos, quat)
    kept: list[dict] = []
    ball_parents = {b.parent for b in tree.bodies if any(j.type == "ball" for j in b.joints)}
    for i, b in enumerate(tree.bodies):
        p = b.parent
        if p >= 0:  # the body's frame in its parent's host's
            P, qP = frame[p]
            pos, quat = P + matrix_from_quaternion(qP) @ b.pos, quaternion_multiply(qP, b.quat)
        else:
            pos, quat = b.pos, b.quat
        if b.joints or p < 0 or i in ball_parents:
            host.append(len(kept))
            frame.append((np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0])))
            kept.append(dict(name=b.name, parent=host[p] if p >= 0 else -1, pos=pos, quat=quat, joints=b.joints,
                             mass=b.mass, com=b.com, inertia=np.array(b.inertia), physical=b.physical,
                             written=b.written))
            continue
        host.append(host[p])
        frame.append((pos, quat))
        h = kept[host[p]]
        R = matrix_from_quaternion(quat)
        m1, m2 = h["mass"], b.mass
        c1, c2 = h["com"], pos + R @ b.com
        m = m1 + m2
        c = (m1 * c1 + m2 * c2) / m if m != 0.0 else c1
        J = h["inertia"] + R @ b.inertia @ R.T
        for mi, ci in ((m1, c1), (m2, c2)):
            d = ci - c
            J = J + mi * (float(d @ d) * np.eye(3) - np.outer(d, d))
        h.update(mass=m, com=c, inertia=0.5 * (J + J.T), physical=False)  # a sum of checked inertias
    folded = None if len(kept) == tree.nb else Tree(tree.name, tuple(Body(**k) for k in kept), gravity=tree.gravity,
                                                     source=tree.source)
    _WELDED[tree] = folded  # None, not the tree itself: a weak key's value must not hold its key
    return folded or tree
