"""What relacc made of a description file: its tree, and everything a user needs to act on a difference.

A :class:`Reading` holds relacc's :class:`relacc.Tree` of the file (bodies in the file's order, every body kept:
one welded by a fixed joint or without joints stays a body of its own, moving with its parent) and, beside it, what
the tree does not carry: where each element is in the file (``places``), joint ranges, dampers and springs, what
relacc took from elsewhere (``taken``: a body's mass properties it cannot compute), what the file has that relacc does
not evaluate (``unevaluated``: constraints, tendons, actuators with dynamics), what it did as the format specifies
(``notes``), and what is physically impossible in the file (``findings``, :mod:`relacc.reading.physical`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from relacc.core.tree.model import Tree


@dataclass(frozen=True)
class Finding:
    """A body of the file that is not a physical rigid body: ``body``, the ``condition`` broken (one phrase), and
    ``numbers``, what it is (text with the values), and ``place``, where (``file:line``)."""

    body: str
    condition: str
    numbers: str
    place: str = ""

    def sentence(self) -> str:
        return f"body {self.body} ({self.place}): {self.condition}: {self.numbers}"

    def as_json(self) -> dict:
        return {"body": self.body, "condition": self.condition, "numbers": self.numbers, "place": self.place}


UNEVALUATED_KINDS = ("coupling", "constraint", "tendon", "actuator", "gravcomp", "fluid", "friction")
"""What a line of :attr:`Reading.unevaluated` is about: joints coupled (every URDF ``<mimic>``, MJCF equality
constraints that are all joint equalities), other constraints (loops, connect, weld...), tendons, actuators with
dynamics, gravity compensation, fluid forces, dry friction."""


@dataclass(frozen=True)
class Coupling:
    """A joint that follows another: ``q_follower = offset + multiplier q_leader`` (rad or m; positions as the file
    measures them), ``higher`` the coefficients of ``q_leader^2 ..`` (an MJCF ``polycoef``'s last three; zeros for a
    URDF ``<mimic>``); ``leader`` None for a joint held at ``offset`` (an MJCF joint equality without ``joint2``).
    ``kind``: ``"mimic"`` or ``"equality"``; ``place``: the element's ``file:line``."""

    follower: str
    leader: str | None
    offset: float
    multiplier: float
    higher: tuple = (0.0, 0.0, 0.0)
    kind: str = "mimic"
    place: str = ""


@dataclass(frozen=True, eq=False)
class Reading:
    """relacc's own reading of a description file (see the module docstring).

    Attributes:
        tree: the tree (m, kg, kg m^2, rad; each body's mass centre and inertia in its own frame).
        format: ``"mjcf"`` or ``"urdf"``. source: the file.
        places: ``{("body" | "joint" | "inertial", name): "file:line"}``.
        ranges: ``{joint name: (lower, upper)}`` of the limited hinges and slides (rad or m).
        damping: ``{joint name: (nv,) N m s/rad or N s/m per speed}`` (zero entries left out).
        stiffness: ``{joint name: (stiffness, spring reference)}`` of joints with a spring (N m/rad or N/m).
        taken: ``{body name: what relacc took from where, one phrase}``: those bodies' terms cannot judge the engine
            they came from.
        unevaluated: one line per kind of element the file has that relacc's comparisons leave out.
        notes: what relacc did as the format specifies (normalized quaternions, left-out whitespace), one line each.
        findings: :class:`Finding` per body that is not physical.
        turned_inertials: ``{body name: (3, 3) inertia as written}`` of the URDF inertials whose ``<origin rpy>``
            turns them (kg m^2, in the inertial's own axes): to reproduce an engine that drops the rotation.
        facts: what an engine's other reading depends on (an MJCF's ``world_children``, ``default_geom_masses``,
            ``gravity_written``, ``gravity_disabled``).
        variant: the engine's way of reading the file this reading follows (:data:`relacc.reading.mjcf.VARIANTS`,
            :data:`relacc.reading.urdf.VARIANTS`; empty: the format's).
        friction: ``{joint name: dry friction}`` (MJCF ``frictionloss``, URDF ``<dynamics friction>``; N m or N) of the
            joints that have one: compared by ``relacc diff``, not evaluated by the dynamics.
        gravcomp: ``{body name: factor}`` (MJCF ``gravcomp``: MuJoCo applies ``factor`` times the body's weight
            upward at its mass centre) of the bodies that have one: compared by ``relacc diff``, not evaluated by the
            dynamics.
        couplings: :class:`Coupling` per URDF ``<mimic>`` and active MJCF joint equality: compared by ``relacc diff``,
            not evaluated by the dynamics (said in ``unevaluated``).
        unevaluated_kinds: the kind of each line of ``unevaluated`` (:data:`UNEVALUATED_KINDS`).
        sensitivity: ``{joint name: s}`` of the joints whose stiffness and damping the format derives from the mass
            matrix at the reference configuration (MJCF ``springdamper``, from the diagonal of its inverse): how
            much the mass matrix's rounding moves them, relatively, per unit of
            :func:`relacc.core.tolerances.robot_tolerance` (the largest over the joint's speeds of
            :func:`relacc.core.tolerances.inverse_diagonal_sensitivity`).
    """

    tree: Tree
    format: str
    source: str
    places: dict = field(default_factory=dict)
    ranges: dict = field(default_factory=dict)
    damping: dict = field(default_factory=dict)
    stiffness: dict = field(default_factory=dict)
    taken: dict = field(default_factory=dict)
    unevaluated: tuple = ()
    notes: tuple = ()
    findings: tuple = ()
    turned_inertials: dict = field(default_factory=dict)
    facts: dict = field(default_factory=dict)
    variant: frozenset = frozenset()
    friction: dict = field(default_factory=dict)
    gravcomp: dict = field(default_factory=dict)
    couplings: tuple = ()
    unevaluated_kinds: tuple = ()
    sensitivity: dict = field(default_factory=dict)

    def place(self, kind: str, name: str) -> str:
        """``file:line`` of an element, or the file when unknown."""
        return self.places.get((kind, name), self.source)

    def joint_damping(self, name: str, nv: int) -> np.ndarray:
        return np.asarray(self.damping.get(name, np.zeros(nv)), dtype=float)
