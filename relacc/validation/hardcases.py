"""The hard-case catalogue: states where accuracy is hardest to keep, and what to expect there.

Every entry is named, parametrized and states its accuracy model. Running an
entry compares, for each case it applies to,

* the core against complex-step derivatives of its own position and V
  (velocity, V u, acceleration, Vdot): condition 1 everywhere, because the
  note's forward formulas never divide and never subtract positions;
* each engine against the core: condition 1, except for the quantities the
  engine forms in global coordinates (``Engine.global_coordinates``), whose
  condition is :func:`relacc.core.scales.global_condition`,
  ``1 + |s1| m / scale``.

An entry passes when every error is at most ``c eps condition`` and every
value is finite.

Families:

* ``gimbal``: case 3 with the middle angle of B1 or B2 at
  ``+-(pi/2 - delta)``, delta from 1e-1 to 1e-12 and 0.
* ``quaternion``: identity, half turns (w = 0), the antipodal sign (w < 0),
  near-identity relative rotations.
* ``spin``: angular rates up to 1e6 rad/s (angular accelerations scaled alike).
* ``far``: B1's origin up to 1e8 m from R's origin.
* ``geometry``: ``|r2'|`` or ``|q2'|`` from 0 and 1e-12 m to 1e3 m; prismatic
  offsets up to 1e3 m.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from enum import StrEnum

import numpy as np

import relacc
from relacc.core.cases import Case
from relacc.core.chain import TwoBodyChain
from relacc.core.scales import term_scales
from relacc.core.states import random_states, random_unit_quaternions
from relacc.fixtures import Fixture
from relacc.fixtures.model import inline
from relacc.validation.compare import against_derivatives, against_engines

N_STATES = 12
"""States per entry and case."""


class EditKind(StrEnum):
    """How a catalogue entry changes its seeded states (:func:`states_for`)."""

    GIMBAL = "gimbal"                # a middle 1-2-3 angle at sign (pi/2 - value)
    IDENTITY = "identity"            # both quaternions (1, 0, 0, 0)
    HALF_TURN = "half_turn"          # both quaternions with w = 0
    ANTIPODAL = "antipodal"          # both quaternions with w < 0
    NEAR_IDENTITY = "near_identity"  # B2's relative rotation by value rad
    SPIN = "spin"                    # angular speeds and their rates of norm value
    FAR = "far"                      # |s1| = value m
    S2 = "s2"                        # |s2'| = value m


@dataclass(frozen=True)
class Edit:
    """A catalogue entry's change to its seeded states.

    Attributes:
        kind: what changes. value: its knob (rad for ``GIMBAL``'s delta and ``NEAR_IDENTITY``'s angle, rad/s for
            ``SPIN``, m for ``FAR`` and ``S2``; unused otherwise). body: ``B1`` or ``B2`` (``GIMBAL``). sign: the
            middle angle's sign (``GIMBAL``).
    """

    kind: EditKind
    value: float = 0.0
    body: str = ""
    sign: int = 1


@dataclass(frozen=True)
class HardCase:
    """One entry of the catalogue.

    Attributes:
        name: unique id, e.g. ``gimbal-B1+1e-06``.
        family: ``gimbal``, ``quaternion``, ``spin``, ``far`` or ``geometry``.
        parameter: the family's knob (delta in rad, rate in rad/s, distance
            or length in m; 0 for the quaternion family).
        cases: the cases it applies to.
        description: one line.
        model: the accuracy model, in words.
        geometry: overrides of the chain (``q2``, ``r2``), or empty.
        edit: the state edit (:class:`Edit`, :func:`states_for`), or None.
    """

    name: str
    family: str
    parameter: float
    cases: tuple[int, ...]
    description: str
    model: str
    geometry: dict = field(default_factory=dict)
    edit: Edit | None = None


_COND1 = "error <= c eps: the forward formulas and the engines' maps are well conditioned here"
GLOBAL_MODEL = ("core: error <= c eps; engines: error <= c eps (1 + |s1| m / scale) for the quantities they form in "
           "global coordinates (relacc.core.scales.global_condition), m the quantity's change per metre of lever")


def catalogue() -> tuple[HardCase, ...]:
    """Every entry, in family order."""
    out = []
    for body in ("B1", "B2"):
        for sign in (+1, -1):
            for delta in (1e-1, 1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 0.0):
                out.append(HardCase(
                    f"gimbal-{body}{'+' if sign > 0 else '-'}{delta:.0e}", "gimbal", delta, (3,),
                    f"theta_{body} middle angle = {'+' if sign > 0 else '-'}(pi/2 - {delta:g})",
                    _COND1 + " (only the inverse map, rates from angular velocity, is singular)",
                    edit=Edit(EditKind.GIMBAL, delta, body, sign)))
    for name, desc, edit in (
        ("quat-identity", "both quaternions (1, 0, 0, 0)", Edit(EditKind.IDENTITY)),
        ("quat-half-turn", "both quaternions with w = 0 (half turns about random axes)", Edit(EditKind.HALF_TURN)),
        ("quat-antipodal", "both quaternions with w < 0 (the antipodal sign)", Edit(EditKind.ANTIPODAL)),
        ("quat-near-identity-1e-08", "relative rotation B2/B1 by 1e-8 rad", Edit(EditKind.NEAR_IDENTITY, 1e-8)),
        ("quat-near-identity-1e-15", "relative rotation B2/B1 by 1e-15 rad", Edit(EditKind.NEAR_IDENTITY, 1e-15)),
    ):
        out.append(HardCase(name, "quaternion", 0.0, (1, 2), desc, _COND1, edit=edit))
    for rate in (1e0, 1e2, 1e4, 1e6):
        out.append(HardCase(f"spin-{rate:.0e}", "spin", rate, (1, 2, 3),
                            f"angular speeds (and accelerations) of norm {rate:g} rad/s", _COND1,
                            edit=Edit(EditKind.SPIN, rate)))
    for dist in (1e0, 1e2, 1e4, 1e6, 1e8):
        out.append(HardCase(f"far-{dist:.0e}", "far", dist, (1, 2, 3), f"|s1| = {dist:g} m", GLOBAL_MODEL,
                            edit=Edit(EditKind.FAR, dist)))
    for length in (0.0, 1e-12, 1e-6, 1e3):
        out.append(HardCase(f"geometry-r2-{length:.0e}", "geometry", length, (1, 2, 3), f"|r2'| = {length:g} m",
                            _COND1 + "; MuJoCo: plus the offset its compiler drops for sites within ~1e-6 m of "
                            "their body (Engine.lost_offset)", geometry={"r2": length}))
        out.append(HardCase(f"geometry-q2-{length:.0e}", "geometry", length, (1, 2, 3), f"|q2'| = {length:g} m",
                            _COND1, geometry={"q2": length}))
    out.append(HardCase("geometry-s2-1e+03", "geometry", 1e3, (1, 2, 3), "|s2'| = 1000 m (large prismatic offset)",
                        _COND1, edit=Edit(EditKind.S2, 1e3)))
    return tuple(out)


def chain_for(hc: HardCase, base: TwoBodyChain) -> TwoBodyChain:
    """The base chain with the entry's geometry: each override keeps the vector's direction."""
    return replace(base, **{key: length * getattr(base, key) / np.linalg.norm(getattr(base, key))
                            for key, length in hc.geometry.items()})


def states_for(hc: HardCase, case: int, n: int = N_STATES, seed: int = 0):
    """``(q, u, udot)`` of an entry for one case: seeded random states with the entry's edit.

    States come from ``relacc.core.states.random_states(case, n, [seed, case, k])`` where
    ``k`` is the entry's position in the catalogue.
    """
    k = [h.name for h in catalogue()].index(hc.name)
    s = random_states(case, n, [seed, case, k])
    q, u, udot = s.q.copy(), s.u.copy(), s.udot.copy()
    rng = np.random.default_rng([seed, case, k, 1])
    edit = hc.edit
    if edit is None:
        return q, u, udot
    kind = edit.kind
    if kind == EditKind.GIMBAL:
        q[:, 4 if edit.body == "B1" else 10] = edit.sign * (np.pi / 2 - edit.value)
    elif kind == EditKind.IDENTITY:
        q[:, 3:7] = q[:, 10:14] = (1.0, 0.0, 0.0, 0.0)
    elif kind == EditKind.HALF_TURN:
        for sl in (slice(3, 7), slice(10, 14)):
            axis = rng.normal(size=(n, 3))
            q[:, sl] = np.c_[np.zeros(n), axis / np.linalg.norm(axis, axis=1, keepdims=True)]
    elif kind == EditKind.ANTIPODAL:
        for sl in (slice(3, 7), slice(10, 14)):
            quat = random_unit_quaternions(rng, n)
            q[:, sl] = -quat * np.sign(quat[:, :1])
    elif kind == EditKind.NEAR_IDENTITY:
        angle = edit.value
        axis = rng.normal(size=(n, 3))
        q[:, 10:14] = relacc.quaternion_exp(angle * axis / np.linalg.norm(axis, axis=1, keepdims=True))
    elif kind == EditKind.SPIN:
        rate = edit.value
        for sl in (slice(3, 6), slice(9, 12)):
            u[:, sl] *= rate / np.linalg.norm(u[:, sl], axis=1, keepdims=True)
            udot[:, sl] *= rate / np.linalg.norm(udot[:, sl], axis=1, keepdims=True)
    elif kind == EditKind.FAR:
        q[:, 0:3] *= edit.value / np.linalg.norm(q[:, 0:3], axis=1, keepdims=True)
    elif kind == EditKind.S2:
        sl = slice(7, 10) if case != Case.ANGLE_RATES else slice(6, 9)
        q[:, sl] *= edit.value / np.linalg.norm(q[:, sl], axis=1, keepdims=True)
    return q, u, udot


@dataclass(frozen=True)
class Result:
    """One entry x case x evaluator x quantity.

    Attributes:
        evaluator: ``relacc`` (core vs complex step) or ``<engine>/<route>`` (engine vs core).
        max_error: largest normalized error. max_bound: largest bound of the
            accuracy model (``c eps`` for the core; :meth:`Engine.bound` for engines).
        max_ratio: largest error / bound; passes when <= 1.
        finite: every value the evaluator returned is finite.
    """

    name: str
    family: str
    parameter: float
    case: int
    evaluator: str
    quantity: str
    max_error: float
    max_bound: float
    max_ratio: float
    finite: bool

    @property
    def passed(self) -> bool:
        return self.finite and self.max_ratio <= 1.0

    @classmethod
    def of(cls, hc: HardCase, comp) -> "Result":
        """An entry's summary of one :class:`relacc.validation.compare.Comparison`."""
        return cls(hc.name, hc.family, hc.parameter, comp.case, comp.evaluator, comp.quantity, comp.max_error,
                   comp.max_bound, comp.max_ratio, comp.finite)


class Runner:
    """Runs catalogue entries against the core and engines; caches engines per geometry."""

    def __init__(self, fixture: Fixture, engines=None, n: int = N_STATES, seed: int = 0):
        from relacc.engines import chain_engines

        self.engine_names = chain_engines() if engines is None else tuple(engines)
        self.fixture, self.n, self.seed = fixture, n, seed
        self._engines = {}

    def engines_for(self, hc: HardCase):
        """Engines loaded with the entry's geometry (an inline fixture: no file outlives the loading)."""
        key = tuple(sorted(hc.geometry.items()))
        if key not in self._engines:
            fixture = self.fixture
            if hc.geometry:
                fixture = inline(f"{self.fixture.name}_{len(self._engines)}", chain_for(hc, self.fixture.chain))
            from relacc.engines import load_engine

            self._engines[key] = {name: load_engine(name, fixture) for name in self.engine_names}
        return self._engines[key]

    def run(self, hc: HardCase) -> list[Result]:
        """The entry's comparisons: the core against complex-step derivatives, each engine against the core."""
        chain = chain_for(hc, self.fixture.chain)
        out = []
        for case in hc.cases:
            q, u, udot = states_for(hc, case, self.n, self.seed)
            core = relacc.g2_kinematics(chain, case, q, u, udot)
            sc = term_scales(chain, case, q, u, udot)
            comps = (against_derivatives(chain, case, q, u, udot, core, sc)
                     + against_engines(self.engines_for(hc), chain, case, q, u, udot, core, sc))
            out += [Result.of(hc, c) for c in comps]
        return out


def run_catalogue(fixture: Fixture, engines=None, n=N_STATES, seed=0) -> list[Result]:
    """Every entry's results."""
    runner = Runner(fixture, engines, n, seed)
    return [r for hc in catalogue() for r in runner.run(hc)]


__all__ = ["GLOBAL_MODEL", "Edit", "EditKind", "HardCase", "Result", "Runner", "catalogue", "chain_for",
           "run_catalogue", "states_for"]
