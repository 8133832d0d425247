"""One interface for a robot model loaded in one engine, in relacc's common coordinates.

relacc compares robots in **MuJoCo's coordinates** (the MJCF's own), joint by joint in MuJoCo's
order, and each adapter converts its engine's conventions once, in its own module:

* free joint: ``q = [p (3), quat (4)]``, ``p`` the body frame's origin in world (m), ``quat`` the
  body's orientation ``(w, x, y, z)``; ``v = [p_dot (3, world components, m/s), omega (3, body
  components, rad/s)]``;
* ball joint: ``q`` the child's orientation relative to its parent, ``(w, x, y, z)``; ``v`` its
  angular velocity relative to the parent, child components (rad/s);
* hinge, slide: one angle (rad) or displacement (m) and its rate, MuJoCo's ``qpos``/``qvel``
  (``ref`` included: the body is where the MJCF draws it at ``q = ref``).

An engine whose speeds differ (Pinocchio: a free joint's linear velocity in body components; Drake:
a free joint's angular velocity in world components, a ball's in the parent's) maps them by a speed
map ``v_e = T(q) v``: its mass matrix is ``T^T M_e T``, its bias ``T^T (b_e + M_e T_dot v)``, its
accelerations ``a = T^-1 (a_e - T_dot v)``, its Jacobians ``J_e T``. A free joint's speeds are the
note's case 2 in MuJoCo and case 1 (reordered) in Drake; Pinocchio's are neither (the body's spatial
velocity).

Every adapter exposes :class:`Robot`: its structure at the reference configuration
(:class:`Structure`), and the dynamics and the links' centre-of-mass kinematics at a state, all in
the common coordinates restricted to the degrees of freedom it shares with the reference
(``dofs``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

JOINT_TYPES = ("free", "ball", "slide", "hinge")
"""Joint types in the common description (MuJoCo's names)."""

NQ = {"free": 7, "ball": 4, "slide": 1, "hinge": 1}
NV = {"free": 6, "ball": 3, "slide": 1, "hinge": 1}


@dataclass(frozen=True)
class Joint:
    """One joint as an engine sees it, at the reference configuration.

    Attributes:
        name: the MJCF joint's name. type: one of :data:`JOINT_TYPES`. body: the body it moves.
        axis: ``(3,)`` unit axis in world components (hinge, slide), else None.
        anchor: ``(3,)`` the joint's position in world (m).
        armature, damping: ``(nv,)`` per degree of freedom (kg m^2 or kg; N m s/rad or N s/m).
    """

    name: str
    type: str
    body: str
    axis: np.ndarray | None = field(repr=False)
    anchor: np.ndarray = field(repr=False)
    armature: np.ndarray = field(repr=False)
    damping: np.ndarray = field(repr=False)


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


@dataclass(frozen=True)
class Structure:
    """What an engine made of a model file: joints and links at the reference configuration, gravity, mass.

    Attributes:
        nq, nv: the engine's own counts. joints: in the reference's order, those the engine has.
        links: one per moving body it has. gravity: ``(3,)`` m/s^2, world. total_mass: kg, every body.
        bodies: every body name it has (world excluded).
    """

    nq: int
    nv: int
    joints: tuple[Joint, ...]
    links: tuple[Link, ...]
    gravity: np.ndarray = field(repr=False)
    total_mass: float
    bodies: tuple[str, ...]


@dataclass(frozen=True)
class LinkKinematics:
    """The links' centres of mass at one state, common coordinates.

    Attributes:
        position: ``(L, 3)`` m, world. J: ``(L, 3, n)`` the point's velocity Jacobian over the shared
            speeds (m/s per unit speed). Jdot_v: ``(L, 3)`` ``J_dot v``, m/s^2 (classical, world).
        acceleration: ``(L, 3)`` classical acceleration at the given speed rates, m/s^2, world.
    """

    position: np.ndarray
    J: np.ndarray
    Jdot_v: np.ndarray
    acceleration: np.ndarray


@dataclass(frozen=True)
class Dynamics:
    """Rigid-body dynamics at one state over the shared speeds, common coordinates.

    ``M a + bias = tau``: M ``(n, n)``; bias ``(n,)`` (Coriolis, centrifugal and gravity);
    gravity ``(n,)`` the gravity part alone (``bias`` at zero speeds); forward ``(n,)`` the
    accelerations at zero ``tau`` (no passive force, actuator or constraint). Units per speed:
    kg m^2 or kg; N m or N; rad/s^2 or m/s^2.
    """

    M: np.ndarray
    bias: np.ndarray
    gravity: np.ndarray
    forward: np.ndarray


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


class Robot:
    """A model file loaded in one engine (subclasses: one per engine, in their own modules).

    Attributes:
        engine: its name. structure: :class:`Structure`.
        dofs: ``(n,)`` indices of the reference's speeds that this engine shares, ascending;
            :meth:`dynamics` and :meth:`kinematics` answer over these. qdofs: the same for positions.
    """

    engine: str
    structure: Structure
    dofs: np.ndarray
    qdofs: np.ndarray

    def dynamics(self, q, v) -> Dynamics:
        """:class:`Dynamics` at the reference's ``q (nq_ref,)``, ``v (nv_ref,)`` (speeds it lacks: zero)."""
        raise NotImplementedError

    def kinematics(self, q, v, a, links) -> LinkKinematics:
        """:class:`LinkKinematics` of the named links at ``q``, ``v``, speed rates ``a`` (reference coordinates)."""
        raise NotImplementedError
