"""PyBullet stepping: ``stepSimulation`` with its fixed step, a body of its own loaded for the run, with exactly a
scene's effects acting, in a client of its own (imports only ``pybullet``).

What PyBullet adds by default is switched off, each measured on pybullet 3.2.7 with a prismatic joint coasting at
5 m/s for 20 steps of 10 ms (no effect: it must keep its speed exactly):

* the velocity motor every revolute and prismatic joint has (``setJointMotorControlArray(VELOCITY_CONTROL,
  forces=0)``);
* the multibody's linear and angular damping (0.04 each) and each joint's ``<dynamics damping>`` from the file
  (``changeDynamics(linearDamping=0, angularDamping=0, jointDamping=0)`` on the base and every link): the scene's
  dampers are its own, applied as forces;
* the joint velocity cap (``maxJointVelocity``, 100 rad/s or m/s by default: a 500 m/s joint was held at 100), raised
  on the base before the damping is zeroed (set together on a link, the damping came back: 500 m/s fell to 468);
* the URDF's joint limits, which ``changeDynamics`` does not lift (``jointLowerLimit``/``jointUpperLimit`` and
  ``jointLimitForce=0`` left a revolute joint stopped at its limit): the run's body is loaded from a copy of the file
  (:func:`relacc.engines.pybullet_.files.placed_copy`), its revolute joints made continuous and its prismatic joints
  given ``lower > upper`` (which Bullet reads as unlimited).

The scene's springs, dampers and loads are relacc's generalized forces at the step's state (the same as every
engine's, :meth:`relacc.engines.base.Adapter.generalized_forces`), applied with ``TORQUE_CONTROL`` before each
``stepSimulation``; gravity is ``setGravity``. Bullet's multibody step is semi-implicit Euler (``v`` first, then ``q``
with the new ``v``): the scene integrator ``euler``.
"""

from __future__ import annotations

import weakref
from pathlib import Path

import numpy as np

from relacc.dynamics.steps import Stepper
from relacc.engines.base import fixed_step_only
from relacc.engines.pybullet_.client import disconnect, pb
from relacc.engines.pybullet_.files import placed_copy
from relacc.errors import EngineError, IntegrationError
from relacc.isolate import captured_output


def _load_for_run(adapter, c: int) -> int:
    """A body of the adapter's file in client ``c`` (a world of its own: a second body where the adapter's is would
    collide with it), loaded as the adapter's is, for stepping."""
    flags = pb.URDF_USE_INERTIA_FROM_FILE if adapter.inertia_from_file else 0
    with placed_copy(Path(adapter.source), unlimited=True) as copy, captured_output(stdout=True):
        body = pb.loadURDF(copy, useFixedBase=True, flags=flags, physicsClientId=c)
    joints = list(adapter.order)
    pb.setJointMotorControlArray(body, joints, pb.VELOCITY_CONTROL, forces=[0.0] * len(joints), physicsClientId=c)
    pb.changeDynamics(body, -1, maxJointVelocity=1e30, physicsClientId=c)
    for link in range(-1, pb.getNumJoints(body, physicsClientId=c)):
        pb.changeDynamics(body, link, linearDamping=0.0, angularDamping=0.0, jointDamping=0.0, physicsClientId=c)
    return body


def stepper(adapter, effects, dt, integrator, accuracy=None) -> Stepper:
    """``stepSimulation`` at ``dt`` under exactly ``effects`` (module docstring); time runs on from one call to the
    next, from 0.

    Raises:
        EngineError: an integrator other than ``euler`` (Bullet's own step), or an accuracy.
    """
    fixed_step_only("PyBullet", accuracy)
    if integrator != "euler":
        raise EngineError(f"PyBullet has no {integrator!r} integrator: its stepSimulation is semi-implicit Euler "
                          "('euler')")
    c = pb.connect(pb.DIRECT)
    body = _load_for_run(adapter, c)
    joints = list(adapter.order)
    g = adapter.gravity0 if effects is None or effects.gravity is None else np.asarray(effects.gravity, dtype=float)
    forced = effects is not None and bool(effects.joints or effects.bodies)
    steps = [0]

    def advance(x, w, k):
        pb.setGravity(*(float(a) for a in g), physicsClientId=c)
        pb.setTimeStep(float(dt), physicsClientId=c)
        for j, (xi, wi) in enumerate(zip(x, w)):
            pb.resetJointState(body, joints[j], float(xi), float(wi), physicsClientId=c)
        q, v = np.asarray(x, dtype=float), np.asarray(w, dtype=float)
        for _ in range(int(k)):
            if forced:
                tau = adapter.generalized_forces(q[None], v[None], effects, steps[0] * dt)[0]
                pb.setJointMotorControlArray(body, joints, pb.TORQUE_CONTROL, forces=[float(f) for f in tau],
                                             physicsClientId=c)
            pb.stepSimulation(physicsClientId=c)
            steps[0] += 1
            states = pb.getJointStates(body, joints, physicsClientId=c)
            q = np.array([s[0] for s in states])
            v = np.array([s[1] for s in states])
            if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v))):
                raise IntegrationError("the integration diverged (PyBullet's stepSimulation): its state is no longer "
                                       "finite; reduce the step")
        return q, v

    made = Stepper(advance)
    weakref.finalize(made, _disconnect, c)
    return made


def _disconnect(client: int) -> None:
    try:
        disconnect(client)
    except pb.error:  # already gone (interpreter exit)
        pass
