"""The referee: when evaluators disagree beyond the error model, which one is the odd one out.

With two engines a disagreement has no referee. relacc has five independent
evaluators of G2's kinematics on the same states:

* each engine (Pinocchio, MuJoCo, Drake), with its own accuracy model
  (:meth:`relacc.engines.chain.ChainEngine.bound`);
* relacc's fused kernels (the corrected formulas as ``relacc check`` runs them);
* relacc's reference implementation (the note's formulas one by one,
  ``backend="reference"``), which shares no code with the kernels;
* complex-step derivatives of the reference's own position, velocity and V
  along the motion (for velocity, V, acceleration and Vdot), exact to rounding.

Two evaluators *agree* on a quantity when, at every state, their normalized
difference is within the sum of their bounds. The odd one out is the
evaluator that disagrees with every other while all the others agree among
themselves; when no single evaluator explains the disagreements, the
referee says so and gives the pairwise table.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from relacc.core.derivatives import along_motion
from relacc.core.kinematics import g2_kinematics
from relacc.core.scales import term_scales
from relacc.core.tolerances import normalized_error, rounding_tolerance
from relacc.validation.compare import routes_for

CORE, REFERENCE, COMPLEX_STEP = "relacc", "relacc-reference", "complex-step"


@dataclass(frozen=True)
class RouteVerdict:
    """The referee's verdict on one case x route x quantity.

    Attributes:
        odd_one_out: the evaluator that disagrees with all the others while
            they agree among themselves, or None (everyone agrees, or no single
            evaluator explains the disagreements).
        agreeing: the evaluators that agree with each other (all but the odd one out).
        pairs: ``{"a|b": largest difference / (bound_a + bound_b)}``; a pair agrees when <= 1.
    """

    case: int
    route: str
    quantity: str
    odd_one_out: str | None
    agreeing: tuple
    pairs: dict = field(repr=False)

    @property
    def everyone_agrees(self) -> bool:
        return all(r <= 1.0 for r in self.pairs.values())

    def sentence(self) -> str:
        """One line for ``relacc check`` and the report."""
        where = f"case {self.case} {self.quantity} ({self.route} route)"
        if self.everyone_agrees:
            return f"{where}: every evaluator agrees"
        if self.odd_one_out is None:
            worst = max(self.pairs, key=lambda pair: self.pairs[pair])
            return (f"{where}: no single odd one out; the worst pair is {worst.replace('|', ' vs ')} at "
                    f"{self.pairs[worst]:.3g} of its bound")
        ratio = max(r for k, r in self.pairs.items() if self.odd_one_out in k.split("|"))
        return (f"{where}: the odd one out is {self.odd_one_out} (up to {ratio:.3g} x its bound away); "
                f"{', '.join(self.agreeing)} agree")

    def as_json(self) -> dict:
        return {"case": self.case, "route": self.route, "quantity": self.quantity, "odd_one_out": self.odd_one_out,
                "agreeing": list(self.agreeing), "pairs": self.pairs, "verdict": self.sentence()}


def judge(values: dict, bounds: dict, scale) -> tuple[str | None, tuple, dict]:
    """``(odd_one_out, agreeing, pairs)`` from every evaluator's values ``(n, ...)`` and bounds ``(n,)``."""
    names = list(values)
    pairs = {}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            err = normalized_error(values[a], values[b], scale)
            finite = np.all(np.isfinite(values[a])) and np.all(np.isfinite(values[b]))
            pairs[f"{a}|{b}"] = float(np.max(err / (bounds[a] + bounds[b]))) if finite else float("inf")

    def agree(a, b):
        return pairs.get(f"{a}|{b}", pairs.get(f"{b}|{a}")) <= 1.0

    odd = [x for x in names
           if all(agree(a, b) for a in names for b in names if a < b and x not in (a, b))
           and not any(agree(x, y) for y in names if y != x)]
    if len(odd) == 1 and len(names) >= 3:
        return odd[0], tuple(n for n in names if n != odd[0]), pairs
    return None, tuple(names) if all(r <= 1.0 for r in pairs.values()) else (), pairs


def referee(harness, case, quantity, route: str = "quaternion", k: int = 0) -> RouteVerdict:
    """Every evaluator on chunk ``k`` of a case's states, for one quantity and route, judged.

    Args:
        harness: a :class:`relacc.validation.check.Harness` (its engines, states and caches).
    """
    s = harness.states(case, k)
    chain = harness.chain
    scale = harness.scales(case, k).of(quantity)
    tol = np.full(len(s), rounding_tolerance())
    values, bounds = {}, {}
    for name, engine in harness.engines.items():
        if route in routes_for(case):
            values[name] = getattr(harness.engine_result(case, name, route, k), quantity)
            bounds[name] = np.broadcast_to(engine.bound(route, quantity, chain, case, s.q, s.u, s.udot), tol.shape)
    values[CORE] = getattr(harness.core_result(case, k=k), quantity)
    values[REFERENCE] = getattr(g2_kinematics(chain, case, s.q, s.u, s.udot, backend="reference"), quantity)
    bounds[CORE] = bounds[REFERENCE] = tol
    derived = _complex_step(chain, case, s, quantity)
    if derived is not None:
        values[COMPLEX_STEP], bounds[COMPLEX_STEP] = derived, tol
        if quantity == "V":  # complex steps give V u, not V: judge V u for everyone
            values = {n: (np.einsum("nij,nj->ni", v, s.u) if n != COMPLEX_STEP else v) for n, v in values.items()}
            scale = term_scales(chain, case, s.q, s.u, s.udot).velocity
    odd, agreeing, pairs = judge(values, bounds, scale)
    return RouteVerdict(int(case), route, quantity, odd, agreeing, pairs)


def _complex_step(chain, case, s, quantity):
    """The quantity by complex-step differentiation of the reference along the motion (None for position)."""
    def of(name):
        return lambda q, u: getattr(g2_kinematics(chain, case, q, u, backend="reference"), name)

    if quantity in ("velocity", "V"):
        return along_motion(case, s.q, s.u, None, of("position"))
    if quantity == "acceleration":
        return along_motion(case, s.q, s.u, s.udot, of("velocity"))
    if quantity == "Vdot":
        return along_motion(case, s.q, s.u, None, of("V"))
    return None
