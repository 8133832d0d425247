"""Pinocchio on a model file, as the benchmarks' anchor for trees: batched forward dynamics and Jacobian loops.

Imports only ``pinocchio``. The model is Pinocchio's own reading of the file (its MJCF parser, composites for
bodies with several joints; or its URDF parser), matched to MuJoCo's by :class:`relacc.engines.robots.pinocchio_.
PinocchioRobot`, which converts MuJoCo's states (quaternion order, free-joint placement, speed maps) so that
every evaluator sees the same states.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from relacc.engines.robots.pinocchio_ import LWA, PinocchioRobot


def states(robot: PinocchioRobot, q, v):
    """MuJoCo's states ``q (n, nq)``, ``v (n, nv)`` in Pinocchio's coordinates, column-major ``(nq_e, n)``."""
    qe = np.stack([robot.engine_q(x) for x in q], axis=1)
    ve = np.stack([robot.speed_map(x, y)[0] @ y[robot.dofs] for x, y in zip(q, v)], axis=1)
    return np.asfortranarray(qe), np.asfortranarray(ve)


def aba_in_parallel(robot: PinocchioRobot, threads: int, qe, ve):
    """A closure timing ``pin.abaInParallel`` on a ``pin.ModelPool`` (its fastest use: inputs and output prepared in
    its column-major layout); its ``out`` attribute holds the accelerations ``(nv_e, n)``."""
    pool = pin.ModelPool(robot.model, threads)
    tau = np.zeros_like(ve)
    out = np.asfortranarray(np.zeros_like(ve))

    def run():
        pin.abaInParallel(threads, pool, qe, ve, tau, out)

    run.out = out
    return run


def jacobian_loop(robot: PinocchioRobot, qe, ve, ae):
    """A closure looping over the states: ``computeJointJacobiansTimeVariation`` then, per link frame at its mass
    centre, ``getFrameJacobian`` and ``getFrameJacobianTimeVariation`` (LOCAL_WORLD_ALIGNED, the world components
    relacc reports) stored into ``(n, links, 6, nv_e)`` arrays, as a user collecting every body's would."""
    m, d = robot.model, robot.data
    frames = [f for _, _, f in robot.link_frames.values()]
    n = qe.shape[1]
    J, Jd = np.empty((n, len(frames), 6, m.nv)), np.empty((n, len(frames), 6, m.nv))

    def run():
        for i in range(n):
            pin.computeJointJacobiansTimeVariation(m, d, qe[:, i], ve[:, i])
            pin.updateFramePlacements(m, d)
            for k, f in enumerate(frames):
                J[i, k] = pin.getFrameJacobian(m, d, f, LWA)
                Jd[i, k] = pin.getFrameJacobianTimeVariation(m, d, f, LWA)

    return run


def version() -> str:
    return pin.__version__
