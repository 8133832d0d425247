"""PyBullet adapter: imports only ``pybullet`` (its ``import`` prints its build time on standard output, and freeing
a client can print Bullet's allocation count there: :mod:`.client` keeps both off it). Conventions converted here
and nowhere else:

* a URDF only (``loadURDF``; PyBullet's ``loadMJCF`` is a partial reader: on the chain's MJCF it skips the
  ``<freejoint>`` ("unknown field") and the ball joint ("joint without axis attribute") and keeps the inertias in
  single precision, so relacc does not offer it an MJCF; a ``.xacro``'s expansion is given it from a temporary copy,
  :mod:`.files`), its root link fixed
  (``useFixedBase=True``: relacc, MuJoCo, Pinocchio and Drake weld a URDF's root to the world); one client of its
  own per adapter (``p.connect(p.DIRECT)``);
* coordinates: the movable joints' positions in PyBullet's order (``uIndex``), each a revolute angle or prismatic
  displacement as in case 2, matched to relacc's joints by name; fixed links are kept as links;
* dynamics: ``calculateMassMatrix``; the bias ``calculateInverseDynamics`` at zero accelerations, under the gravity
  set with ``setGravity`` (PyBullet's world has none until a user sets it: relacc sets the model's); gravity forces
  the same at zero speeds; forward dynamics ``M^-1 (tau - bias)``, solved by numpy (PyBullet offers forward dynamics
  only inside ``stepSimulation``);
* points: a link's mass centre and its frame from ``getLinkState`` (PyBullet's link frame *is* its inertial frame);
  ``calculateJacobian`` at a point given in that frame. PyBullet offers no ``J_dot v`` and no classical
  acceleration, so those two rows are not compared for it (said in the comparison);
* inertias: PyBullet stores a diagonal inertia in a principal frame, diagonalized by Bullet's Jacobi iteration
  (threshold 1e-6): :meth:`PyBulletAdapter.inertia_allowance`.

Two loadings, two cards (:mod:`.card`); the package loads only its cards, the adapter is :mod:`.adapter`.
"""

from relacc.engines.pybullet_.card import CARDS, TRAITS

__all__ = ["CARDS", "TRAITS"]
