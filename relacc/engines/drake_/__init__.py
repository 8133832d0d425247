"""Drake adapter: imports only ``pydrake``. Conventions converted here and nowhere else:

* a free joint (and, in a plant built from relacc's tree, a body's three slides and ball) is a
  ``QuaternionFloatingJoint``: ``q = [qw, qx, qy, qz, x, y, z]`` (the child's orientation and origin in the parent
  frame), ``v = [omega, p_dot]`` both in the **parent's** components: ``omega_F = R omega_B``, so
  ``T = [[0, R], [I, 0]]`` and ``T_dot = [[0, R [omega~]], [0, 0]]``; the chain's velocities are therefore the note's
  case-1 speeds, reordered;
* a ball (Drake's MJCF parser) is a ``BallRpyJoint``: ``q`` roll-pitch-yaw angles (singular at pitch +-pi/2),
  ``v`` the child's angular velocity in the parent's components, ``R_FM omega_M`` (``T_dot = R [omega~]``);
* a body with several MJCF joints becomes a chain of massless bodies, one joint each; hinges and slides keep their
  names and coordinates;
* armature: Drake keeps it only as the reflected inertia of an actuator it reads on that joint (``<motor>`` or
  ``<position>``; ``rotor_inertia gear^2``), which is what this adapter reports.

Evaluations: ``CalcMassMatrix``; ``f = tau + CalcGravityGeneralizedForces - CalcBiasTerm`` with the effects'
generalized forces ``tau`` (joint springs and dampers mapped from the reference's speeds, ``T^-T tau``; loads through
``CalcJacobianTranslationalVelocity`` and ``CalcJacobianAngularVelocity`` at each body's mass centre); forward
dynamics from the plant's generalized-acceleration output (its articulated-body algorithm) with zero actuation and
joint damping and ``tau`` as applied generalized forces; a point's Jacobian ``CalcJacobianTranslationalVelocity``,
``J_dot v`` by ``CalcBiasTranslationalAcceleration`` (Drake has no Jacobian-rate matrix: where asked for, it is
Drake's own automatic differentiation of ``J`` along ``q_dot = N(q) v``, ``ToAutoDiffXd``), its classical
acceleration from ``CalcSpatialAccelerationsFromVdot`` shifted from the body's origin (``Shift``), independently of
``J_dot``. Simulation (:mod:`.run`): Drake's ``Simulator`` with its own integrators.

Accuracy far from the origin: Drake forms point velocities and Jacobians in the world frame from world positions,
so they lose about ``eps |p|`` per metre of lever like the other engines (``global_coordinates``); its acceleration
kinematics, propagated body by body, and its positions keep full accuracy.

The package itself loads only its :mod:`.card` (what the engine is and can do, without importing it); the
adapter is :mod:`.adapter`, imported when asked for (:func:`relacc.engines.registry.adapter_module`).
"""

from relacc.engines.drake_.card import TRAITS

__all__ = ["TRAITS"]
