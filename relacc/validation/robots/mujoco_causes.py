"""MuJoCo's own known differences, reproduced: when MuJoCo's ``J_dot v`` differs from relacc's reading, does MuJoCo's
other reading of the same quantity (its acceleration routine, ``mj_rnePostConstraint`` at zero rates, instead of
``mj_jacDot``) agree with relacc? Then the difference is MuJoCo's ``mj_jacDot``, and relacc says which case it is.
"""

from __future__ import annotations

import numpy as np

from relacc.core.conventions import ModelQuantity
from relacc.core.tolerances import robot_tolerance
from relacc.engines.base import com

MUJOCO_JACDOT = ("MuJoCo's mj_jacDot takes a ball joint's columns from the velocity of its whole body, so a slide "
                 "after a ball on the same body adds v_slide x omega_ball to J_dot v (relacc's finding): MuJoCo's own "
                 "acceleration routine (mj_rnePostConstraint) agrees with relacc")
MUJOCO_JACDOT_OTHER = ("MuJoCo's mj_jacDot differs from its own acceleration routine (mj_rnePostConstraint), which "
                       "agrees with relacc")


def mujoco_cause(quantity: str, reference, mujoco, states) -> str:
    """The cause text when MuJoCo's acceleration routine at zero rates agrees with relacc's ``J_dot v`` on every link
    (normalized as :func:`relacc.validation.robots.agreement.point_terms`), else empty. ``reference``: relacc's
    reading as an evaluator; ``mujoco``: MuJoCo's adapter matched to it."""
    if quantity not in (ModelQuantity.JDOT_V, ModelQuantity.CLASSICAL_ACCELERATION):
        return ""
    from relacc.validation.robots.agreement import CHUNK, point_terms, shared_links

    links = shared_links(reference.structure, mujoco.structure, 0.0)
    if not links:
        return ""
    tol = robot_tolerance(len(reference.structure.links))
    worst = 0.0
    for start in range(0, len(states.q), CHUNK):  # batched, a chunk of states at a time (as the comparison)
        q, u, udot = (x[start:start + CHUNK] for x in (states.q, states.u, states.udot))
        mine = reference.kinematics(q, u, udot, links)
        states_e = mujoco.to_engine(q, u, np.zeros_like(u))
        qe, ve, ae = states_e.q, states_e.v, states_e.a
        theirs = mujoco.points(qe, ve, ae, [com(name) for name in links])  # at zero rates: J_dot v by rne
        for i, (v, a) in enumerate(zip(u, udot)):
            scale, _ = point_terms(mine.J[i], mine.position[i], v, a)
            x, y = mine.Jdot_v[i], theirs.acceleration[i]
            worst = max(worst, float((np.abs(x - y).max(axis=1) / np.maximum(scale, np.finfo(float).tiny)).max()))
    if worst > tol:
        return ""
    return MUJOCO_JACDOT if ball_then_slide(reference.tree) else MUJOCO_JACDOT_OTHER


def ball_then_slide(tree) -> bool:
    """Whether a body of the tree has a slide after a ball."""
    for body in tree.bodies:
        kinds = [j.type for j in body.joints]
        if "ball" in kinds and "slide" in kinds[kinds.index("ball") + 1:]:
            return True
    return False


ALGORITHM_CAUSES = {"mujoco": mujoco_cause}
"""Each engine's known differences in its algorithms, as a function of ``(quantity, reference, adapter, states)``
returning the cause's text or empty (engines without one are absent)."""
