"""What may act on a tree: gravity, springs and dampers on named joints, loads on named bodies.

Absent means off, and off means not computed. Gravity is the tree's (its model file's) unless
:class:`TreeEffects` gives another; nothing else from a model file acts (no contacts, actuators,
joint damping or limits) unless named here.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from relacc.core.cases import fixed_vector
from relacc.core.tolerances import QUATERNION_NORM_TOLERANCE
from relacc.errors import InputError

if TYPE_CHECKING:
    from relacc.core.tree import Tree


def _num(owner, name, value, minimum=None) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InputError(f"{owner}: {name} must be a number, got {value!r:.60}")
    x = float(value)
    if not np.isfinite(x) or (minimum is not None and x < minimum):
        raise InputError(f"{owner}: {name} must be finite" + (f" and >= {minimum}" if minimum is not None else "")
                         + f", got {x}")
    return x


@dataclass(frozen=True)
class JointEffect:
    """A spring and a damper on one joint, acting on its MuJoCo (case 2) speeds.

    Attributes:
        stiffness: N/m (slide), N m/rad (hinge, ball); 0 for none. Free joints take none.
        damping: N s/m or N m s/rad, on every speed of the joint; 0 for none.
        rest: where the spring is relaxed: the coordinate (hinge rad, slide m; default 0, MuJoCo's
            ``springref``) or, for a ball, a unit quaternion ``(w, x, y, z)`` (default identity). A ball's
            spring torque is ``-k Log(rest^-1 q)`` (child components), MuJoCo's ``mju_subQuat``.
    """

    stiffness: float = 0.0
    damping: float = 0.0
    rest: object = None

    def __post_init__(self):
        object.__setattr__(self, "stiffness", _num("joint effect", "stiffness", self.stiffness, 0.0))
        object.__setattr__(self, "damping", _num("joint effect", "damping", self.damping, 0.0))


@dataclass(frozen=True)
class BodyLoad:
    """A force at a body's mass centre and a torque on it, fixed-frame components.

    ``force(t) = force * s(t)``, ``torque(t) = torque * s(t)`` with ``s = 1`` (``frequency`` 0, constant) or
    ``s = sin(2 pi frequency t + phase)`` (sinusoidal). Units: N, N m, Hz, rad.
    """

    force: np.ndarray = field(default_factory=lambda: np.zeros(3))
    torque: np.ndarray = field(default_factory=lambda: np.zeros(3))
    frequency: float = 0.0
    phase: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "force", fixed_vector("body load", "force", self.force))
        object.__setattr__(self, "torque", fixed_vector("body load", "torque", self.torque))
        object.__setattr__(self, "frequency", _num("body load", "frequency", self.frequency, 0.0))
        object.__setattr__(self, "phase", _num("body load", "phase", self.phase))

    def factor(self, t: ArrayLike) -> np.ndarray:
        """``s(t)``: 1, or the sinusoid at time ``t`` (s)."""
        if self.frequency == 0:
            return np.ones_like(np.asarray(t, dtype=float))
        return np.sin(2 * np.pi * self.frequency * np.asarray(t, dtype=float) + self.phase)


@dataclass(frozen=True, eq=False)
class TreeEffects:
    """Effects on a tree. ``gravity``: ``(3,)`` m/s^2 fixed components, or None for the tree's own;
    ``joints``: ``{joint name: JointEffect}``; ``bodies``: ``{body name: BodyLoad}``."""

    gravity: np.ndarray | None = None
    joints: dict = field(default_factory=dict)
    bodies: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.gravity is not None:
            object.__setattr__(self, "gravity", fixed_vector("effects", "gravity", self.gravity))
        for name, value in dict(self.joints).items():
            if not isinstance(value, JointEffect):
                raise InputError(f"effects: joint {name!r} must map to a relacc JointEffect, "
                                 f"got {type(value).__name__}")
        for name, value in dict(self.bodies).items():
            if not isinstance(value, BodyLoad):
                raise InputError(f"effects: body {name!r} must map to a relacc BodyLoad, got {type(value).__name__}")
        object.__setattr__(self, "joints", dict(self.joints))
        object.__setattr__(self, "bodies", dict(self.bodies))

    def active(self) -> tuple[str, ...]:
        """Names of what acts, in a fixed order: ``gravity`` (when given and not zero), ``joint springs``,
        ``joint dampers``, ``body loads``."""
        out = []
        if self.gravity is not None and np.any(self.gravity):
            out.append("gravity")
        if any(e.stiffness for e in self.joints.values()):
            out.append("joint springs")
        if any(e.damping for e in self.joints.values()):
            out.append("joint dampers")
        if self.bodies:
            out.append("body loads")
        return tuple(out)

    @property
    def conserves_energy(self) -> bool:
        """True when only conservative effects act (gravity, springs)."""
        return not set(self.active()) - {"gravity", "joint springs"}

    @property
    def conserves_momentum(self) -> bool:
        """True when no external force or torque acts (joint springs and dampers are internal)."""
        return not set(self.active()) & {"gravity", "body loads"}

    def describe(self) -> dict:
        """Plain data: each effect and its values."""
        out = {}
        if self.gravity is not None:
            out["gravity"] = self.gravity.tolist()
        for name, e in self.joints.items():
            out[f"joint {name}"] = {"stiffness": e.stiffness, "damping": e.damping,
                                    "rest": None if e.rest is None else np.asarray(e.rest, dtype=float).tolist()}
        for name, b in self.bodies.items():
            out[f"body {name}"] = {"force": b.force.tolist(), "torque": b.torque.tolist(), "frequency": b.frequency,
                                   "phase": b.phase}
        return out

    def resolve(self, tree: "Tree") -> tuple:
        """``(gravity, [(joint index, JointEffect, rest)], [(body index, BodyLoad)])``, names checked against ``tree``.

        Raises:
            InputError: an unknown joint or body, a spring on a free joint, a bad rest value.
        """
        gravity = tree.gravity if self.gravity is None else self.gravity
        joints = []
        for name, eff in self.joints.items():
            k = tree.joint(name)
            kind = tree.joints[k][1].type
            rest: np.ndarray | float  # a ball's rest quaternion, a hinge's or slide's rest coordinate
            if kind == "free" and eff.stiffness:
                raise InputError(f"effects: joint {name!r} is free: it takes a damper, not a spring")
            if kind == "ball":
                rest = np.array((1.0, 0.0, 0.0, 0.0)) if eff.rest is None else \
                    fixed_vector(f"effects: joint {name!r}", "rest", eff.rest, 4)
                if abs(float(rest @ rest) - 1) > QUATERNION_NORM_TOLERANCE:
                    raise InputError(f"effects: joint {name!r}: rest must be a unit quaternion (w, x, y, z), its "
                                     f"squared norm within {QUATERNION_NORM_TOLERANCE:g} of 1 (never normalized)")
            else:
                rest = 0.0 if eff.rest is None else _num(f"effects: joint {name!r}", "rest", eff.rest)
            joints.append((k, eff, rest))
        bodies = [(tree.body(name), load) for name, load in self.bodies.items()]
        return gravity, joints, bodies


NO_EFFECTS = TreeEffects()
"""Gravity of the tree's model file, nothing else."""
