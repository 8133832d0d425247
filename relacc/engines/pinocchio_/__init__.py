"""Pinocchio adapter: imports only ``pinocchio``. Conventions converted here and nowhere else:

* configuration: quaternions ``(x, y, z, w)``; a free joint's placement is relative to its joint frame
  (``q = jointPlacement^-1 X``, ``X`` the body's pose in world); an unbounded revolute joint has ``q = (cos, sin)``;
* speeds: a free joint's ``v = [R^T p_dot, omega]``, both in body components, so ``T = diag(R^T, I)`` and
  ``T_dot = diag(-[omega~] R^T, 0)``; ball, hinge and slide speeds are the reference's;
* dynamics: ``crba`` (upper triangle, armature included); the bias ``rnea`` at zero accelerations with
  ``model.gravity`` set; forward dynamics ``aba`` (``abaInParallel`` on a ``pin.ModelPool`` for batches); the
  effects' generalized forces: joint springs and dampers mapped from the reference's speeds (``T^-T tau``), loads
  through the LOCAL_WORLD_ALIGNED frame Jacobians at each body's mass centre (``J^T F``, ``J_w^T T``);
* points: frames (a site or a URDF link of that name; a frame added at each link's mass centre);
  ``getFrameJacobian`` and ``getFrameJacobianTimeVariation`` in LOCAL_WORLD_ALIGNED (in WORLD they describe the
  body point at the world origin, something else); classical accelerations by ``forwardKinematics(q, v, a)`` then
  ``getFrameClassicalAcceleration``.

Accuracy: the frame Jacobian and its time variation are assembled in the WORLD frame and shifted to the point, so
far from the origin they lose about ``eps |p|`` per metre of lever (``global_coordinates``); the classical
acceleration is propagated in local frames and keeps full accuracy. Integration (:meth:`PinocchioAdapter.stepper`):
Pinocchio has no integrator of its own; RKMK4 or semi-implicit Euler (:mod:`relacc.dynamics.integrate`) on its
manifold, ``pin.integrate`` and the inverse of ``pin.dIntegrate``.

The package itself loads only its :mod:`.card` (what the engine is and can do, without importing it); the
adapter is :mod:`.adapter`, imported when asked for (:func:`relacc.engines.registry.adapter_module`).
"""

from relacc.engines.pinocchio_.card import TRAITS

__all__ = ["TRAITS"]
