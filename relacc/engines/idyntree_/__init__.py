"""iDynTree adapter: imports only ``idyntree`` (``idyntree.bindings``). Conventions converted here and nowhere else:

* a URDF only (a ``.xacro``'s expansion too), read by iDynTree's own parser (``ModelLoader.loadModelFromString``,
  the file's text without its visual and collision elements, which have no part in the dynamics); its default base
  link (the URDF's root) held at the world with zero twist and zero acceleration, as relacc, MuJoCo, Pinocchio and
  Drake weld a URDF's root (iDynTree's model is always floating: relacc keeps the joints' block of its matrices);
* coordinates: the joints' DOFs in iDynTree's order (``getDOFsOffset``), each a revolute angle or prismatic
  displacement as in case 2, matched to relacc's joints by name; fixed joints keep their links;
* velocity representation chosen explicitly: ``MIXED_REPRESENTATION``, a frame's velocity ``[p_dot, omega]`` in
  world components, so that a frame's bias acceleration's linear part is the classical ``J_dot v`` of its origin;
* dynamics: ``getFreeFloatingMassMatrix``, ``generalizedBiasForces`` and ``generalizedGravityForces`` (their joints'
  block) under the gravity relacc gives a URDF (``-9.81`` along z); forward dynamics ``M^-1 (tau - bias)``, solved by
  numpy (``KinDynComputations`` offers no forward dynamics);
* points: a frame added on each moving link at its mass centre (the link and the links welded to it, by iDynTree's
  own inertias) and at each body's mass centre, before the model is loaded: ``getWorldTransform``,
  ``getFrameFreeFloatingJacobian``, ``getFrameBiasAcc`` (``J_dot v``) and ``getFrameAcc`` (the classical
  acceleration at given joint accelerations), linear parts.

The package itself loads only its :mod:`.card`; the adapter is :mod:`.adapter`.
"""

from relacc.engines.idyntree_.card import TRAITS

__all__ = ["TRAITS"]
