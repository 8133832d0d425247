"""The one interface of an engine adapter, and everything adapters share (engine-free).

An **adapter** is one model in one engine: a model file read by the engine's own parser (or, where that parser
would read the model otherwise, a model the engine builds from relacc's tree), matched joint by joint to the
*reference*: relacc's tree of the same model as relacc reads it (:class:`relacc.Tree`, :mod:`relacc.reading`).
Everything an adapter answers, it answers in the reference's coordinates, the tree's case 2 (MuJoCo's own
``qpos``/``qvel``):

* free joint: ``q = [p (3), quat (4)]``, ``p`` the body frame's origin in its parent (world: m), ``quat`` its
  orientation ``(w, x, y, z)``; ``v = [p_dot (3, parent components), omega (3, body components)]``;
* ball joint: ``q`` the child's orientation in its parent ``(w, x, y, z)``; ``v`` its angular velocity relative to
  the parent, child components (rad/s);
* hinge, slide: one angle (rad) or displacement (m) and its rate (MuJoCo's ``ref`` included).

An engine whose coordinates differ converts them once, in its adapter, joint by joint (:class:`Match`): its
positions from the reference's (:meth:`Adapter.q_block`, and back, :meth:`Adapter.q_back`) and its speeds by a
speed map ``v_e = T(q) v`` with rate ``T_dot(q, v)`` (:meth:`Adapter.v_block`). Here, once for every engine:
``M = T^T M_e T``, ``bias = T^T (b_e + M_e T_dot v)``, ``a = T^-1 (a_e - T_dot v)``, ``J = J_e T``,
``J_dot v = J_dot_e v_e + J_e T_dot v``; a point's classical acceleration needs no map.

Each adapter implements, in its engine's own coordinates and batched over states: :meth:`Adapter.equations`
(``M_e``, ``f_e`` under exactly the given effects), :meth:`Adapter.forward`, :meth:`Adapter.points` (named points
and links' mass centres: position, Jacobian, its rate, classical acceleration) and :meth:`Adapter.stepper`.
"""

from __future__ import annotations

import abc
import dataclasses
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from relacc.errors import EngineError

if TYPE_CHECKING:
    from relacc.core.tree import Tree
    from relacc.dynamics.tree_effects import TreeEffects

JOINT_TYPES = ("free", "ball", "slide", "hinge")
"""Joint types in the common description (MuJoCo's names)."""

NQ = {"free": 7, "ball": 4, "slide": 1, "hinge": 1, "floating": 7}
NV = {"free": 6, "ball": 3, "slide": 1, "hinge": 1, "floating": 6}


@dataclass(frozen=True)
class BuiltJoint:
    """One joint as an engine built it, at the reference configuration (not :class:`relacc.Joint`, a joint of
    relacc's model).

    Attributes:
        name: the reference joint's name. type: one of :data:`JOINT_TYPES`. body: the body it moves.
        axis: ``(3,)`` unit axis in world components (hinge, slide), else None.
        anchor: ``(3,)`` the joint's position in world (m); a hinge's, the point of its axis nearest the origin.
        armature, damping: ``(nv,)`` per degree of freedom (kg m^2 or kg; N m s/rad or N s/m).
        sensitivity: of a damping derived from the mass matrix (:attr:`relacc.reading.Reading.sensitivity`; 0 for
            one written).
    """

    name: str
    type: str
    body: str
    axis: np.ndarray | None = field(repr=False)
    anchor: np.ndarray | None = field(repr=False)
    armature: np.ndarray = field(repr=False)
    damping: np.ndarray = field(repr=False)
    sensitivity: float = 0.0


@dataclass(frozen=True)
class Link:
    """A rigid group of bodies (a moving body and the bodies welded to it), at the reference configuration.

    Attributes:
        name: its moving body's name. bodies: every body in it.
        mass: kg. com: ``(3,)`` centre of mass in world (m).
        inertia: ``(3, 3)`` about the centre of mass, world components (kg m^2).
    """

    name: str
    bodies: tuple[str, ...]
    mass: float
    com: np.ndarray = field(repr=False)
    inertia: np.ndarray = field(repr=False)


def moving_mass(links) -> float:
    """The one definition of a model's total mass: the sum over its moving links (kg)."""
    return float(sum(link.mass for link in links))


@dataclass(frozen=True)
class Structure:
    """What an engine made of a model file: joints and links at the reference configuration, gravity, mass.

    Attributes:
        nq, nv: the engine's own counts. joints: in the reference's order, those the engine has.
        links: one per moving body it has. gravity: ``(3,)`` m/s^2, world. total_mass: kg, of the moving links
            (:func:`moving_mass`; bodies welded to the world carry none of the dynamics and are left out).
        bodies: every body name it has (world excluded).
    """

    nq: int
    nv: int
    joints: tuple[BuiltJoint, ...]
    links: tuple[Link, ...]
    gravity: np.ndarray = field(repr=False)
    total_mass: float
    bodies: tuple[str, ...]


@dataclass(frozen=True)
class KnownBehaviour:
    """An engine behaviour relacc knows and reproduces, so that a difference it explains is named as such.

    Attributes:
        key: a short name. text: the sentence a cause quotes.
        applies: whether it applies, given relacc's reading (a file's behaviours) or an adapter (an algorithm's).
        change: relacc's reading read the engine's way (a file's behaviours, returning a new reading), or the adapter
            rebuilt without the difference (an algorithm's, returning a new adapter).
    """

    key: str
    text: str
    applies: Callable[[Any], bool]
    change: Callable[[Any], Any]


@dataclass(frozen=True)
class EngineStates:
    """A batch of reference states in an engine's coordinates (:meth:`Adapter.to_engine`).

    Attributes:
        q: ``(n, nq_e)`` the engine's coordinates. v: ``(n, nv_e)`` its speeds, ``T`` times the reference's.
        a: ``(n, nv_e)`` its speeds' rates, ``T a_ref + T_dot v_ref``, or None without rates.
        T: ``(n, nv_e, k)`` the speed map from the reference's ``k`` shared speeds (``v_e = T v``).
        T_dot: ``(n, nv_e, k)`` its rate along the motion.
    """

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray | None
    T: np.ndarray
    T_dot: np.ndarray

    @property
    def rates(self) -> np.ndarray:
        """``a``, which these states must have been converted with.

        Raises:
            EngineError: they were converted without rates.
        """
        if self.a is None:
            raise EngineError("these engine states were converted without rates (to_engine(q, v) without a)")
        return self.a


class Loop:
    """A benchmark anchor: calling it runs an engine's own loop over the states, as a user would write it; what the
    loop fills is in its attributes (``acc``, ``pos``, ``vel``: ``(n, 3)`` or ``(n, k, 3)``, fixed-frame components;
    ``out``: accelerations), and :meth:`close` releases a pool it holds."""

    acc: Any = None
    pos: Any = None
    vel: Any = None
    out: Any = None

    def __init__(self, run: Callable[[], object], close: Callable[[], object] | None = None, **results):
        self._run, self._close = run, close
        for name, value in results.items():
            if name not in ("acc", "pos", "vel", "out"):
                raise TypeError(f"Loop has no result {name!r}")
            setattr(self, name, value)

    def __call__(self) -> None:
        self._run()

    def close(self) -> None:
        if self._close is not None:
            self._close()


@dataclass(frozen=True)
class Points:
    """Points at a batch of states: ``(n, P, ...)``, world components.

    Attributes:
        position: ``(n, P, 3)`` m. J: ``(n, P, 3, nv)`` the point's velocity Jacobian (m/s per unit speed).
        Jdot: ``(n, P, 3, nv)`` its time derivative along the motion, or None where not asked for.
        Jdot_v: ``(n, P, 3)`` ``J_dot v`` (m/s^2). acceleration: ``(n, P, 3)`` classical acceleration
            (m/s^2) at the given speed rates, by the engine's own acceleration routine; None without rates.
    """

    position: np.ndarray
    J: np.ndarray
    Jdot: np.ndarray | None
    Jdot_v: np.ndarray
    acceleration: np.ndarray | None


@dataclass(frozen=True)
class Dynamics:
    """Rigid-body dynamics at states over the shared speeds ``k``, reference coordinates (one state: no batch axis).

    ``M a + bias = tau``: M ``(n, k, k)``; bias ``(n, k)`` (Coriolis, centrifugal and gravity);
    gravity ``(n, k)`` the gravity part alone (``bias`` at zero speeds); forward ``(n, k)`` the
    accelerations at zero ``tau`` (no passive force, actuator or constraint), None where the engine has speeds
    the reference lacks. Units per speed: kg m^2 or kg; N m or N; rad/s^2 or m/s^2.
    """

    M: np.ndarray
    bias: np.ndarray
    gravity: np.ndarray
    forward: np.ndarray | None


@dataclass(frozen=True)
class Match:
    """Where some of the reference's joints sit in an engine's coordinates.

    ``kind``: the reference joint's type, or ``floating`` for three slides along the parent's axes then a ball
    (one engine joint, a floating joint relative to the parent). ``joints``: reference joint indices; ``ref_q``,
    ``ref_v``: their positions and speeds in the reference; ``q``, ``v``: the engine's, all index tuples.
    """

    kind: str
    joints: tuple
    ref_q: tuple
    ref_v: tuple
    q: tuple
    v: tuple


def by_order(reference, matches, engine_joints) -> list[Match]:
    """``matches`` completed by structure where names say nothing: the reference's unmatched joints, in order, paired
    with the engine's unmatched joints, in order, when the two sequences have the same joint types (a file whose
    bodies and joints are unnamed: each parser names them its own way, none the file's). ``engine_joints``: the
    engine's joints in its order, ``(id, type, its positions (tuple), its speeds (tuple))``; those already in
    ``matches`` (by their speeds) are skipped."""
    used = {v for m in matches for v in m.v}
    matched = {k for m in matches for k in m.joints}
    mine = [(k, j, qa, da) for k, ((_, j), qa, da) in enumerate(zip(reference.joints, reference.qadr(2),
                                                                      reference.dofadr)) if k not in matched]
    theirs = [e for e in engine_joints if not set(e[3]) & used]
    if not mine or [j.type for _, j, _, _ in mine] != [e[1] for e in theirs]:
        return list(matches)
    extra = [Match(j.type, (k,), tuple(range(qa, qa + NQ[j.type])), tuple(range(da, da + NV[j.type])), tuple(q),
                   tuple(v)) for (k, j, qa, da), (_, _, q, v) in zip(mine, theirs)]
    return sorted(list(matches) + extra, key=lambda m: m.joints)


def match_by_name(reference, engine_joints) -> list[Match]:
    """relacc's one-speed joints matched to an engine's by name and type, then by order where names say nothing
    (:func:`by_order`). ``engine_joints``: ``(name, type, its position index, its speed index)`` in the engine's
    order, hinges and slides only (a URDF engine's revolute and prismatic joints)."""
    theirs = {name: (kind, qi, vi) for name, kind, qi, vi in engine_joints}
    matches = []
    for k, ((_, j), qa, da) in enumerate(zip(reference.joints, reference.qadr(2), reference.dofadr)):
        e = theirs.get(j.name)
        if e is not None and e[0] == j.type:
            matches.append(Match(j.type, (k,), (qa,), (da,), (e[1],), (e[2],)))
    return by_order(reference, matches, [(name, kind, (qi,), (vi,)) for name, kind, qi, vi in engine_joints])


def fixed_base_only(engine: str, path, reference, why: str) -> None:
    """Refuse a model whose tree (relacc's reading) has a free or ball joint, for an engine whose adapter relacc
    builds on a URDF's fixed base with one-speed joints (PyBullet, iDynTree); ``why``: what the engine does with one.

    Raises:
        ModelError: the tree has such a joint (the message names it and says why).
    """
    from relacc.errors import ModelError

    for _, j in reference.joints:
        if j.type in ("free", "ball"):
            said = why if j.type == "free" else f"relacc's {engine} adapter matches one-speed joints only"
            raise ModelError(f"{path}: joint {j.name} is a {'floating' if j.type == 'free' else 'spherical'} joint; "
                             f"{said}: relacc compares {engine} on URDFs whose joints are revolute, continuous, "
                             "prismatic or fixed")


def heads(reference) -> dict[str, list[str]]:
    """``{moving body name: [it and the bodies welded to it]}`` of relacc's tree, bodies welded to the world left out:
    the links an engine that keeps a URDF's links (PyBullet, iDynTree) is compared on, by the URDF's link names."""
    head: dict[int, int] = {}
    out: dict[str, list[str]] = {}
    for b, body in enumerate(reference.bodies):
        head[b] = b if body.joints else (head[body.parent] if body.parent >= 0 else -1)
        if head[b] >= 0:
            out.setdefault(reference.bodies[head[b]].name, []).append(body.name)
    return out


def solved_forward(M: np.ndarray, f: np.ndarray) -> np.ndarray:
    """``(n, nv)`` ``M^-1 f`` state by state, for an engine whose API offers no forward dynamics outside its stepper
    (PyBullet, iDynTree); a state whose mass matrix is singular (a joint that moves no inertia) is NaN: undefined."""
    out = np.full(f.shape, np.nan)
    for i in range(len(f)):
        try:
            out[i] = np.linalg.solve(M[i], f[i])
        except np.linalg.LinAlgError:
            pass
    return out


def combine(parts) -> tuple[float, np.ndarray, np.ndarray]:
    """``(mass, com, inertia about com)`` of rigid parts ``(mass, com (3,), inertia about own com (3, 3))``.

    All in one frame's components; the parallel-axis theorem moves each part to the common centre.
    """
    parts = list(parts)
    mass = float(sum(m for m, _, _ in parts))
    if mass <= 0:
        return mass, np.zeros(3), np.zeros((3, 3))
    com = sum(m * np.asarray(c, dtype=float) for m, c, _ in parts) / mass
    inertia = np.zeros((3, 3))
    for m, c, I in parts:
        d = np.asarray(c, dtype=float) - com
        inertia += np.asarray(I, dtype=float) + m * (d @ d * np.eye(3) - np.outer(d, d))
    return mass, com, inertia


def com(link: str) -> tuple[str, str]:
    """The point spec of a link's centre of mass (by the engine's own inertias), for :meth:`Adapter.points`."""
    return ("com", link)


def body(name: str) -> tuple[str, str]:
    """The point spec of one body's mass centre (a body, not its link), for :meth:`Adapter.points`."""
    return ("body", name)


def point(name: str) -> tuple[str, str]:
    """The point spec of a named point of the model (a MuJoCo site; a frame of that name elsewhere)."""
    return ("point", name)


class Answering:
    """What a comparison asks an evaluator at reference states, each question answered once for the same states
    (:class:`Answers`, in ``self.answers``): :meth:`dynamics` and :meth:`kinematics` of a batch, or of one state without
    its batch axis. An evaluator gives ``_dynamics(q, v)`` and ``_kinematics(q, v, a, links)`` of batches: an engine's
    :class:`Adapter`, relacc's own reading (:class:`relacc.validation.robots.tree.TreeRobot`)."""

    answers: Answers

    def dynamics(self, q: np.ndarray, v: np.ndarray) -> Dynamics:
        """:class:`Dynamics` at reference states ``q (n, nq)``, ``v (n, nv)`` (or one state, ``(nq,)``, ``(nv,)``:
        then without the batch axis; speeds the evaluator lacks: zero), the model's own gravity as the evaluator read
        it and nothing else; read-only, and evaluated once for the same states (:class:`Answers`)."""
        one = np.ndim(q) == 1
        q, v = np.atleast_2d(np.asarray(q, dtype=float)), np.atleast_2d(np.asarray(v, dtype=float))
        return first(self.answers("dynamics", (q, v), lambda: self._dynamics(q, v)), one)

    def kinematics(self, q: np.ndarray, v: np.ndarray, a: np.ndarray, links: Sequence[str]) -> Points:
        """Each named link's centre of mass at reference states ``q (n, nq)``, ``v (n, nv)``, rates ``a (n, nv)``, over
        the shared speeds: :class:`Points` ``(n, L, ...)`` (one state: ``(L, ...)``), ``J_dot v`` included; read-only,
        and evaluated once for the same states (:class:`Answers`)."""
        one = np.ndim(q) == 1
        q, v, a = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (q, v, a))
        return first(self.answers(("kinematics", tuple(links)), (q, v, a), lambda: self._kinematics(q, v, a, links)),
                     one)

    def _dynamics(self, q: np.ndarray, v: np.ndarray) -> Dynamics:
        """:meth:`dynamics` of a batch ``(n, nq)``, ``(n, nv)``, evaluated (the evaluator's own)."""
        raise NotImplementedError

    def _kinematics(self, q: np.ndarray, v: np.ndarray, a: np.ndarray, links: Sequence[str]) -> Points:
        """:meth:`kinematics` of a batch, evaluated (the evaluator's own)."""
        raise NotImplementedError


class Adapter(Answering, abc.ABC):
    """One model in one engine, matched to the reference (see the module docstring).

    Attributes:
        engine: its name. reference: the :class:`relacc.Tree` it is matched to. source: the file it read.
        structure: :class:`Structure`. matches: :class:`Match` per reference joint it has.
        warnings: its parser's messages. nq_e, nv_e: its own counts.
        global_coordinates: quantities it forms from differences of world positions (their accuracy follows
            :func:`relacc.core.scales.global_condition`).
        absolute_velocities: quantities it forms from world-frame spatial velocities, which carry B1's absolute
            translational speed in terms that cancel (:func:`relacc.core.scales.velocity_condition`).
    """

    engine: str = ""
    point_rates: bool = True
    """Whether :meth:`points` gives ``J_dot v`` and classical accelerations (an engine that offers neither fills them
    with NaN and sets this False: the comparison then leaves those two quantities out for it)."""
    varying_speed_maps: tuple[str, ...] = ()
    """The match kinds whose speed map ``T`` (:meth:`v_block`) depends on the position; every other kind's is the same
    at every position (``tests/test_adapter_contract.py`` holds each engine to its declaration)."""
    global_coordinates: frozenset = frozenset()
    absolute_velocities: frozenset = frozenset()
    structure: Structure
    """What the engine built, set by each adapter when it has loaded the model."""

    def __init__(self, reference: Tree, matches: Iterable[Match], nq_e: int, nv_e: int, source: object = None,
                 warnings: Iterable[str] = ()):
        self.reference, self.matches, self.nq_e, self.nv_e = reference, tuple(matches), int(nq_e), int(nv_e)
        self.source, self.warnings = source, list(warnings)
        self.dofs = np.array(sorted(i for m in self.matches for i in m.ref_v), dtype=int)
        self.qdofs = np.array(sorted(i for m in self.matches for i in m.ref_q), dtype=int)
        self.extra_dofs = self.nv_e - len(self.dofs)
        self._joint_plan: tuple | None = None  # (effects, resolved joint effects, matches): see _joint_forces
        self.answers = Answers()

    # --- what each engine implements -------------------------------------------------------------------------

    def inertia_allowance(self, reading: Any) -> float:
        """kg m^2: how far this engine's body inertias may be from relacc's ``reading`` of the same file by the
        engine's own documented numerical tolerances (0: none beyond rounding). Added, through the mass matrix, to
        the dynamics comparison's tolerance (:func:`relacc.validation.robots.agreement.compare_dynamics`)."""
        return 0.0

    @property
    @abc.abstractmethod
    def version(self) -> str:
        """The engine's version string."""

    @abc.abstractmethod
    def default_q(self) -> np.ndarray:
        """``(nq_e,)`` the engine's positions of joints the reference lacks (and the starting point of the rest)."""

    def q_block(self, match: Match, x: np.ndarray) -> np.ndarray:
        """The engine's positions ``(n, len(match.q))`` of one match from the reference's ``x (n, len(ref_q))``."""
        return x

    def q_back(self, match: Match, xe: np.ndarray) -> np.ndarray:
        """The inverse of :meth:`q_block`."""
        return xe

    def v_block(self, match: Match, x: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(T, T_dot)`` ``(n, len(match.v), len(ref_v))``: the match's engine speeds ``T w`` from the reference's
        positions ``x`` and speeds ``w`` (default: the same speeds)."""
        n, k = len(x), len(match.ref_v)
        return np.broadcast_to(np.eye(k), (n, k, k)), np.zeros((n, k, k))

    def v_block_inverse(self, match: Match, x: np.ndarray) -> np.ndarray:
        """``(n, len(ref_v), len(match.v))``: the inverse of :meth:`v_block`'s ``T`` at the reference's positions ``x``
        (an adapter whose ``T`` has a closed-form inverse gives it; default: LAPACK's)."""
        return np.linalg.inv(self.v_block(match, x, np.zeros((len(x), len(match.ref_v))))[0])

    @abc.abstractmethod
    def equations(self, qe: np.ndarray, ve: np.ndarray, effects: TreeEffects | None = None, t: ArrayLike = 0.0
                  ) -> tuple[np.ndarray, np.ndarray]:
        """``(M_e (n, nv_e, nv_e), f_e (n, nv_e))``: ``M_e vdot_e = f_e`` with ``f_e`` the generalized forces of
        exactly ``effects`` (a :class:`relacc.dynamics.tree_effects.TreeEffects`; None: the model's own gravity
        as the engine read it, nothing else) minus the Coriolis and centrifugal terms, at time ``t`` (s)."""

    @abc.abstractmethod
    def forward(self, qe: np.ndarray, ve: np.ndarray, effects: TreeEffects | None = None, t: ArrayLike = 0.0
                ) -> np.ndarray:
        """``(n, nv_e)`` the engine's forward dynamics under exactly ``effects`` (as :meth:`equations`)."""

    @abc.abstractmethod
    def points(self, qe: np.ndarray, ve: np.ndarray, ae: np.ndarray | None, specs: Sequence[tuple[str, str]], *,
               jdot: bool = False) -> Points:
        """:class:`Points` of ``specs`` (:func:`point`, :func:`com`) at engine states ``qe (n, nq_e)``,
        ``ve (n, nv_e)``, rates ``ae`` (or None); ``jdot``: also the Jacobian's rate as a matrix."""

    @abc.abstractmethod
    def stepper(self, effects: TreeEffects, dt: float, integrator: str, accuracy: float | None = None) -> Any:
        """The engine's integrator under exactly ``effects``, a :class:`relacc.dynamics.steps.Stepper` in engine
        coordinates; ``accuracy``: an error-controlled integrator's target (None: fixed steps).

        Raises:
            EngineError: an integrator the engine lacks, or an accuracy it cannot honour.
        """

    def load_forces(self, qe: np.ndarray, effects: TreeEffects, t: ArrayLike = 0.0) -> np.ndarray:
        """``(n, nv_e)`` the generalized forces of ``effects``' body loads at time ``t`` (s; a scalar or one per state;
        engines that configure their model to apply them, like MuJoCo, leave this zero)."""
        return np.zeros((len(qe), self.nv_e))

    def generalized_forces(self, qe: np.ndarray, ve: np.ndarray, effects: TreeEffects | None, t: ArrayLike = 0.0
                           ) -> np.ndarray:
        """``(n, nv_e)`` the generalized forces of ``effects``' joint springs, dampers and body loads at time ``t``
        (gravity excepted: it is the engine's gravity field). Joints' are relacc's (MuJoCo's passive force,
        :func:`relacc.dynamics.tree.joint_forces`) on the reference's speeds, mapped to the engine's by ``T^-T``
        (the same power); loads are the engine's own (:meth:`load_forces`)."""
        qe = np.atleast_2d(qe)
        tau = np.zeros((len(qe), self.nv_e))
        if effects is None:
            return tau
        if effects.joints:
            tau += self._joint_forces(qe, ve, effects)
        if effects.bodies:
            tau += self.load_forces(qe, effects, t)
        return tau

    def applied(self, effects: TreeEffects) -> dict:
        """What the engine is told to apply for ``effects``, as plain data for reports."""
        return {"effects": describe(effects)}

    def energy(self, qe: np.ndarray, ve: np.ndarray, effects: TreeEffects) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(kinetic, gravity, spring)`` energies ``(n,)`` J of engine states: relacc's formulas
        (:mod:`relacc.dynamics.tree_energy`) at the states mapped back to the reference's coordinates."""
        from relacc.dynamics.tree_energy import tree_energy

        q, v = self.from_engine(qe, ve)
        return tree_energy(self.reference, q, v, effects)

    def momenta(self, qe: np.ndarray, ve: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Linear (kg m/s) and angular (kg m^2/s, about the world origin) momenta ``(n, 3)`` of engine states."""
        from relacc.dynamics.tree_energy import tree_momenta

        q, v = self.from_engine(qe, ve)
        return tree_momenta(self.reference, q, v)

    def lost_offset(self, name: str) -> float:
        """Metres by which the engine's model misplaces the named point (0 unless an engine rounds the model)."""
        return 0.0

    @property
    def tree(self) -> Tree:
        """The :class:`relacc.Tree` this adapter is matched to (:attr:`reference`)."""
        return self.reference

    # --- built here, once for every engine ------------------------------------------------------------------

    def engine_q(self, q: np.ndarray) -> np.ndarray:
        """``(n, nq_e)`` the engine's positions of reference positions ``q (n, nq)``."""
        q = np.atleast_2d(np.asarray(q, dtype=float))
        qe = np.repeat(self.default_q()[None], len(q), axis=0)
        for m in self.matches:
            qe[:, list(m.q)] = self.q_block(m, q[:, list(m.ref_q)])
        return qe

    def speed_map(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(T, T_dot)`` ``(n, nv_e, len(dofs))``: the engine's speeds from the shared reference speeds,
        ``v_e = T v[dofs]``, and the map's rate along ``v``."""
        q, v = np.atleast_2d(np.asarray(q, dtype=float)), np.atleast_2d(np.asarray(v, dtype=float))
        n = len(q)
        column = {d: i for i, d in enumerate(self.dofs)}
        T, Td = np.zeros((n, self.nv_e, len(self.dofs))), np.zeros((n, self.nv_e, len(self.dofs)))
        for m in self.matches:
            Tm, Tdm = self.v_block(m, q[:, list(m.ref_q)], v[:, list(m.ref_v)])
            rows, cols = np.array(m.v)[:, None], np.array([column[d] for d in m.ref_v])[None, :]
            T[:, rows, cols], Td[:, rows, cols] = Tm, Tdm
        return T, Td

    def to_engine(self, q: ArrayLike, v: ArrayLike, a: ArrayLike | None = None) -> EngineStates:
        """Reference states ``q (n, nq)``, ``v (n, nv)`` (rates ``a`` or None) in the engine's coordinates, speeds the
        engine lacks dropped, with the speed map (:class:`EngineStates`)."""
        q, v = np.atleast_2d(np.asarray(q, dtype=float)), np.atleast_2d(np.asarray(v, dtype=float))
        T, Td = self.speed_map(q, v)
        vs = v[:, self.dofs]
        ve = np.einsum("nij,nj->ni", T, vs)
        ae = None if a is None else (np.einsum("nij,nj->ni", T, np.atleast_2d(a)[:, self.dofs])
                                     + np.einsum("nij,nj->ni", Td, vs))
        return EngineStates(np.ascontiguousarray(self.engine_q(q)), ve, ae, T, Td)

    def from_engine(self, qe: np.ndarray, ve: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Engine states back to the reference's ``(q (n, nq), v (n, nv))``; every reference speed must be shared.

        Raises:
            EngineError: the engine lacks some of the reference's joints.
        """
        if len(self.dofs) != self.reference.nv:
            raise EngineError(f"{self.engine} lacks some of the reference's joints: its states do not map back")
        qe, ve = np.atleast_2d(np.asarray(qe, dtype=float)), np.atleast_2d(np.asarray(ve, dtype=float))
        q = np.zeros((len(qe), self.reference.nq_in(2)))
        for m in self.matches:
            q[:, list(m.ref_q)] = self.q_back(m, qe[:, list(m.q)])
        T, _ = self.speed_map(q, np.zeros((len(q), self.reference.nv)))
        v = np.zeros((len(q), self.reference.nv))
        v[:, self.dofs] = np.linalg.solve(T, ve[..., None])[..., 0]
        return q, v

    def _joint_forces(self, qe, ve, effects) -> np.ndarray:
        """``(n, nv_e)`` the generalized forces of ``effects``' joint springs and dampers on the engine's speeds.

        Only the matches of joints with an effect are mapped back (a match's speeds map on their own: ``T`` is
        block-diagonal by match), each by its block ``T_m``: ``v = T_m^-1 v_e``, ``tau_e = T_m^-T f``. Steppers call
        this at every stage of every step, so the plan is made once per ``effects`` (:meth:`_plan_joint_forces`): the
        positions mapped back only where a spring or a varying ``T_m`` reads them, the matches whose ``T_m^-1`` is a
        constant factor (one speed, or a multiple of the identity) mapped in one operation, the others one by one.
        """
        cached = self._joint_plan
        if cached is None or cached[0] is not effects:
            cached = self._joint_plan = (effects, *self._plan_joint_forces(effects))
        _, forces, positions, (iv_s, ref_v_s, factors), matrices = cached
        n = len(qe)
        q, v = np.zeros((n, forces.nq)), np.zeros((n, forces.nv))
        x_of = {}
        for m, iq, ref_q in positions:
            x_of[m] = q[:, ref_q] = self.q_back(m, qe[:, iq])
        if len(factors):
            v[:, ref_v_s] = ve[:, iv_s] * factors
        blocks = []
        for m, iv, ref_v, T_inv in matrices:
            if T_inv is None:  # T depends on the position: inverted once for both directions
                T_inv = self.v_block_inverse(m, x_of[m])
            blocks.append(T_inv)
            v[:, ref_v] = (T_inv @ ve[:, iv, None])[..., 0]
        f = forces(q, v)
        tau = np.zeros((n, self.nv_e))
        if len(factors):
            tau[:, iv_s] = f[:, ref_v_s] * factors
        for (_, iv, ref_v, _), T_inv in zip(matrices, blocks):
            tau[:, iv] = (f[:, None, ref_v] @ T_inv)[:, 0]
        return tau

    def _plan_joint_forces(self, effects) -> tuple:
        """``(forces, positions, factors, matrices)`` for :meth:`_joint_forces`: the reference's
        :class:`relacc.dynamics.tree.JointForcePlan` of ``effects``' joints (case 2); ``(match, engine q, reference
        q)`` of the matches whose positions are read; ``(engine v, reference v, factor)`` arrays of the speeds whose
        ``T^-1`` is a constant factor (its sense; a product by it is the matrix product's bits); and
        ``(match, engine v, reference v, T^-1 or None)`` of the others (None: it varies with the position). Indices
        as slices where contiguous."""
        from relacc.dynamics.tree import joint_force_plan

        _, resolved, _ = effects.resolve(self.reference)
        sprung = {k for k, eff, _ in resolved if eff.stiffness}
        joints = {k for k, _, _ in resolved}
        matches = [m for m in self.matches if joints & set(m.joints)]
        if len(set().union(*(m.joints for m in matches))) < len(joints):
            raise EngineError(f"{self.engine} lacks a joint the effects name: its forces do not map")
        positions, scaled, matrices = [], [], []
        for m in matches:
            T_inv: float | np.ndarray | None = None
            if m.kind not in self.varying_speed_maps:
                T, _ = self.v_block(m, np.zeros((1, len(m.ref_q))), np.zeros((1, len(m.ref_v))))
                T_inv = np.linalg.inv(np.asarray(T[0], dtype=float))
                if np.array_equal(T_inv, T_inv[0, 0] * np.eye(len(T_inv))):
                    scaled += [(e, r, float(T_inv[0, 0])) for e, r in zip(m.v, m.ref_v)]
                    T_inv = float(T_inv[0, 0])
            if T_inv is None or sprung & set(m.joints):
                positions.append((m, _index(m.q), _index(m.ref_q)))
            if not isinstance(T_inv, float):
                matrices.append((m, _index(m.v), _index(m.ref_v), T_inv))
        factors = (_index(tuple(e for e, _, _ in scaled)), _index(tuple(r for _, r, _ in scaled)),
                   np.array([c for _, _, c in scaled]))
        return joint_force_plan(self.reference, resolved), positions, factors, matrices

    def _dynamics(self, q: np.ndarray, v: np.ndarray) -> Dynamics:
        x = self.to_engine(q, v)
        qe, ve, T, Td = x.q, x.v, x.T, x.T_dot
        Me, fe = self.equations(qe, ve)
        _, ge = self.equations(qe, np.zeros_like(ve))
        Tdv = np.einsum("nij,nj->ni", Td, v[:, self.dofs])
        forward = self.forward(qe, ve) if self.extra_dofs == 0 else None
        return mapped_dynamics(Me, fe, ge, forward, T, Tdv)

    def _kinematics(self, q: np.ndarray, v: np.ndarray, a: np.ndarray, links: Sequence[str]) -> Points:
        x = self.to_engine(q, v, a)
        qe, ve, ae, T, Td = x.q, x.v, x.a, x.T, x.T_dot
        p = self.points(qe, ve, ae, [com(name) for name in links])
        Tdv = np.einsum("nij,nj->ni", Td, v[:, self.dofs])
        return Points(p.position, p.J @ T[:, None], None, p.Jdot_v + np.einsum("nlij,nj->nli", p.J, Tdv),
                      p.acceleration)


def mapped_dynamics(M, f, g, forward, T, Tdv) -> Dynamics:
    """:class:`Dynamics` in the reference's speeds ``(n, k)`` from an evaluator's own: ``M (n, m, m)``, ``f (n, m)``
    (generalized forces minus the Coriolis and centrifugal terms), ``g (n, m)`` (``f`` at zero speeds: gravity),
    ``forward (n, m)`` or None, through ``v_e = T v`` (``T (n, m, k)``) and ``T_dot v`` (``Tdv (n, m)``):
    ``M_ref = T^T M T``, ``bias = T^T (-f + M T_dot v)``, ``gravity = -T^T g``, ``a = T^-1 (a_e - T_dot v)``."""
    Tt = np.swapaxes(T, 1, 2)
    bias = np.einsum("nij,nj->ni", Tt, -f + np.einsum("nij,nj->ni", M, Tdv))
    if forward is not None:
        forward = np.linalg.solve(T, (forward - Tdv)[..., None])[..., 0]
    return Dynamics(Tt @ M @ T, bias, np.einsum("nij,nj->ni", Tt, -g), forward)


class Answers:
    """An evaluator's last answers (a :class:`Dynamics` or :class:`Points`) by question and state arrays: a comparison
    asks each evaluator the same question at the same states once per engine, case and pair of the referee. Called as
    ``answers(what, arrays, make)``: ``make()``'s answer, its arrays made read-only, or the one kept for the same
    ``what`` and arrays (compared by shape and bytes). An evaluator's model never changes after it is made, so an
    answer stays right; at most :attr:`SIZE` are kept."""

    SIZE = 8

    def __init__(self):
        self._kept: dict = {}

    def __call__(self, what, arrays: tuple, make):
        key = (what, *((a.shape, a.tobytes()) for a in arrays))
        if key not in self._kept:
            if len(self._kept) >= self.SIZE:
                self._kept.clear()
            answer = make()
            for x in dataclasses.astuple(answer):
                if isinstance(x, np.ndarray):
                    x.flags.writeable = False
            self._kept[key] = answer
        return self._kept[key]


def first(result, one: bool):
    """``result`` (a :class:`Dynamics` or :class:`Points` of a batch) at its only state when ``one``."""
    if not one:
        return result
    values = (getattr(result, f.name) for f in dataclasses.fields(result))
    return type(result)(*(None if x is None else x[0] for x in values))


def _index(indices: tuple) -> slice | np.ndarray:
    """``indices`` as a slice where they are contiguous and increasing (a view, not a copy), else as an array."""
    i = np.asarray(indices, dtype=int)
    if len(i) and np.array_equal(i, np.arange(i[0], i[0] + len(i))):
        return slice(int(i[0]), int(i[0]) + len(i))
    return i


def _solve(T, b) -> np.ndarray:
    """``x (n, k)`` with ``T x = b`` for ``T (n, k, k)`` (or one ``(1, k, k)`` for all), ``b (n, k)``: a hinge's or
    slide's ``k = 1`` by division."""
    if T.shape[-1] == 1:
        return b / T[:, 0]
    return np.linalg.solve(T, b[..., None])[..., 0]


def describe(effects) -> dict:
    """Plain data of a :class:`relacc.dynamics.tree_effects.TreeEffects` (None: the model's own gravity)."""
    if effects is None:
        return {"gravity": "the model's own"}
    out = {"gravity": "the model's own" if effects.gravity is None else effects.gravity.tolist()}
    if effects.joints:
        out["joints"] = {k: {"stiffness": e.stiffness, "damping": e.damping} for k, e in effects.joints.items()}
    if effects.bodies:
        out["bodies"] = {k: {"force": b.force.tolist(), "torque": b.torque.tolist(), "frequency": b.frequency}
                         for k, b in effects.bodies.items()}
    return out


def fixed_step_only(name: str, accuracy) -> None:
    """Refuse an error-controlled run for an engine that has fixed-step integrators only."""
    if accuracy is not None:
        raise EngineError(f"{name} has fixed-step integrators only; drop the accuracy (got {accuracy})")
