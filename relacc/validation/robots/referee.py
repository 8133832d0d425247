"""The referee of ``relacc compare``: every pair of evaluators compared, and the odd one out named, whoever it is.

The evaluators are relacc's own reading (case 2) and each engine that took part, MuJoCo included; an engine with a
known difference in its algorithms votes as rebuilt without it (its ``ENGINE_READINGS``: Pinocchio's composite-joint
``J_dot v``), so that a known bug does not vote. For each quantity on which some row disagrees, each pair agrees
when its normalized error is within tolerance over every state (``pairs``: ``"a|b"`` to the worst ratio to the
tolerance). The judgement is :func:`relacc.validation.referee.judge` (the chain's referee's too): the largest group
in which every pair agrees (by votes) is the side that agrees when it is the only one that large and holds at least
two; everyone outside it is odd. Two such groups of equal votes are an even split; no two agreeing is said so.

Where relacc took an element from MuJoCo (a mesh's mass properties), the two are not independent: when they agree
they are one vote (``joined``).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from relacc.engines import MESH_ENGINE, label, readings
from relacc.errors import EngineError, ModelError
from relacc.validation.referee import Verdict, judge
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


def referee(voters_, states, dynamics, reading) -> list[Verdict]:
    """A :class:`Verdict` for each quantity on which some row of ``dynamics`` disagrees (module docstring)."""
    disputed = [q for q, rows in dynamics.items() if not all(r.passed for r in rows.values())]
    present = [v for v in voters_ if any(v.engine in rows for rows in dynamics.values()) or v is voters_[0]]
    if not disputed or len(present) < 2:
        return []
    pair_rows = {}
    for a, b in itertools.combinations(present, 2):
        # each pair with the allowances of both engines' own documented tolerances on the file's inertias
        pair_rows[(a.engine, b.engine)] = compare_dynamics(a.evaluator, b.evaluator, states, reading)
    joined = bool(reading.taken) and any(v.engine == MESH_ENGINE for v in present)
    out = []
    for quantity in disputed:
        names = [v.engine for v in present if quantity in _quantities(pair_rows, v.engine)]
        pairs = {f"{a}|{b}": rows[quantity].max_ratio for (a, b), rows in pair_rows.items() if quantity in rows}
        weight = {n: 1 for n in names}
        note = ""
        together = pairs.get(f"relacc|{MESH_ENGINE}", pairs.get(f"{MESH_ENGINE}|relacc", np.inf))
        if joined and together <= 1 and "relacc" in weight:
            weight[MESH_ENGINE] = 0  # one vote for the two
            note = (f"relacc took {', '.join(sorted(reading.taken))} from {label(MESH_ENGINE)}: the two count as one "
                    "vote here")
        odd, agreeing, split = judge(names, pairs, weight)
        apart = tuple(e for e, r in dynamics[quantity].items() if not r.passed and e not in names)
        out.append(Verdict(quantity, odd, agreeing, split, pairs, {v.engine: v.why for v in present if v.why}, note,
                           apart=apart))
    return out


def _quantities(pair_rows, name) -> set:
    return {q for (a, b), rows in pair_rows.items() if name in (a, b) for q in rows}
