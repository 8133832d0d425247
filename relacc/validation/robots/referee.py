"""The referee of ``relacc compare``: every pair of evaluators compared, and the odd one out named, whoever it is.

The evaluators are relacc's own reading (case 2) and each engine that took part, MuJoCo included; an engine with a
known difference in its algorithms votes as rebuilt without it (its ``ENGINE_READINGS``: Pinocchio's composite-joint
``J_dot v``), so that a known bug does not vote. For each quantity on which some row disagrees, each pair agrees
when its normalized error is within tolerance over every state (``pairs``: ``"a|b"`` to the worst ratio to the
tolerance). The largest group in which every pair agrees (by votes) is the side that agrees when it is the only one
that large and holds at least two; everyone outside it is odd. Two such groups of equal votes are an even split;
no two agreeing is said so.

Where relacc took an element from MuJoCo (a mesh's mass properties), the two are not independent: when they agree
they are one vote (``joined``).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np

from relacc.engines import MESH_ENGINE, readings
from relacc.errors import EngineError, ModelError
from relacc.validation.robots.agreement import compare_dynamics


@dataclass
class Voter:
    """An evaluator as the referee counts it: its name, the object it evaluates with (an adapter, or relacc's
    :class:`relacc.validation.robots.tree.TreeRobot`) and, when it votes rebuilt, why."""

    engine: str
    evaluator: object
    why: str = ""


def voters(reference, robots, states, reading) -> list[Voter]:
    """relacc's reading, then each engine (rebuilt without a known difference of its algorithms where one applies)."""
    out = [Voter(reference.engine, reference)]
    for robot in robots:
        why, evaluator = "", robot
        for known in readings(robot.engine):
            if known.applies(robot):
                try:
                    evaluator, why = known.change(robot), known.text
                except (ModelError, EngineError):
                    continue
        out.append(Voter(robot.engine, evaluator, why))
    return out


@dataclass(frozen=True)
class Verdict:
    """The referee on one quantity.

    ``odd_ones_out``: the evaluators outside the agreeing side; ``agreeing``: that side; ``split``: the sides of
    equal votes when no side is larger; ``pairs``: ``"a|b"`` to the worst normalized error over the tolerance (a
    pair agrees at <= 1); ``voted_as``: ``{engine: why}`` for engines that voted rebuilt; ``joined``: a note when
    relacc and MuJoCo voted as one (relacc took part of the model from MuJoCo)."""

    quantity: str
    odd_ones_out: tuple
    agreeing: tuple
    split: tuple
    pairs: dict
    voted_as: dict = field(default_factory=dict)
    joined: str = ""

    def sentence(self) -> str:
        join = lambda names: ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else names[0]  # noqa: E731
        known = f" (once {join(sorted(self.voted_as))}'s known difference is removed)" if self.voted_as else ""
        note = f" ({self.joined})" if self.joined else ""
        if self.split:
            sides = " against ".join(join(list(side)) for side in self.split)
            return f"{self.quantity}: no majority, {sides}{known}{note}"
        if not self.agreeing:
            return f"{self.quantity}: no two evaluators agree ({join(list(self.odd_ones_out))}){known}{note}"
        if not self.odd_ones_out:
            return f"{self.quantity}: no odd one out: {join(list(self.agreeing))} agree{known}{note}"
        odd = join(list(self.odd_ones_out))
        return (f"{self.quantity}: the odd one{'s' if len(self.odd_ones_out) > 1 else ''} out: {odd}; "
                f"{join(list(self.agreeing))} agree{known}{note}")

    def as_json(self) -> dict:
        return {"quantity": self.quantity, "odd_ones_out": list(self.odd_ones_out), "agreeing": list(self.agreeing),
                "split": [list(side) for side in self.split],
                "pairs": {k: (v if np.isfinite(v) else None) for k, v in self.pairs.items()},
                "voted_as": dict(self.voted_as), "joined": self.joined, "verdict": self.sentence()}


def referee(voters_, states, dynamics, reading) -> list[Verdict]:
    """A :class:`Verdict` for each quantity on which some row of ``dynamics`` disagrees (module docstring)."""
    disputed = [q for q, rows in dynamics.items() if not all(r.passed for r in rows.values())]
    present = [v for v in voters_ if any(v.engine in rows for rows in dynamics.values()) or v is voters_[0]]
    if not disputed or len(present) < 2:
        return []
    pair_rows = {}
    for a, b in itertools.combinations(present, 2):
        pair_rows[(a.engine, b.engine)] = compare_dynamics(a.evaluator, b.evaluator, states)
    joined = bool(reading.taken) and any(v.engine == MESH_ENGINE for v in present)
    out = []
    for quantity in disputed:
        names = [v.engine for v in present if quantity in _quantities(pair_rows, v.engine)]
        pairs = {f"{a}|{b}": rows[quantity].max_ratio for (a, b), rows in pair_rows.items() if quantity in rows}
        agree = {frozenset(k.split("|")) for k, r in pairs.items() if r <= 1}
        weight = {n: 1 for n in names}
        note = ""
        if joined and frozenset(("relacc", "mujoco")) in agree and "relacc" in weight:
            weight["mujoco"] = 0  # one vote for the two
            note = (f"relacc took {', '.join(sorted(reading.taken))} from MuJoCo: the two count as one vote here")
        groups = _cliques(names, agree)
        votes = lambda g: sum(weight[n] for n in g)  # noqa: E731
        best = max(votes(g) for g in groups)
        top = [g for g in groups if votes(g) == best]
        voted = {v.engine: v.why for v in present if v.why}
        if max(len(g) for g in groups) < 2:
            out.append(Verdict(quantity, tuple(names), (), (), pairs, voted, note))
        elif len(top) > 1:  # sides of equal votes: each named, with whoever stands in none of them
            out.append(Verdict(quantity, tuple(n for n in names if all(n not in g for g in top)), (),
                               tuple(tuple(n for n in names if n in g) for g in top), pairs, voted, note))
        else:
            side = top[0]
            out.append(Verdict(quantity, tuple(n for n in names if n not in side),
                               tuple(n for n in names if n in side), (), pairs, voted, note))
    return out


def _quantities(pair_rows, name) -> set:
    return {q for (a, b), rows in pair_rows.items() if name in (a, b) for q in rows}


def _cliques(names, agree) -> list[frozenset]:
    """The maximal groups of ``names`` in which every pair agrees (``agree``: agreeing pairs), brute force (at most a
    handful of evaluators)."""
    groups = []
    for k in range(len(names), 0, -1):
        for combo in itertools.combinations(names, k):
            g = frozenset(combo)
            if any(g <= h for h in groups):
                continue
            if all(frozenset(p) in agree for p in itertools.combinations(combo, 2)):
                groups.append(g)
    return groups
