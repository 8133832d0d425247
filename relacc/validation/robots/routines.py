"""An engine's two routines for one quantity, held to each other: when an engine's ``J_dot v`` differs from relacc's
reading and its adapter offers a second routine (:class:`relacc.engines.capabilities.AccelerationRoutine`: its
points' classical acceleration at zero rates, MuJoCo's ``mj_rnePostConstraint`` instead of ``mj_jacDot``), does that
routine agree with relacc? Then the difference is in the engine's first routine, and the adapter says which case it
is (:meth:`relacc.engines.capabilities.AccelerationRoutine.jdot_cause`).
"""

from __future__ import annotations

import numpy as np

from relacc.core.conventions import Quantity
from relacc.core.tolerances import robot_tolerance
from relacc.engines.base import com

EXPLAINS = (Quantity.JDOT_V, Quantity.CLASSICAL_ACCELERATION)
"""The quantities a second acceleration routine can explain (both carry the engine's ``J_dot v``)."""


def routine_cause(reference, engine, states) -> str:
    """The cause text, for a row of :data:`EXPLAINS`, when the engine's acceleration routine at zero rates agrees with
    relacc's ``J_dot v`` on every link (normalized as :func:`relacc.validation.robots.agreement.point_terms`), else
    empty. ``reference``: relacc's reading as an evaluator; ``engine``: an adapter matched to it (empty unless it
    offers :class:`relacc.engines.capabilities.AccelerationRoutine`)."""
    from relacc.engines.capabilities import AccelerationRoutine

    if not isinstance(engine, AccelerationRoutine):
        return ""
    from relacc.validation.robots.agreement import CHUNK, point_terms, shared_links

    links = shared_links(reference.structure, engine.structure, 0.0)
    if not links:
        return ""
    tol = robot_tolerance(len(reference.structure.links))
    worst = 0.0
    for start in range(0, len(states.q), CHUNK):  # batched, a chunk of states at a time (as the comparison)
        q, u, udot = (x[start:start + CHUNK] for x in (states.q, states.u, states.udot))
        mine = reference.kinematics(q, u, udot, links)
        states_e = engine.to_engine(q, u, np.zeros_like(u))
        qe, ve, ae = states_e.q, states_e.v, states_e.a
        theirs = engine.points(qe, ve, ae, [com(name) for name in links]).acceleration  # at zero rates: J_dot v
        if theirs is None:  # asked with rates: never
            return ""
        for i, (v, a) in enumerate(zip(u, udot)):
            scale, _ = point_terms(mine.J[i], mine.position[i], v, a)
            x, y = mine.Jdot_v[i], theirs[i]
            worst = max(worst, float((np.abs(x - y).max(axis=1) / np.maximum(scale, np.finfo(float).tiny)).max()))
    if worst > tol:
        return ""
    return engine.jdot_cause(reference.tree)
