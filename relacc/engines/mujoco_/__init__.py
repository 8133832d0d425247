"""MuJoCo adapter: imports only ``mujoco``. MuJoCo reads the model (MJCF natively, URDF by its URDF parser); its
reading is a contestant like any engine's: ``MujocoAdapter.own`` is the tree of its compiled model (:mod:`.spec`),
and the adapter is matched to the reference it is given (relacc's own reading of the file, :mod:`relacc.reading`)
joint by joint; where that reference is MuJoCo's own tree, every speed map is the identity.

Evaluations (:class:`MujocoAdapter`), per state with the model configured to apply exactly the given effects
(:mod:`.run`):

* ``M`` by ``mj_fullM`` (armature included); ``f = qfrc_smooth`` after ``mj_forward`` (passive minus bias plus
  applied); forward dynamics ``qacc``;
* a point's position (a site's ``site_xpos``, a fused body's place on the body that took it, a link's centre of
  mass over its bodies' ``xipos``), its Jacobian ``mj_jac``, its rate ``mj_jacDot`` (which reads ``cdof_dot``
  written by ``mj_comVel``), and its classical acceleration from MuJoCo's acceleration routine
  ``mj_rnePostConstraint`` at zero gravity: ``cacc`` moved from the subtree's centre of mass to the point and
  made classical by ``omega x v``, independently of ``mj_jacDot``.

Accuracy: MuJoCo works in global coordinates; its Jacobians and accelerations use lever arms formed as
differences of world positions, so far from the origin they lose about ``eps |p|`` per metre of lever
(``global_coordinates``). Its compiler latches a site within about 1e-6 m (``mjEPS``) of its body's frame to the
frame (``site_sameframe``) and discards ``site_pos``: :meth:`MujocoAdapter.lost_offset` reads that flag.

The package itself loads only its :mod:`.card` (what the engine is and can do, without importing it); the
adapter is :mod:`.adapter`, imported when asked for (:func:`relacc.engines.registry.adapter_module`).
"""

from relacc.engines.mujoco_.card import TRAITS

__all__ = ["TRAITS"]
