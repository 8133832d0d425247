"""The physical effects a scene may switch on. Absent means off, and off means not computed.

Every vector is in fixed-frame components unless said otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import TYPE_CHECKING

import numpy as np

from relacc.errors import InputError

if TYPE_CHECKING:
    from relacc.dynamics.tree_effects import TreeEffects


def _vec3(name, value):
    try:
        arr = np.array(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected 3 numbers, got {value!r}") from None
    if arr.dtype.kind not in "iuf" or arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise InputError(f"{name}: expected 3 finite numbers, got {value!r}")
    arr = arr.astype(float)
    arr.setflags(write=False)
    return arr


def _nonneg(name, value, allow_vector=True):
    """A non-negative scalar, or (``allow_vector``) three non-negative numbers, as a (3,) array."""
    if isinstance(value, (bool, str)) or value is None:
        raise InputError(f"{name}: expected a non-negative number{' or 3 of them' if allow_vector else ''}, "
                         f"got {value!r}")
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected a non-negative number, got {value!r}") from None
    if arr.shape == ():
        arr = np.full(3, float(arr))
    if arr.shape != (3,) or (not allow_vector and not np.all(arr == arr[0])):
        raise InputError(f"{name}: expected a non-negative number{' or 3 of them' if allow_vector else ''}, "
                         f"got {value!r}")
    if not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise InputError(f"{name}: must be finite and >= 0, got {value!r}")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class Effects:
    """What acts on the chain. Every field None means that effect is off.

    Attributes:
        gravity: ``(3,)`` gravitational acceleration, fixed components, m/s^2.
        spring_stiffness: ``(3,)`` stiffness of the spring on the prismatic
            offset, per B1 axis, N/m; with ``spring_rest`` ``(3,)`` m (B1 components).
        spring_damping: ``(3,)`` viscous damping on the prismatic offset, N s/m.
        ball_damping: viscous damping on the spherical joint, N m s/rad: a
            torque ``-c omega_hat_B2`` on B2 and its reaction on B1.
        force_G2: ``(3,)`` constant force at G2, fixed components, N.
        torque_B1, torque_B2: ``(3,)`` constant torques on B1, B2, fixed components, N m.
    """

    gravity: np.ndarray | None = None
    spring_stiffness: np.ndarray | None = None
    spring_rest: np.ndarray | None = None
    spring_damping: np.ndarray | None = None
    ball_damping: float | None = None
    force_G2: np.ndarray | None = None
    torque_B1: np.ndarray | None = None
    torque_B2: np.ndarray | None = None

    def __post_init__(self):
        for name in ("gravity", "spring_rest", "force_G2", "torque_B1", "torque_B2"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _vec3(f"effects.{name}", getattr(self, name)))
        for name in ("spring_stiffness", "spring_damping"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _nonneg(f"effects.{name}", getattr(self, name)))
        if self.spring_stiffness is not None and self.spring_rest is None:
            object.__setattr__(self, "spring_rest", _vec3("effects.spring_rest", (0.0, 0.0, 0.0)))
        if self.ball_damping is not None:
            object.__setattr__(self, "ball_damping",
                               float(_nonneg("effects.ball_damping", self.ball_damping, allow_vector=False)[0]))

    def active(self) -> tuple[str, ...]:
        """Names of the effects that are on, in a fixed order."""
        return tuple(f.name for f in fields(self) if f.name != "spring_rest" and getattr(self, f.name) is not None)

    @property
    def conserves_energy(self) -> bool:
        """True when only conservative effects act (gravity, spring stiffness)."""
        return not set(self.active()) - {"gravity", "spring_stiffness"}

    @property
    def conserves_momentum(self) -> bool:
        """True when no external force or torque acts (internal springs and dampers allowed)."""
        return not set(self.active()) & {"gravity", "force_G2", "torque_B1", "torque_B2"}

    def without(self, name: str) -> "Effects":
        """The same effects with one switched off (``spring_stiffness`` also drops ``spring_rest``)."""
        return replace(self, **{name: None}, **({"spring_rest": None} if name == "spring_stiffness" else {}))

    def without_all_but(self, name: str) -> "Effects":
        """Only one of these effects (``spring_stiffness`` keeps its ``spring_rest``)."""
        keep = (name, "spring_rest") if name == "spring_stiffness" else (name,)
        return Effects(**{k: getattr(self, k) for k in keep})

    def for_tree(self) -> TreeEffects:
        """The same effects on the chain's tree (:meth:`relacc.Tree.from_chain`, ``models/two_body.xml``), by joint
        and body name, for the engines' adapters: the slides ``s2_x``, ``s2_y``, ``s2_z`` get the spring and
        damper per axis, the ball ``B2_ball`` its damping (a torque ``-c omega_hat`` on B2 and its reaction on B1,
        the ball's generalized force), ``B2`` the force at G2 (its mass centre) and its torque, ``B1`` its torque;
        gravity off is zero gravity (not the model file's)."""
        from relacc.dynamics.tree_effects import BodyLoad, JointEffect, TreeEffects

        joints = {}
        for k, axis in enumerate("xyz"):
            stiffness = 0.0 if self.spring_stiffness is None else float(self.spring_stiffness[k])
            damping = 0.0 if self.spring_damping is None else float(self.spring_damping[k])
            if stiffness or damping:
                rest = 0.0 if self.spring_rest is None else float(self.spring_rest[k])
                joints[f"s2_{axis}"] = JointEffect(stiffness, damping, rest)
        if self.ball_damping:
            joints["B2_ball"] = JointEffect(damping=self.ball_damping)
        bodies = {}
        zero = np.zeros(3)
        if self.force_G2 is not None or self.torque_B2 is not None:
            bodies["B2"] = BodyLoad(zero if self.force_G2 is None else self.force_G2,
                                    zero if self.torque_B2 is None else self.torque_B2)
        if self.torque_B1 is not None:
            bodies["B1"] = BodyLoad(zero, self.torque_B1)
        return TreeEffects(zero if self.gravity is None else self.gravity, joints, bodies)

    def describe(self) -> dict:
        """Plain data: each active effect and its value."""
        out = {}
        for n in self.active() + (("spring_rest",) if self.spring_stiffness is not None else ()):
            v = getattr(self, n)
            out[n] = v.tolist() if isinstance(v, np.ndarray) else v
        return out


NONE = Effects()
"""No effect at all: torque-free, force-free motion."""
