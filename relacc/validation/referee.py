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
difference is within the sum of their bounds. The judgement is the one every
referee of relacc's makes (:func:`judge`, ``relacc compare``'s too): the largest
group that agrees pairwise is the side that agrees, and whoever is outside it is
an odd one out; groups of equal size are a split, said so with the pairwise table.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from relacc.core.conventions import Route
from relacc.core.derivatives import along_motion
from relacc.core.kinematics import g2_kinematics
from relacc.core.scales import term_scales
from relacc.core.tolerances import normalized_error, rounding_tolerance
from relacc.validation.compare import routes_for

CORE, REFERENCE, COMPLEX_STEP = "relacc", "relacc-reference", "complex-step"


@dataclass(frozen=True)
class Verdict:
    """The referee on one quantity: which evaluators are the odd ones out, for the chain's routes and for a model's
    comparison alike (:func:`judge`).

    Attributes:
        quantity: what was judged.
        odd_ones_out: the evaluators outside the agreeing side (empty when everyone agrees).
        agreeing: that side: the largest group in which every pair agrees, when it is the only one that large and holds
            at least two (empty otherwise).
        split: the sides of equal votes when no side is larger (empty otherwise).
        pairs: ``{"a|b": largest difference / the pair's tolerance}``; a pair agrees when <= 1.
        voted_as: ``{engine: why}`` for engines that voted rebuilt without a known difference (a model's comparison).
        joined: a note when relacc and MuJoCo voted as one (relacc took part of the model from MuJoCo).
        case, route: the chain's case and route, or None (a model's comparison).
    """

    quantity: str
    odd_ones_out: tuple
    agreeing: tuple
    split: tuple
    pairs: dict = field(repr=False)
    voted_as: dict = field(default_factory=dict)
    joined: str = ""
    case: int | None = None
    route: str | None = None
    apart: tuple = ()
    """Evaluators outside the vote whose rows differ (relacc's own cases 1 and 3, each judged against its case 2 and
    not pairwise): named in the sentence, so that a line never says everyone agrees over a row that differs."""

    @property
    def everyone_agrees(self) -> bool:
        return all(r <= 1.0 for r in self.pairs.values())

    def sentence(self) -> str:
        """One line for ``relacc check``, ``relacc compare`` and the reports."""
        join = lambda names: ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else names[0]  # noqa: E731
        where = self.quantity if self.case is None else f"case {self.case} {self.quantity} ({self.route} route)"
        known = f" (once {join(sorted(self.voted_as))}'s known difference is removed)" if self.voted_as else ""
        note = f" ({self.joined})" if self.joined else ""
        if self.apart:
            note += (f"; {join(list(self.apart))} differ{'s' if len(self.apart) == 1 else ''} from relacc's case 2 "
                     "(outside the vote, which is among the case-2 readings)")
        if self.split:
            sides = " against ".join(join(list(side)) for side in self.split)
            return f"{where}: no majority, {sides}{known}{note}"
        if not self.agreeing:
            return f"{where}: no two evaluators agree ({join(list(self.odd_ones_out))}){known}{note}"
        if not self.odd_ones_out:
            among = " among the case-2 readings" if self.apart else ""
            return f"{where}: no odd one out{among}: {join(list(self.agreeing))} agree{known}{note}"
        ratio = max(r for k, r in self.pairs.items() if set(k.split("|")) & set(self.odd_ones_out))
        return (f"{where}: the odd one{'s' if len(self.odd_ones_out) > 1 else ''} out: {join(list(self.odd_ones_out))}"
                f" (up to {ratio:.3g} x the tolerance away); {join(list(self.agreeing))} agree{known}{note}")

    def as_json(self) -> dict:
        out = {"quantity": self.quantity, "odd_ones_out": list(self.odd_ones_out), "agreeing": list(self.agreeing),
               "split": [list(side) for side in self.split],
               "pairs": {k: (v if np.isfinite(v) else None) for k, v in self.pairs.items()},
               "voted_as": dict(self.voted_as), "joined": self.joined, "apart": list(self.apart),
               "verdict": self.sentence()}
        return out if self.case is None else {"case": self.case, "route": self.route, **out}


def judge(names, pairs: dict, weight: dict | None = None) -> tuple[tuple, tuple, tuple]:
    """``(odd_ones_out, agreeing, split)`` from the evaluators' ``names`` and ``pairs`` (``"a|b"``: the worst ratio to
    the pair's tolerance; a pair agrees at <= 1). The side that agrees is the largest group in which every pair agrees
    (by ``weight``, votes: 1 each by default), when it is the only one that large and holds at least two; everyone
    outside it is odd. Groups of equal votes are a split; no two agreeing leaves every evaluator odd."""
    agree = {frozenset(k.split("|")) for k, r in pairs.items() if r <= 1}
    weight = {n: 1 for n in names} if weight is None else weight
    groups = _cliques(list(names), agree)
    votes = lambda g: sum(weight[n] for n in g)  # noqa: E731
    best = max(votes(g) for g in groups)
    top = [g for g in groups if votes(g) == best]
    if max(len(g) for g in groups) < 2:
        return tuple(names), (), ()
    if len(top) > 1:  # sides of equal votes: each named, with whoever stands in none of them
        return (tuple(n for n in names if all(n not in g for g in top)), (),
                tuple(tuple(n for n in names if n in g) for g in top))
    return tuple(n for n in names if n not in top[0]), tuple(n for n in names if n in top[0]), ()


def _cliques(names, agree) -> list[frozenset]:
    """The maximal groups of ``names`` in which every pair agrees (``agree``: agreeing pairs), brute force (at most a
    handful of evaluators)."""
    groups: list[frozenset] = []
    for k in range(len(names), 0, -1):
        for combo in itertools.combinations(names, k):
            g = frozenset(combo)
            if any(g <= h for h in groups):
                continue
            if all(frozenset(p) in agree for p in itertools.combinations(combo, 2)):
                groups.append(g)
    return groups


def pair_ratios(values: dict, bounds: dict, scale) -> dict:
    """``{"a|b": largest normalized difference / (bound_a + bound_b)}`` of every pair of evaluators' values ``(n, ...)``
    with their bounds ``(n,)`` (infinite where either is not finite)."""
    names = list(values)
    pairs = {}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            err = normalized_error(values[a], values[b], scale)
            finite = np.all(np.isfinite(values[a])) and np.all(np.isfinite(values[b]))
            pairs[f"{a}|{b}"] = float(np.max(err / (bounds[a] + bounds[b]))) if finite else float("inf")
    return pairs


def referee(harness, case, quantity, route: str = Route.QUATERNION, k: int = 0) -> Verdict:
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
    pairs = pair_ratios(values, bounds, scale)
    odd, agreeing, split = judge(list(values), pairs)
    return Verdict(quantity, odd, agreeing, split, pairs, case=int(case), route=route)


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
