"""MuJoCo adapter: imports only ``mujoco``.

Conventions of MuJoCo, converted here and nowhere else:

* ``qpos`` of the free joint: ``[x, y, z, qw, qx, qy, qz]``, the body origin in
  world components and the quaternion scalar first whose matrix maps body to
  world components. With ``alignfree`` off (the fixtures set it) the free
  body's frame is B1's frame, so ``qpos = [s1, quat_B1]``.
* ``qvel`` of the free joint: ``[linear velocity of the body origin in world
  components, angular velocity in body components] = [s1_dot, omega'_B1]``.
* Slide joints of B2: displacement along B1's axes, so ``qpos = s2'``,
  ``qvel = s2'_dot``.
* Ball joint: ``qpos = quat_B2/B1`` (w first), ``qvel`` is the angular
  velocity of B2 relative to B1 in B2 components, ``omega_hat'_B2``.

So on the quaternion route MuJoCo's ``(qpos, qvel, qacc)`` *are* the Case 2
coordinates and body speeds: ``[P] = I``.

Accuracy: MuJoCo works in global coordinates. Its Jacobians and
accelerations use lever arms formed as differences of world positions, so
far from the origin they lose about ``eps |s1|`` per metre of lever
(``global_coordinates``; measured: 5e7 eps at |s1| = 1e8 m). Positions are
exact to the terms' rounding.

Compile-time rounding: MuJoCo's compiler latches a site whose offset from
its body frame is within about 1e-6 m (``mjEPS``) to the body frame
(``site_sameframe = mjSAMEFRAME_BODY``) and then discards ``site_pos``, so
for ``|r2'|`` of a micrometre or less the site G2 sits on B2's origin
(measured: 8e-7 m off for ``|r2'| = 1e-6`` m). :meth:`lost_offset` reads
that flag and the accuracy model adds the lost offset.

G2 is the site ``G2``. Jacobian: ``mj_jac`` at the site's world position on
body B2, after ``mj_kinematics``, ``mj_comPos``. Time variation:
``mj_jacDot``, which reads ``cdof_dot`` written by ``mj_comVel`` (without it
the result is stale). Acceleration: ``mj_rnePostConstraint`` then
``mj_objectAcceleration`` on the site in world components; both report the
*proper* acceleration (gravity subtracted), so the adapter runs with gravity
set to zero and reads the classical acceleration directly.
"""

from __future__ import annotations

import mujoco
import numpy as np

from relacc.engines.base import (
    Engine,
    PointKinematics,
    identity_input,
    note_from_quaternions,
    quaternion_route_input,
)
from relacc.errors import FixtureError
from relacc.fixtures import Fixture


def _load(path) -> mujoco.MjModel:
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except Exception as exc:  # mujoco raises ValueError with the parser's message
        raise FixtureError(f"{path}: MuJoCo cannot load it: {exc}") from None
    model.opt.gravity[:] = 0.0  # set explicitly: accelerations below are then classical
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    return model


class _Route:
    """One loaded model with its data and the ids of G2 and B2."""

    def __init__(self, path):
        self.model = _load(path)
        self.data = mujoco.MjData(self.model)
        self.site = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_SITE, "G2")
        self.body = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, "B2")
        if self.site < 0 or self.body < 0:
            raise FixtureError(f"{path}: needs a site named G2 and a body named B2")


class MujocoEngine(Engine):
    """MuJoCo with the chain's MJCF fixtures (quaternion and euler routes)."""

    name = "mujoco"
    global_coordinates = frozenset({"velocity", "acceleration", "V", "Vdot"})

    def __init__(self, fixture: Fixture):
        self.routes = {
            "quaternion": _Route(fixture.path("two_body.xml")),
            "euler": _Route(fixture.path("two_body_euler.xml")),
        }

    @property
    def version(self) -> str:
        return mujoco.__version__

    def lost_offset(self, route):
        r = self.routes[route]
        if r.model.site_sameframe[r.site] == 1:  # mjSAMEFRAME_BODY: site_pos is ignored
            return float(np.linalg.norm(r.model.site_pos[r.site]))
        return 0.0

    def engine_input(self, route, case, q, u, udot):
        if route == "euler":
            return identity_input(q, u, udot)
        n = q.shape[0]
        eye = lambda q14, nu: np.broadcast_to(np.eye(12), (n, 12, 12))  # noqa: E731
        zero = lambda q14, nu: np.zeros((n, 12, 12))  # noqa: E731
        return quaternion_route_input(case, q, u, udot, eye, zero, lambda q14: q14)

    def note_coordinates(self, route, case, q_e):
        return q_e if route == "euler" else note_from_quaternions(case, q_e)

    def points(self, route, q, v, a):
        r = self.routes[route]
        m, d, site, body = r.model, r.data, r.site, r.body
        n, nv = q.shape[0], m.nv
        pos, J, Jd = np.empty((n, 3)), np.empty((n, 3, nv)), np.empty((n, 3, nv))
        acc = None if a is None else np.empty((n, 3))
        res = np.empty(6)
        for i in range(n):
            d.qpos[:] = q[i]
            d.qvel[:] = v[i]
            mujoco.mj_kinematics(m, d)
            mujoco.mj_comPos(m, d)
            mujoco.mj_comVel(m, d)
            pos[i] = d.site_xpos[site]
            mujoco.mj_jac(m, d, J[i], None, pos[i], body)
            mujoco.mj_jacDot(m, d, Jd[i], None, pos[i], body)
            if a is not None:
                d.qacc[:] = a[i]
                mujoco.mj_rnePostConstraint(m, d)
                mujoco.mj_objectAcceleration(m, d, mujoco.mjtObj.mjOBJ_SITE, site, res, 0)
                acc[i] = res[3:]  # [angular; linear], world components
        return PointKinematics(position=pos, J=J, J_dot=Jd, acceleration=acc)
