"""Two descriptions of one robot (``relacc diff A B``): are they the same robot, and if not, what differs and where.

Each file is read by relacc itself (:func:`relacc.reading.read`), never through an engine. The comparison is of what
the physics depends on, in a way that does not depend on either file's choice of frames:

* **Parts.** A body with joints and every body welded to it (a URDF link on a fixed joint, an MJCF body without
  joints) make one *part*: its mass, its mass centre and its inertia about the mass centre are the composite's. Bodies
  welded to the world make the world's part: on a fixed base their mass moves nothing, and is said once (a note).
  A massless body with joints whose one child has joints is a frame of that child's part, its joints first (URDF
  has one joint a link: an MJCF body's six joints are a URDF chain of five massless links and the massive one), in
  each file where that leaves fewer parts and joints without a counterpart (:func:`_matched`).
* **At the reference configuration** (every joint at its ``ref``: a file's zero), in world components: each part's
  mass centre, inertia and gravity compensation (MJCF ``gravcomp``: the fraction of its weight MuJoCo holds up), each
  joint's axis and (hinge, ball) anchor, zero, armature, damping, friction loss, spring and range, a hinge's anchor
  compared as its distance from the other file's axis line (where on the line a file puts it is a choice of frame);
  joint couplings (URDF ``<mimic>``, MJCF ``<equality><joint>``: :class:`relacc.reading.model.Coupling`).
  How either file chose its link frames and inertial frames, principal axes or full tensors, drops out.
* **Beyond the tree.** Each file's elements that no comparison evaluates (:attr:`relacc.reading.Reading.unevaluated`
  of the kinds not in :data:`COMPARED`: equality constraints other than joint couplings, tendons, loop joints, fluid
  forces ...) are notes of that file's, and :attr:`Diff.beyond`.
* **Placement.** A whole robot placed or rotated differently in the world is one rigid motion, found from the parts'
  mass centres and their feet on the joint axes (a fit that leaves out points beyond the tolerance, so that one moved
  mass centre does not spread over the others), one ``placement`` entry; B is compared after it.
* **Where the frames coincide** (a converted file keeps its source's link frames: MuJoCo's saved XML does), a part
  made of one body is compared in its body's own components too, number by number, so that a number *rounded* to
  fewer digits is named as such.

Matching: parts by a joint name in common, then by a body name in common, then by structure (a matched parent's
unmatched children with the same joint types, in file order); joints within a part by name, then by type and order.

Tolerance (:func:`relacc.core.tolerances.printed_tolerance`): a difference counts beyond what printing each file's
numbers to 6 significant digits can change, ``2 rtol`` of the magnitude of the written terms a quantity is formed
from: a mass, the masses summed; a position, the lengths of the placements on its path from the world plus ``pi``
times its distance from each of their origins (each printed orientation may be off by ``rtol pi`` rad); an inertia,
each body's largest entry (times ``1 + 2 pi`` per orientation on its path) and its parallel-axis terms. ``rtol``
defaults to :data:`relacc.core.tolerances.PRINTED_RTOL` (5e-6) and may only be widened.

Kinds of difference: ``changed``, ``added`` (in B only: an armature, a damping, a limit), ``dropped`` (in A only; a
fused body's mass left out), ``rounded`` (one file's number is the other's rounded to the digits it prints),
``placement``, ``convention`` (a joint axis reversed: the same motion is q -> -q), ``unmatched``.

The dynamics of A and B (mass matrix, bias forces ``f`` of ``M udot = f``, and forward dynamics, MuJoCo's speeds,
case 2) are compared at matched coordinates, through the sign of each reversed joint, at the reference configuration
and at seeded random states: the consequence of the differences, worst state first.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from relacc.core.rotations import matrix_from_quaternion
from relacc.core.tolerances import PRINTED_RTOL, printed_tolerance

COMPARED = ("coupling", "gravcomp", "friction")
"""The kinds of a reading's unevaluated elements (:data:`relacc.reading.model.UNEVALUATED_KINDS`) that ``diff``
compares itself: joint couplings, gravity compensation, dry friction; the others are notes (:attr:`Diff.beyond`)."""

KINDS = ("changed", "added", "dropped", "rounded", "placement", "convention", "unmatched")
"""The kinds of a :class:`Difference` (module docstring)."""

UNITS = {"mass": "kg", "mass centre": "m", "inertia": "kg m^2", "axis": "unit vector", "anchor": "m",
         "armature": "kg m^2 or kg", "damping": "N m s/rad or N s/m", "friction loss": "N m or N", "range": "rad or m",
         "stiffness": "N m/rad or N/m", "spring reference": "rad or m", "type": "", "gravity": "m/s^2",
         "placement": "deg, unit axis, m", "part": "", "joint": "", "zero": "rad or m",
         "gravity compensation": "of the part's weight",
         "coupling": "offset rad or m, multiplier, higher coefficients"}
"""Units of each quantity a difference names (world components for vectors and tensors, at the reference
configuration; ``mass centre (body frame)`` in the body's own components)."""


@dataclass(frozen=True)
class Difference:
    """One difference between A and B: its ``kind`` (:data:`KINDS`), the ``element`` (a part, body or joint name,
    ``A-name / B-name`` where they differ), the ``quantity`` (its units in :data:`UNITS`), the values ``a`` and ``b``
    (numbers, lists or text; None where absent), ``relative`` (``|a - b| / max(|a|, |b|)``, None for text), and each
    element's place (``file:line``)."""

    kind: str
    element: str
    quantity: str
    a: object
    b: object
    relative: float | None
    where_a: str
    where_b: str

    def as_json(self) -> dict:
        return {"kind": self.kind, "element": self.element, "quantity": self.quantity, "a": self.a, "b": self.b,
                "relative": self.relative, "where_a": self.where_a, "where_b": self.where_b}

    def line(self) -> str:
        unit = UNITS.get(self.quantity.split(" (")[0], "")
        values = f"A {_show(self.a)}, B {_show(self.b)}" + (f" {unit}" if unit and self.kind not in (
            "unmatched",) else "")
        rel = f" ({self.relative:.2g} relative)" if self.relative is not None else ""
        where = self.where_a if self.where_a == self.where_b else f"{self.where_a} | {self.where_b}"
        return f"  {self.kind:10s} {self.element}: {self.quantity}: {values}{rel}  [{where}]"


def _show(x) -> str:
    if x is None:
        return "none"
    if isinstance(x, (list, tuple)):
        return "(" + ", ".join(_show(v) for v in x) + ")"
    if isinstance(x, float):
        return f"{x:.8g}"
    return str(x)


@dataclass(frozen=True, eq=False)
class Part:
    """A moving part of one file (module docstring): its body ``name`` (the one with joints that carries the rest;
    ``""`` the world's part), ``bodies`` (names, that body first), the ``parent`` part's index (-1 the world), its
    joints (its massless frames' first, root first: module docstring) with the name of each one's body
    (``joint_bodies``) and their world ``anchors`` and ``axes`` ``(nj, 3)``, ``mass`` (kg), ``com`` ``(3,)`` (m) and
    ``inertia`` ``(3, 3)`` about it (kg m^2), world components at the reference configuration, ``R``/``origin`` its
    body's frame in the world, and the tolerance scales (module docstring) of each quantity (``turn_scale``: of its
    frame's orientation)."""

    name: str
    bodies: tuple
    masses: tuple
    parent: int
    index: int
    joints: tuple
    joint_bodies: tuple
    anchors: np.ndarray
    axes: np.ndarray
    anchor_scales: tuple
    axis_scales: tuple
    mass: float
    com: np.ndarray
    inertia: np.ndarray
    com_scale: float
    inertia_scale: float
    R: np.ndarray
    origin: np.ndarray
    local_com: np.ndarray
    single: bool
    turn_scale: float = 1.0


def parts_of(reading, frames: bool = True) -> tuple[list[Part], Part]:
    """``(parts, world part)`` of a reading (module docstring), parts in file order (parents first); ``frames``
    false: each massless body with joints a part of its own."""
    tree = reading.tree
    n = len(tree.bodies)
    R = [np.eye(3)] * n
    p = [np.zeros(3)] * n
    chain: list[list[int]] = [[] for _ in range(n)]
    children: list[list[int]] = [[] for _ in range(n)]
    for b, body in enumerate(tree.bodies):
        if body.parent >= 0:
            children[body.parent].append(b)
    top = list(range(n))  # a massless frame's part is its one child's (module docstring); children follow parents
    for b in reversed(range(n)):
        body, kids = tree.bodies[b], children[b]
        if frames and body.joints and len(kids) == 1 and tree.bodies[kids[0]].joints and body.mass == 0 and \
                not np.any(body.inertia):
            top[b] = top[kids[0]]
    owner = [-1] * n
    for b, body in enumerate(tree.bodies):
        parent = body.parent
        Rp, pp = (np.eye(3), np.zeros(3)) if parent < 0 else (R[parent], p[parent])
        R[b] = Rp @ matrix_from_quaternion(body.quat)
        p[b] = pp + Rp @ body.pos
        chain[b] = ([] if parent < 0 else chain[parent]) + [b]
        owner[b] = top[b] if body.joints else (owner[parent] if parent >= 0 else -1)

    def scale(b: int, x: np.ndarray) -> float:
        """Position scale of the world point ``x`` moved with body ``b``: the placements on its path, and pi times
        its distance from each of their parents' origins (module docstring)."""
        s = 0.0
        for k in chain[b]:
            s += float(np.linalg.norm(tree.bodies[k].pos))
            parent = tree.bodies[k].parent
            s += np.pi * float(np.linalg.norm(x - (p[parent] if parent >= 0 else np.zeros(3))))
        return s

    groups: dict[int, list[int]] = {}
    for b in range(n):
        groups.setdefault(owner[b], []).append(b)
    index = {o: i for i, o in enumerate(o for o in groups if o >= 0)}
    parts: list[Part] = []
    world = None
    for o, members in groups.items():
        if o >= 0:  # the body that carries the rest first
            members = [o] + [b for b in members if b != o]
        body_names = tuple(tree.bodies[b].name for b in members)
        masses = tuple(float(tree.bodies[b].mass) for b in members)
        m = float(sum(masses))
        coms = [p[b] + R[b] @ tree.bodies[b].com for b in members]
        com = sum(mi * c for mi, c in zip(masses, coms)) / m if m > 0 else (p[o] if o >= 0 else np.zeros(3))
        inertia = np.zeros((3, 3))
        i_scale = 0.0
        c_scale = 0.0
        for b, mi, c in zip(members, masses, coms):
            body = tree.bodies[b]
            d = c - com
            inertia += R[b] @ body.inertia @ R[b].T + mi * (float(d @ d) * np.eye(3) - np.outer(d, d))
            s = scale(b, c) + float(np.linalg.norm(body.com))
            big = float(np.abs(body.inertia).max(initial=0.0))
            i_scale += big * (1 + 2 * np.pi * len(chain[b])) + mi * float(np.linalg.norm(d)) * (
                float(np.linalg.norm(d)) + 2 * s) + body.written / PRINTED_RTOL
            c_scale += mi * (s + float(np.linalg.norm(d)))
        c_scale = c_scale / m if m > 0 else 0.0
        if o < 0:
            world = Part("", body_names, masses, -1, -1, (), (), np.zeros((0, 3)), np.zeros((0, 3)), (), (), m, com,
                         inertia, c_scale, i_scale, np.eye(3), np.zeros(3), np.zeros(3), False)
            continue
        jointed = sorted(b for b in members if tree.bodies[b].joints)  # root first: the order the joints act in
        held = [(b, j) for b in jointed for j in tree.bodies[b].joints]  # each joint with the body it moves
        joints = tuple(j for _, j in held)
        holder = [b for b, _ in held]
        anchors = np.array([p[b] + R[b] @ j.pos for b, j in held]).reshape(-1, 3)
        axes = np.array([R[b] @ j.axis for b, j in held]).reshape(-1, 3)
        parent = tree.bodies[jointed[0]].parent
        body = tree.bodies[o]
        parts.append(Part(body.name, body_names, masses, index[owner[parent]] if parent >= 0 and owner[parent] >= 0
                          else -1, index[o], joints, tuple(tree.bodies[b].name for b in holder), anchors, axes,
                          tuple(scale(b, a) for b, a in zip(holder, anchors)),
                          tuple(1 + np.pi * len(chain[b]) for b in holder),
                          m, com, inertia, c_scale, i_scale, R[o], p[o], body.com.copy(), len(members) == 1,
                          1 + np.pi * len(chain[o])))
    if world is None:
        world = Part("", (), (), -1, -1, (), (), np.zeros((0, 3)), np.zeros((0, 3)), (), (), 0.0, np.zeros(3),
                     np.zeros((3, 3)), 0.0, 0.0, np.eye(3), np.zeros(3), np.zeros(3), False)
    return parts, world


@dataclass(frozen=True)
class Match:
    """Matched parts ``pairs`` ``[(i_A, i_B, how)]`` (how: ``"joint name"``, ``"body name"``, ``"structure"``), and
    the parts of each file without a counterpart."""

    pairs: list
    only_a: list
    only_b: list


def match(parts_a: list[Part], parts_b: list[Part]) -> Match:
    """Parts of A matched to parts of B (module docstring)."""
    pairs: list = []
    used_a: set = set()
    used_b: set = set()

    def pair(i, k, how):
        pairs.append((i, k, how))
        used_a.add(i)
        used_b.add(k)

    joint_owner_b = {j.name: k for k, part in enumerate(parts_b) for j in part.joints}
    for i, part in enumerate(parts_a):
        for j in part.joints:
            k = joint_owner_b.get(j.name)
            if k is not None and k not in used_b:
                pair(i, k, "joint name")
                break
    body_owner_b = {name: k for k, part in enumerate(parts_b) for name in part.bodies}
    for i, part in enumerate(parts_a):
        if i in used_a:
            continue
        for name in part.bodies:
            k = body_owner_b.get(name)
            if k is not None and k not in used_b:
                pair(i, k, "body name")
                break
    changed = True
    while changed:  # by structure, a matched parent's children in order
        changed = False
        counterpart = {i: {k} for i, k, _ in pairs}
        world_a, world_b = _world_like(parts_a, used_a, parts_b, used_b), _world_like(parts_b, used_b, parts_a, used_a)
        for i in world_a:
            counterpart[i] = world_b
        for i, part in enumerate(parts_a):
            if i in used_a or part.parent not in counterpart:
                continue
            kinds = tuple(j.type for j in part.joints)
            for k, other in enumerate(parts_b):
                if k not in used_b and other.parent in counterpart[part.parent] and \
                        tuple(j.type for j in other.joints) == kinds:
                    pair(i, k, "structure")
                    changed = True
                    break
    pairs.sort()
    return Match(pairs, [i for i in range(len(parts_a)) if i not in used_a],
                 [k for k in range(len(parts_b)) if k not in used_b])


def _world_like(parts: list[Part], used: set, others: list[Part], others_used: set) -> set:
    """The world (-1) and, where the other file has no such part, this file's unmatched root part on a free joint
    alone: a floating base whose counterpart is the other file's fixed base (Trossen's mobile AI: its MJCF's arms
    hang from a free base, its URDF's from the world). Their children are matched to the world's children of the
    other file by structure."""
    def free_roots(ps, taken):
        return {k for k, part in enumerate(ps) if k not in taken and part.parent == -1
                and [j.type for j in part.joints] == ["free"]}

    return {-1} | (free_roots(parts, used) if not free_roots(others, others_used) else set())


def joint_pairs(a: Part, b: Part) -> tuple[list, list, list]:
    """``([(ja, jb)], only in a, only in b)``: joint indices of two matched parts, by name, then by type in order."""
    pairs = []
    names_b = {j.name: k for k, j in enumerate(b.joints)}
    used_b: set = set()
    rest_a = []
    for i, j in enumerate(a.joints):
        k = names_b.get(j.name)
        if k is not None:
            pairs.append((i, k))
            used_b.add(k)
        else:
            rest_a.append(i)
    only_a = []
    for i in rest_a:
        k = next((k for k, j in enumerate(b.joints) if k not in used_b and j.type == a.joints[i].type), None)
        if k is None:
            only_a.append(i)
        else:
            pairs.append((i, k))
            used_b.add(k)
    return sorted(pairs), only_a, [k for k in range(len(b.joints)) if k not in used_b]


def significant_digits(x: float) -> int:
    """Significant digits of the shortest text that reads back as ``x`` (``0.163``: 3)."""
    if x == 0 or not np.isfinite(x):
        return 1
    return next(d for d in range(1, 18) if float(f"{x:.{d - 1}e}") == x)  # 17 digits always read back


ROUNDED_DIGITS = 2
"""The fewest significant digits a number may be written with to count as another rounded: one digit (``0.2`` for
``0.1745``, ``2`` for ``1.745``) is too coarse to tell a rounding from a change (SO-101's gripper range ``-0.2 2``
against SO-100's ``-0.174533 1.74533``: two ranges chosen apart, 13% off)."""


def rounds_to(x: float, y: float) -> bool:
    """Whether ``y`` is ``x`` rounded to the significant digits ``y`` is written with (fewer than ``x``'s, and at
    least :data:`ROUNDED_DIGITS`)."""
    d = significant_digits(y)
    return ROUNDED_DIGITS <= d < significant_digits(x) and float(f"{x:.{d - 1}e}") == y


def rounded_pair(a, b) -> bool:
    """Whether one of two numbers (or arrays, entry by entry, at least one entry differing) is the other rounded."""
    a, b = np.atleast_1d(np.asarray(a, dtype=float)), np.atleast_1d(np.asarray(b, dtype=float))
    differ = a != b
    if not differ.any():
        return False
    return all(rounds_to(x, y) for x, y in zip(a[differ], b[differ])) or \
        all(rounds_to(y, x) for x, y in zip(a[differ], b[differ]))


def _relative(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    big = max(float(np.abs(a).max(initial=0.0)), float(np.abs(b).max(initial=0.0)))
    return float(np.abs(a - b).max(initial=0.0)) / big if big > 0 else 0.0


def _values(x):
    x = np.asarray(x, dtype=float)
    return [float(v) for v in x.ravel()] if x.ndim and x.size > 1 else float(x.ravel()[0])


def fit_placement(points_a: np.ndarray, points_b: np.ndarray, tolerances: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(R, p)``: the rigid motion taking B's world points ``(n, 3)`` to A's, ``x_a = R x_b + p`` (Kabsch), refitted on
    the points within ``tolerances`` ``(n,)`` (m) of it, so that a few moved points do not spread over the rest (first
    fitted on the points that the median translation fits, where they are most of them); the
    identity when it already fits every point, or when too few points remain; a translation alone (``R`` the identity)
    when that fits those points within their tolerances, rather than the tiny turn the printed digits' rounding gives
    a least-squares fit (unitree_ros' G1: its MJCF's robot 0.793 m up and "turned 1.9e-5 deg")."""
    if len(points_a) == 0 or np.all(np.linalg.norm(points_a - points_b, axis=1) <= tolerances):
        return np.eye(3), np.zeros(3)
    keep = np.ones(len(points_a), dtype=bool)
    start = np.linalg.norm(points_a - (points_b + np.median(points_a - points_b, axis=0)), axis=1) <= tolerances
    if start.sum() >= max(3, (len(points_a) + 1) // 2):  # a translation most points agree on: fit from its points
        keep = start  # (unitree's Go2: a floating base 0.445 m up, every mass centre its own, the geometry the same)
    R, p = np.eye(3), np.zeros(3)
    for _ in range(4):
        if keep.sum() < 3:
            return np.eye(3), np.zeros(3)
        a, b = points_a[keep], points_b[keep]
        ca, cb = a.mean(axis=0), b.mean(axis=0)
        U, _, Vt = np.linalg.svd((b - cb).T @ (a - ca))
        D = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
        R = Vt.T @ D @ U.T
        p = ca - R @ cb
        inside = np.linalg.norm(points_a - (points_b @ R.T + p), axis=1) <= tolerances
        if (inside == keep).all():
            break
        keep = inside
    if keep.sum() < max(3, (len(points_a) + 1) // 2):
        return np.eye(3), np.zeros(3)
    if np.all(np.linalg.norm(points_a[keep] - points_b[keep], axis=1) <= tolerances[keep]):
        return np.eye(3), np.zeros(3)  # not moved: the points left out are parts that changed (Trossen's follower arm)
    shift = (points_a[keep] - points_b[keep]).mean(axis=0)  # the simplest motion that fits: a translation alone
    if np.all(np.linalg.norm(points_a[keep] - (points_b[keep] + shift), axis=1) <= tolerances[keep]):
        return np.eye(3), shift
    return R, p


@dataclass
class Diff:
    """The answer of :func:`diff` (see :meth:`as_json` for the documented contract, docs/diff.md)."""

    a: str
    b: str
    matched: dict
    differences: list
    notes: list
    dynamics: list
    rtol: float
    trees: dict = field(default_factory=dict)
    engines: dict = field(default_factory=dict)
    beyond: list = field(default_factory=list)
    """Each file's elements beyond the tree that no comparison evaluates (``"A: 2 tendons: ..."``, from
    :attr:`relacc.reading.Reading.unevaluated`), also in ``notes``."""

    @property
    def same(self) -> bool:
        return not self.differences and not any(row["beyond"] for row in self.dynamics)

    def verdict(self) -> str:
        """The answer in one sentence: the same robot, or how many differences of which kinds, the dynamics beyond
        printing, and how the parts were matched."""
        pairs = self.matched["parts"]
        how: dict = {}
        for pair in pairs:
            how[pair["how"]] = how.get(pair["how"], 0) + 1
        matched = f"{len(pairs)} moving parts matched ({', '.join(f'{n} by {k}' for k, n in how.items())})" \
            if pairs else "no moving part matched"
        if self.same:
            left = f"; {len(self.beyond)} kind{'s' if len(self.beyond) > 1 else ''} of element beyond the tree not " \
                "compared (the notes say which)" if self.beyond else ""
            return f"the same robot within printing to 6 significant digits (rtol {self.rtol:g}){left}: {matched}"
        kinds: dict = {}
        for d in self.differences:
            kinds[d.kind] = kinds.get(d.kind, 0) + 1
        beyond = [row["quantity"] for row in self.dynamics if row["beyond"]]
        said = ", ".join(f"{n} {k}" for k, n in kinds.items()) or "none in the description"
        n = len(self.differences)
        return (f"not the same robot: {n} difference{'s' if n != 1 else ''} ({said})"
                + (f"; the {', '.join(beyond)} differ{'s' if len(beyond) == 1 else ''} beyond printing" if beyond
                   else "") + f"; {matched}")

    def as_json(self) -> dict:
        return {"same": self.same, "a": self.a, "b": self.b, "rtol": self.rtol, "matched": self.matched,
                "differences": [d.as_json() for d in self.differences], "notes": self.notes,
                "dynamics": self.dynamics, "trees": self.trees, "engines": self.engines, "not_compared": self.beyond}


def diff(path_a, path_b, *, rtol: float = PRINTED_RTOL, states: int = 8, seed: int = 0) -> Diff:
    """``relacc diff A B``: whether two description files describe the same robot, and what differs (module
    docstring).

    Args:
        path_a, path_b: MJCF (``.xml``), URDF (``.urdf``) or xacro files. rtol: the relative printing error allowed
            each number (:data:`relacc.core.tolerances.PRINTED_RTOL`, at least). states: seeded random states
            the dynamics are compared at, besides the reference configuration. seed: their seed.

    Raises:
        ModelError: a file that cannot be read (as :func:`relacc.reading.read`).
    """
    from relacc.reading import read

    ra, rb = read(path_a), read(path_b)
    return diff_readings(ra, rb, rtol=rtol, states=states, seed=seed)


def diff_readings(ra, rb, *, rtol: float = PRINTED_RTOL, states: int = 8, seed: int = 0) -> Diff:
    """:func:`diff` of two readings."""
    (parts_a, world_a), (parts_b, world_b), m, frames_a = _matched(ra, rb)
    out: list[Difference] = []
    notes: list[str] = []

    def tol(scale):
        return printed_tolerance(scale, rtol)

    def name_of(a: Part, b: Part) -> str:
        return a.name if a.name == b.name else f"{a.name} / {b.name}"

    for reading, world, label in ((ra, world_a, "A"), (rb, world_b, "B")):
        if world.bodies and world.mass > 0:
            notes.append(f"{label}: {', '.join(world.bodies)} ({world.mass:.6g} kg) welded to the world: on a fixed "
                         "base its mass moves nothing")
    beyond = [f"{label}: {line}" for reading, label in ((ra, "A"), (rb, "B"))
              for line, kind in itertools.zip_longest(reading.unevaluated, reading.unevaluated_kinds, fillvalue="")
              if kind not in COMPARED]
    notes.extend(beyond)

    joints = {(i, k): joint_pairs(parts_a[i], parts_b[k]) for i, k, _ in m.pairs}  # each matched pair's joints

    # placement: B's world points taken to A's
    pa, pb, pt = [], [], []
    for i, k, _ in m.pairs:
        a, b = parts_a[i], parts_b[k]
        if a.mass > 0 and b.mass > 0:
            pa.append(a.com)
            pb.append(b.com)
            pt.append(tol(max(a.com_scale, b.com_scale)))
            for ja, jb in joints[(i, k)][0]:
                if a.joints[ja].type == "hinge" and b.joints[jb].type == "hinge":
                    pa.append(_foot(a.com, a.anchors[ja], a.axes[ja]))
                    pb.append(_foot(b.com, b.anchors[jb], b.axes[jb]))
                    pt.append(tol(max(a.anchor_scales[ja], b.anchor_scales[jb]) + a.com_scale + b.com_scale))
    for x, y in _axis_pairs(parts_a, parts_b, m, joints, tol):  # the joints' geometry alone, whatever the masses
        pa.append(x[0])
        pb.append(x[1])
        pt.append(y)
    floating = any(j.type == "free" for parts in (parts_a, parts_b) for part in parts for j in part.joints)
    R, p = fit_placement(np.array(pa).reshape(-1, 3), np.array(pb).reshape(-1, 3), np.array(pt))
    if not np.allclose(R, np.eye(3), rtol=0, atol=0) or np.any(p != 0):
        from scipy.spatial.transform import Rotation

        turn = Rotation.from_matrix(R.T).as_rotvec()  # B's robot is A's turned by R^T, then moved by -R^T p
        angle = float(np.linalg.norm(turn))
        about = turn / angle if angle > 0 else np.array([0.0, 0.0, 1.0])
        moved = -R.T @ p
        motion = {"turned_deg": float(np.degrees(angle)), "about": _values(about), "moved_m": _values(moved)}
        out.append(Difference("placement", "the robot", "placement", None, motion, None, ra.source, rb.source))
        turned = f"turned {np.degrees(angle):.6g} deg about {np.array2string(about, precision=6)} and " if angle else ""
        notes.append(f"B's robot is A's {turned}moved by {np.array2string(moved, precision=6)} m in the world"
                     + (" (a floating base: its initial pose only)" if floating else "")
                     + "; B compared after taking that motion back")
    com_b = {k: R @ part.com + p for k, part in enumerate(parts_b)}
    inertia_b = {k: R @ part.inertia @ R.T for k, part in enumerate(parts_b)}

    signs: dict = {}
    absorbed: dict = {}  # A's unmatched parts whose first body is welded into a matched part of B: a joint removed
    for i in m.only_a:
        owner_b = next((k for k, part in enumerate(parts_b) if parts_a[i].name in part.bodies), None)
        if owner_b is not None:
            absorbed.setdefault(owner_b, []).append(parts_a[i])
    for i, k, how in m.pairs:
        a, b = parts_a[i], parts_b[k]
        el = name_of(a, b)
        wa, wb = ra.place("body", a.name), rb.place("body", b.name)
        _part_terms(out, a, b, el, wa, wb, com_b[k], inertia_b[k], R, p, tol, ra, rb, tuple(absorbed.get(k, ())))
        _compensation(out, el, ra, rb, [a, *absorbed.get(k, ())], b, tol)
        jp, only_ja, only_jb = joints[(i, k)]
        for ja, jb in jp:
            signs[(i, ja)] = _joint_terms(out, ra, rb, a, b, ja, jb, R, p, tol)
        for ja in only_ja:
            j = a.joints[ja]
            out.append(Difference("unmatched", j.name, "joint", j.type, None, None, ra.place("joint", j.name),
                                  rb.source))
        for jb in only_jb:
            j = b.joints[jb]
            out.append(Difference("unmatched", j.name, "joint", None, j.type, None, ra.source,
                                  rb.place("joint", j.name)))
    for i in m.only_a:
        a = parts_a[i]
        welded = any(a in group for group in absorbed.values())
        out.append(Difference("unmatched", a.name, "joint" if welded else "part",
                              ", ".join(f"{j.name} ({j.type})" for j in a.joints),
                              "welded to its parent" if welded else None, None,
                              ra.place("joint", a.joints[0].name) if welded else ra.place("body", a.name),
                              rb.place("body", a.name) if welded else rb.source))
    for k in m.only_b:
        b = parts_b[k]
        out.append(Difference("unmatched", b.name, "part", None, ", ".join(j.name for j in b.joints), None,
                              ra.source, rb.place("body", b.name)))
    _coupling_terms(out, ra, rb, parts_a, parts_b, joints, signs, tol)
    ga, gb = ra.tree.gravity, rb.tree.gravity
    if np.linalg.norm(ga - gb) > tol(max(np.linalg.norm(ga), np.linalg.norm(gb))):
        out.append(Difference("rounded" if rounded_pair(ga, gb) else "changed", "world", "gravity", _values(ga),
                              _values(gb), _relative(ga, gb), ra.place("option", "gravity"),
                              rb.place("option", "gravity")))
    matched = {"parts": [{"a": parts_a[i].name, "b": parts_b[k].name, "how": how,
                          "bodies_a": list(parts_a[i].bodies), "bodies_b": list(parts_b[k].bodies)}
                         for i, k, how in m.pairs],
               "only_a": [parts_a[i].name for i in m.only_a], "only_b": [parts_b[k].name for k in m.only_b]}
    from relacc.validation.diff_dynamics import compare_dynamics

    dynamics, why = compare_dynamics(ra, rb, parts_a, parts_b, m, R, p, signs, joints, rtol, states, seed)
    if any(row["beyond"] for row in dynamics):  # are the listed masses, inertias and armatures the whole of it?
        from relacc.errors import RelaccError
        from relacc.validation.diff_dynamics import explain, with_inertials_of

        try:
            a_with_b = with_inertials_of(ra, rb, parts_a, parts_b, m, R, p, joints)
        except RelaccError as exc:  # said, not skipped: the rows stand without the explanation
            notes.append(f"the dynamics beyond printing not compared again with A given B's inertial numbers: {exc}")
        else:
            again, why_not = compare_dynamics(a_with_b, rb, parts_of(a_with_b, frames_a)[0], parts_b, m, R, p, signs,
                                              joints, rtol, states, seed)
            explain(dynamics, again)
            if why_not:
                notes.append(f"the dynamics beyond printing not compared again with A given B's inertial numbers: "
                             f"{why_not}")
    held_a = _held_root(ra, parts_a, m.only_a, m.only_b)
    held_b = _held_root(rb, parts_b, m.only_b, m.only_a)
    held = held_a or held_b
    if why and held is not None:  # one file's base fixed, the other's free: the rest compared with that joint held
        label = "A" if held_a is not None else "B"
        sub = diff_readings(held[0], rb, rtol=rtol, states=states, seed=seed) if label == "A" else \
            diff_readings(ra, held[0], rtol=rtol, states=states, seed=seed)
        if sub.dynamics:
            dynamics, why = sub.dynamics, ""
            notes.append(f"dynamics compared with {label}'s free joint {held[1]} held where it places its body "
                         f"(the other file's base is fixed)")
    if why and held is None and (m.only_a or m.only_b) and m.pairs:  # parts one file alone has: held as placed
        welded_a, names_a = _welded(ra, parts_a, m.only_a)
        welded_b, names_b = _welded(rb, parts_b, m.only_b)
        sub = diff_readings(welded_a, welded_b, rtol=rtol, states=states, seed=seed)
        if sub.dynamics:
            dynamics, why = sub.dynamics, ""
            notes.append("dynamics compared with the joints of the parts only one file has held where that file places "
                         f"them ({', '.join(names_a + names_b)}): their masses move with their parents'")
    if why:
        notes.append(f"dynamics not compared: {why}")
    trees = {"a": _tree(parts_a, world_a), "b": _tree(parts_b, world_b),
             "pairs": [[i, k, how] for i, k, how in m.pairs]}
    return Diff(str(ra.source), str(rb.source), matched, out, notes, dynamics, rtol, trees, beyond=beyond)


def _matched(ra, rb) -> tuple:
    """``(parts of A, parts of B, their match, whether A's massless frames joined their child's part)``: each file's
    massless bodies with joints kept parts of their own, or made frames of their one child's part (module
    docstring), whichever leaves fewest parts and joints without a counterpart, kept parts first: a URDF's chain of
    massless links against an MJCF body with several joints, and against an MJCF that gave those links a small mass
    (MuJoCo refuses a massless body that moves)."""
    parts = {(r, f): parts_of(reading, f) for r, reading in enumerate((ra, rb)) for f in (False, True)}
    best: tuple | None = None
    for fa, fb in ((False, False), (True, True), (True, False), (False, True)):
        (pa, _), (pb, _) = parts[(0, fa)], parts[(1, fb)]
        m = match(pa, pb)
        left = len(m.only_a) + len(m.only_b) + sum(len(x) for i, k, _ in m.pairs for x in joint_pairs(pa[i], pb[k])[1:])
        if best is None or left < best[0]:
            best = (left, parts[(0, fa)], parts[(1, fb)], m, fa)
        if not left:
            break
    assert best is not None
    return best[1:]


def _held_root(reading, parts: list[Part], only: list, others_only: list) -> tuple | None:
    """``(reading with the joint removed, the joint's name and body in words)`` where the only part without a
    counterpart is this file's root part on a free joint alone and the other file has none: a floating base against a
    fixed one (a URDF without its floating joint, its MJCF with one). Else None."""
    if len(only) != 1 or others_only:
        return None
    part = parts[only[0]]
    if part.parent != -1 or len(part.joints) != 1 or part.joints[0].type != "free":
        return None
    return _welded(reading, parts, only)[0], f"{part.joints[0].name!r} (of {part.name})"


def _welded(reading, parts: list[Part], only: list) -> tuple:
    """``(reading, joint names)``: the reading with the joints of the parts ``only`` (indices into ``parts``) removed,
    their bodies held where the file places them (at the joints' zero), and those joints' names (A's gripper against
    an MJCF without one: mujoco_menagerie's Z1 arm against example-robot-data's)."""
    from dataclasses import replace

    from relacc.core.tree.model import Tree

    if not only:
        return reading, []
    held = {name for i in only for name in parts[i].joint_bodies}
    t = reading.tree
    names = [j.name or f"(unnamed, of {b.name})" for b in t.bodies if b.name in held for j in b.joints]
    bodies = tuple(replace(b, joints=()) if b.name in held else b for b in t.bodies)
    return replace(reading, tree=Tree(t.name, bodies, gravity=t.gravity, points=t.points, source=t.source)), names


def _tree(parts: list[Part], world: Part) -> dict:
    """One file's parts as plain data: ``{"world": the bodies welded to the world, "parts": [{"name", "parent" (a
    part's index, -1 the world), "bodies" (its first body first), "joints": [[name, type]]}]}`` in file order."""
    return {"world": list(world.bodies),
            "parts": [{"name": p.name, "parent": p.parent, "bodies": list(p.bodies),
                       "joints": [[j.name, j.type] for j in p.joints]} for p in parts]}


def _axis_pairs(parts_a: list[Part], parts_b: list[Part], m: Match, joints: dict, tol) -> list:
    """``[((x_A, x_B), tolerance m)]``: for each two matched hinges whose axes are at least 0.1 rad from parallel, the
    point of A's two axis lines nearest both (the middle of their common perpendicular) and B's: points of the joints'
    geometry alone, which a placement fit can use where every mass centre moved (unitree's Go2 and B2, URDF against
    MJCF: the MJCF's own masses and its floating base 0.445 m up read as a changed anchor at every joint). Each is
    off by its anchors' tolerance plus its axes' times its distance from them, over the sine between the axes."""
    lines = []
    for i, k, _ in m.pairs:
        a, b = parts_a[i], parts_b[k]
        for ja, jb in joints[(i, k)][0]:
            if a.joints[ja].type == "hinge" and b.joints[jb].type == "hinge":
                lines.append((a.anchors[ja], a.axes[ja], b.anchors[jb], b.axes[jb],
                              tol(a.anchor_scales[ja] + b.anchor_scales[jb]),
                              tol(a.axis_scales[ja] + b.axis_scales[jb])))
    out = []
    for (p1, u1, q1, v1, t1, r1), (p2, u2, q2, v2, t2, r2) in itertools.combinations(lines, 2):
        sine = float(np.linalg.norm(np.cross(u1, u2)))
        if sine < 0.1:
            continue
        x_a, x_b = _nearest(p1, u1, p2, u2), _nearest(q1, v1, q2, v2)
        lever = float(np.linalg.norm(x_a - p1) + np.linalg.norm(x_a - p2))
        out.append(((x_a, x_b), (t1 + t2 + (r1 + r2) * lever) / sine))
    return out


def _nearest(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray) -> np.ndarray:
    """The middle of the common perpendicular of the lines ``p1 + s u1`` and ``p2 + t u2`` (not parallel) (m)."""
    w = p1 - p2
    b, d, e = float(u1 @ u2), float(u1 @ w), float(u2 @ w)
    den = 1.0 - b * b  # unit axes
    s, t = (b * e - d) / den, (e - b * d) / den
    return 0.5 * ((p1 + s * u1) + (p2 + t * u2))


def _foot(x: np.ndarray, anchor: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """The point of the line through ``anchor`` along ``axis`` nearest ``x`` (m, world)."""
    return anchor + float((x - anchor) @ axis) * axis


def _combined(parts: list[Part]) -> tuple[float, np.ndarray, np.ndarray, float, float]:
    """``(mass, com, inertia, com scale, inertia scale)`` of several parts as one (world components)."""
    m = float(sum(x.mass for x in parts))
    com = np.sum([x.mass * x.com for x in parts], axis=0) / m if m > 0 else parts[0].com
    inertia = np.sum([x.inertia + x.mass * (float((x.com - com) @ (x.com - com)) * np.eye(3)
                                            - np.outer(x.com - com, x.com - com)) for x in parts], axis=0)
    c_scale = max(x.com_scale for x in parts)
    i_scale = float(sum(x.inertia_scale + x.mass * float(np.linalg.norm(x.com - com)) * (
        float(np.linalg.norm(x.com - com)) + 2 * c_scale) for x in parts))
    return m, com, inertia, c_scale, i_scale


def _part_terms(out, a: Part, b: Part, el, wa, wb, com_b, inertia_b, R, p, tol, ra, rb, absorbed=()) -> None:
    """The mass, mass centre and inertia of two matched parts (module docstring). ``absorbed``: A's unmatched parts
    whose first body is welded into ``b`` in B (a joint removed): compared as one with ``a``, the joint said once."""
    wia, wib = ra.place("inertial", a.name), rb.place("inertial", b.name)
    a_bodies = set(a.bodies).union(*(x.bodies for x in absorbed))
    mass_a, com_a, inertia_a, c_scale, i_scale = _combined([a, *absorbed])
    missing = [(name, mass) for name, mass in zip(a.bodies, a.masses) if name not in b.bodies]
    extra = [(name, mass) for name, mass in zip(b.bodies, b.masses) if name not in a_bodies and mass > 0]
    if abs(mass_a - b.mass) > tol(mass_a + b.mass):
        gone = next((n for n, mass in missing if mass > 0 and abs(mass_a - mass - b.mass) <= tol(mass_a + b.mass)),
                    None)
        new = next((n for n, mass in extra if abs(mass_a + mass - b.mass) <= tol(mass_a + b.mass)), None)
        if gone:
            out.append(Difference("dropped", f"{el} (fused body {gone})", "mass", mass_a, b.mass,
                                  _relative(mass_a, b.mass), ra.place("body", gone), wb))
            return  # its mass centre and inertia follow from the mass left out
        if new:
            out.append(Difference("added", f"{el} (fused body {new})", "mass", mass_a, b.mass,
                                  _relative(mass_a, b.mass), wa, rb.place("body", new)))
            return
        kind = "rounded" if rounded_pair(mass_a, b.mass) else "changed"
        out.append(Difference(kind, el, "mass", mass_a, b.mass, _relative(mass_a, b.mass), wia, wib))
    coincide = not absorbed and a.single and b.single and \
        np.abs(a.R - R @ b.R).max() <= tol(a.turn_scale + b.turn_scale) and \
        np.linalg.norm(a.origin - (R @ b.origin + p)) <= tol(a.com_scale + b.com_scale)
    if mass_a > 0 and b.mass > 0 and np.linalg.norm(com_a - com_b) > tol(c_scale + b.com_scale):
        if coincide and rounded_pair(a.local_com, b.local_com):
            out.append(Difference("rounded", el, "mass centre (body frame)", _values(a.local_com),
                                  _values(b.local_com), _relative(a.local_com, b.local_com), wia, wib))
        else:
            out.append(Difference("changed", el, "mass centre", _values(com_a), _values(com_b),
                                  float(np.linalg.norm(com_a - com_b)) / max(float(np.linalg.norm(com_a)), 1e-300),
                                  wia, wib))
    t = tol(i_scale + b.inertia_scale)
    if np.abs(inertia_a - inertia_b).max() > t:
        for name, mass in missing:  # a massless fused body's inertia left out (it moves no mass centre)
            k = ra.tree.body(name)
            if mass == 0:
                Rk = _world_rotation(ra.tree, k)
                if np.abs(inertia_a - Rk @ ra.tree.bodies[k].inertia @ Rk.T - inertia_b).max() <= t:
                    out.append(Difference("dropped", f"{el} (massless fused body {name})", "inertia",
                                          _values(inertia_a), _values(inertia_b), _relative(inertia_a, inertia_b),
                                          ra.place("inertial", name), wib))
                    return
        out.append(Difference("changed", el, "inertia", _values(inertia_a), _values(inertia_b),
                              _relative(inertia_a, inertia_b), wia, wib))


def _coupling_terms(out, ra, rb, parts_a: list[Part], parts_b: list[Part], joints: dict, signs: dict, tol) -> None:
    """Each joint coupling of A (a URDF ``<mimic>``, an MJCF joint equality: :class:`relacc.reading.model.Coupling`)
    against B's between the matched joints, in A's coordinates (a reversed joint's sign applied, a coupling B writes
    the other way round inverted): ``(offset, multiplier)`` compared as printed numbers, ``changed`` or ``rounded``;
    a coupling the other file writes only through other joints (``q_f = o1 + m1 q_m`` and ``q_m = o2 + m2 q_l``, or
    both tied to a third) compared with the relation those imply (:func:`_through`, its linear couplings as one
    system); a coupling the other file does not tie at all is ``dropped`` or ``added``. Couplings of joints without a
    counterpart are left to those joints' ``unmatched`` entries. ``joints``: each matched pair of parts'
    :func:`joint_pairs`; ``signs``: each matched joint's (-1 where B reverses its axis). The quantity names the
    leader: ``coupling (on j2)``, ``coupling (on j2 / k2)`` where the files name it differently."""
    to_b = {parts_a[i].joints[ja].name: (parts_b[k].joints[jb].name, signs[(i, ja)])
            for (i, k), (pairs, _, _) in joints.items() for ja, jb in pairs}
    to_a = {b: (a, sign) for a, (b, sign) in to_b.items()}
    theirs = {(c.follower, c.leader): c for c in rb.couplings}
    roots_a, roots_b = _roots(ra.couplings), _roots(rb.couplings)
    seen: set = set()
    for c in ra.couplings:
        if c.follower not in to_b or (c.leader is not None and c.leader not in to_b):
            continue
        (fb, sf), (lb, sl) = to_b[c.follower], to_b[c.leader] if c.leader is not None else (None, 1.0)
        el = c.follower if c.follower == fb else f"{c.follower} / {fb}"
        what = _coupling_on(c.leader, lb)
        mine = [c.offset, c.multiplier, *c.higher]
        other, flipped = theirs.get((fb, lb)), False
        if other is None and lb is not None:
            other, flipped = theirs.get((lb, fb)), True
        if other is None:
            through = _through(roots_b, fb, lb) if lb is not None else None
            if through is None:
                out.append(Difference("dropped", el, what, mine, None, None, c.place, rb.source))
                continue
            o, m = through  # B ties the two through other joints: its couplings' lines are in B's own entries
            _number(out, el, what, mine, _in_signs(o, m, (0.0, 0.0, 0.0), sf, sl), tol, c.place, rb.source)
            continue
        seen.add((other.follower, other.leader))
        if flipped:  # B writes q_l = o + m q_f: A's q_f = (q_l - o) / m, in A's signs
            if other.multiplier == 0 or any(other.higher):
                out.append(Difference("changed", el, what, mine, [other.offset, other.multiplier,
                                                                          *other.higher], None, c.place, other.place))
                continue
            theirs_in_a = [-other.offset / (sf * other.multiplier), 1.0 / (sl * sf * other.multiplier), 0.0, 0.0, 0.0]
        else:
            theirs_in_a = _in_signs(other.offset, other.multiplier, other.higher, sf, sl)
        _number(out, el, what, mine, theirs_in_a, tol, c.place, other.place)
    for c in rb.couplings:
        if (c.follower, c.leader) in seen or c.follower not in to_a or (c.leader is not None and c.leader not in to_a):
            continue
        el = c.follower if to_a[c.follower][0] == c.follower else f"{to_a[c.follower][0]} / {c.follower}"
        (fa, sf), (la, sl) = to_a[c.follower], to_a[c.leader] if c.leader is not None else (None, 1.0)
        what = _coupling_on(la, c.leader)
        through = _through(roots_a, fa, la) if la is not None else None
        if through is not None:  # A ties the two through other joints
            _number(out, el, what, list(through) + [0.0, 0.0, 0.0],
                    _in_signs(c.offset, c.multiplier, c.higher, sf, sl), tol, ra.source, c.place)
            continue
        out.append(Difference("added", el, what, None, [c.offset, c.multiplier, *c.higher], None, ra.source,
                              c.place))


def _coupling_on(leader_a: str | None, leader_b: str | None) -> str:
    """The quantity of a coupling difference: ``coupling (on LEADER)``, both files' names where they differ; plain
    ``coupling`` for one that fixes its joint (no leader)."""
    if leader_a is None and leader_b is None:
        return "coupling"
    name = leader_a if leader_b is None or leader_a == leader_b else \
        leader_b if leader_a is None else f"{leader_a} / {leader_b}"
    return f"coupling (on {name})"


def _in_signs(offset: float, multiplier: float, higher, sf: float, sl: float) -> list[float]:
    """A coupling ``q_f = o + m q_l + sum h_p q_l^(p+2)`` as ``[offset, multiplier, higher...]`` for the other
    file's joints, whose coordinates are ``sf`` and ``sl`` (+1 or -1) times its follower's and leader's:
    ``sf o + sf sl m q_l' + sum sf sl^(p+2) h_p q_l'^(p+2)``."""
    return [sf * offset, sf * sl * multiplier, *(sf * sl ** (p + 2) * h for p, h in enumerate(higher))]


def _roots(couplings) -> dict:
    """``{joint: (root, offset, multiplier)}``: each joint the linear couplings tie together as ``offset + multiplier
    q_root``, ``root`` one joint of those tied to it (each coupling ``q_f = o + m q_l``, ``m`` not zero, read either
    way). A coupling with higher terms, or that fixes a joint (``m`` 0), ties nothing; where the couplings tie a joint
    twice the first way found is kept."""
    edges: dict = {}
    for c in couplings:
        if c.leader is not None and c.multiplier != 0.0 and not any(c.higher):
            edges.setdefault(c.follower, []).append((c.leader, c.offset, c.multiplier, True))
            edges.setdefault(c.leader, []).append((c.follower, c.offset, c.multiplier, False))
    out: dict = {}
    for root in edges:
        if root in out:
            continue
        out[root], todo = (root, 0.0, 1.0), [root]
        while todo:
            j = todo.pop()
            _, o_j, m_j = out[j]
            for k, o, m, j_follows in edges[j]:
                if k not in out:  # q_j = o + m q_k, or q_k = o + m q_j
                    out[k] = (root, (o_j - o) / m, m_j / m) if j_follows else (root, o + m * o_j, m * m_j)
                    todo.append(k)
    return out


def _through(roots: dict, f: str, leader: str):
    """``(offset, multiplier)`` of ``q_f = offset + multiplier q_leader`` as a file's linear couplings imply it through
    other joints (:func:`_roots`), or None where they do not tie the two."""
    if f not in roots or leader not in roots or roots[f][0] != roots[leader][0]:
        return None
    (_, o_f, m_f), (_, o_l, m_l) = roots[f], roots[leader]
    return o_f - m_f / m_l * o_l, m_f / m_l


def _compensation(out, el, ra, rb, a_parts: list, b: Part, tol) -> None:
    """The gravity compensation of two matched parts (MJCF ``gravcomp``, :attr:`relacc.reading.Reading.gravcomp`):
    the fraction of the part's weight MuJoCo holds up, ``sum(gravcomp m) / sum(m)`` over its bodies; placed at the
    line of the first body that has one."""
    def fraction(reading, parts):
        pairs = [(reading.gravcomp.get(name, 0.0), mass) for part in parts for name, mass in
                 zip(part.bodies, part.masses)]
        total = sum(m for _, m in pairs)
        held = sum(g * m for g, m in pairs)
        where = next((reading.place("body", name) for part in parts for name in part.bodies
                      if name in reading.gravcomp), reading.place("body", parts[0].name))
        return (held / total if total > 0 else 0.0), where

    fa, wa = fraction(ra, a_parts)
    fb, wb = fraction(rb, [b])
    _number(out, el, "gravity compensation", fa, fb, tol, wa, wb)


def _world_rotation(tree, b: int) -> np.ndarray:
    """``(3, 3)`` body ``b``'s frame in the world at the reference configuration."""
    R = np.eye(3)
    while b >= 0:
        R = matrix_from_quaternion(tree.bodies[b].quat) @ R
        b = tree.bodies[b].parent
    return R


def _joint_terms(out, ra, rb, a: Part, b: Part, ja: int, jb: int, R, p, tol) -> float:
    """The type, axis, anchor, zero, armature, damping, friction loss, spring and range of two matched joints;
    returns the sign that maps A's coordinate and speed to B's (-1 where the axis is reversed)."""
    j, k = a.joints[ja], b.joints[jb]
    el = j.name if j.name == k.name else f"{j.name} / {k.name}"
    wa, wb = ra.place("joint", j.name), rb.place("joint", k.name)
    if j.type != k.type:
        out.append(Difference("changed", el, "type", j.type, k.type, None, wa, wb))
        return 1.0
    sign = 1.0
    if j.type in ("hinge", "slide"):
        axis_a, axis_b = a.axes[ja], R @ b.axes[jb]
        t = tol(a.axis_scales[ja] + b.axis_scales[jb])
        if np.linalg.norm(axis_a + axis_b) <= t:
            sign = -1.0
            out.append(Difference("convention", el, "axis", _values(axis_a), _values(axis_b), None, wa, wb))
        elif np.linalg.norm(axis_a - axis_b) > t:
            out.append(Difference("changed", el, "axis", _values(axis_a), _values(axis_b),
                                  float(np.linalg.norm(axis_a - axis_b)), wa, wb))
    if j.type in ("hinge", "ball"):
        anchor_b = R @ b.anchors[jb] + p
        off = anchor_b - a.anchors[ja]
        if j.type == "hinge":
            off = off - float(off @ a.axes[ja]) * a.axes[ja]
        if np.linalg.norm(off) > tol(a.anchor_scales[ja] + b.anchor_scales[jb]):
            body_a, body_b = a.joint_bodies[ja], b.joint_bodies[jb]
            pos_a = ra.tree.bodies[ra.tree.body(body_a)].pos
            pos_b = rb.tree.bodies[rb.tree.body(body_b)].pos
            if rounded_pair(pos_a, pos_b):  # the body's place in its parent, written to fewer digits
                out.append(Difference("rounded", el, "anchor (position in the parent)", _values(pos_a),
                                      _values(pos_b), _relative(pos_a, pos_b), ra.place("body", body_a),
                                      rb.place("body", body_b)))
            else:
                out.append(Difference("changed", el, "anchor", _values(a.anchors[ja]), _values(anchor_b),
                                      float(np.linalg.norm(off)), wa, wb))
    if j.type in ("hinge", "slide") and j.ref != k.ref:
        _number(out, el, "zero", j.ref, k.ref, tol, wa, wb)
    _number(out, el, "armature", j.armature, k.armature, tol, wa, wb)
    nv = j.nv
    _number(out, el, "damping", ra.joint_damping(j.name, nv), rb.joint_damping(k.name, nv), tol, wa, wb)
    _number(out, el, "friction loss", ra.friction.get(j.name, 0.0), rb.friction.get(k.name, 0.0), tol, wa, wb)
    sa, sb = ra.stiffness.get(j.name), rb.stiffness.get(k.name)
    _number(out, el, "stiffness", sa[0] if sa else 0.0, sb[0] if sb else 0.0, tol, wa, wb)
    if sa and sb:
        _number(out, el, "spring reference", sa[1], sign * sb[1], tol, wa, wb)
    lim_a, lim_b = ra.ranges.get(j.name), rb.ranges.get(k.name)
    if lim_b is not None and sign < 0:
        lim_b = (-lim_b[1], -lim_b[0])
    if lim_a is None and lim_b is not None:
        out.append(Difference("added", el, "range", None, list(lim_b), None, wa, wb))
    elif lim_b is None and lim_a is not None:
        out.append(Difference("dropped", el, "range", list(lim_a), None, None, wa, wb))
    elif lim_a is not None:
        _number(out, el, "range", np.asarray(lim_a), np.asarray(lim_b), tol, wa, wb)
    return sign


def _number(out, el, quantity, a, b, tol, wa, wb) -> None:
    """One number (or vector) of a joint: absent in one file (zero) -> added/dropped; else rounded or changed."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if np.abs(a - b).max(initial=0.0) <= tol(np.abs(a).max(initial=0.0) + np.abs(b).max(initial=0.0)):
        return
    if not a.any():
        kind = "added"
    elif not b.any():
        kind = "dropped"
    else:
        kind = "rounded" if rounded_pair(a, b) else "changed"
    out.append(Difference(kind, el, quantity, _values(a), _values(b), _relative(a, b), wa, wb))
