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

import contextlib
import time

import mujoco
import numpy as np
from mujoco import rollout

from relacc.dynamics.steps import Stepper
from relacc.engines.base import (
    Engine,
    PointKinematics,
    identity_input,
    note_from_quaternions,
    quaternion_route_input,
)
from relacc.errors import EngineError, FixtureError
from relacc.fixtures import Fixture

WARNINGS_KEPT = 1000
"""MuJoCo's warnings are kept in memory, the newest this many, for the command that caused them."""

_WARNINGS: list[str] = []


def _warning(message: str) -> None:
    """MuJoCo's warning handler: keep the message (one line) for relacc's output, never the terminal or a file."""
    _WARNINGS.append(" ".join(str(message).split()))
    del _WARNINGS[:-WARNINGS_KEPT]


# Without a handler MuJoCo prints its warnings and appends them to MUJOCO_LOG.TXT in the working
# directory; relacc reports them in its own output instead (captured_warnings).
mujoco.set_mju_user_warning(_warning)


@contextlib.contextmanager
def captured_warnings():
    """Inside the block, MuJoCo's warnings are collected into the list it yields (one line each)."""
    start = len(_WARNINGS)
    got: list[str] = []
    try:
        yield got
    finally:
        got.extend(_WARNINGS[start:])
        del _WARNINGS[start:]


def _load(path) -> mujoco.MjModel:
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except Exception as exc:  # mujoco raises ValueError with the parser's message
        raise FixtureError(f"{path}: MuJoCo cannot load it: {exc}") from None
    model.opt.gravity[:] = 0.0  # set explicitly: accelerations below are then classical
    model.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONTACT
    return model


def full_inertia(m, d, dst):
    """Dense joint-space inertia into ``dst``.

    ``mj_fullM`` takes ``(m, d, dst)`` in MuJoCo 4 and ``(m, dst, qM)`` before.
    """
    if hasattr(d, "qM"):
        mujoco.mj_fullM(m, dst, d.qM)
    else:
        mujoco.mj_fullM(m, d, dst)


UNSTABLE = ("mjWARN_BADQACC", "mjWARN_BADQVEL", "mjWARN_BADQPOS")
"""MuJoCo's warnings that a simulation became unstable (NaN, inf or a huge value in qacc, qvel or qpos)."""


def unstable_count(d) -> int:
    """How many instability warnings MuJoCo has counted on ``d`` so far."""
    return sum(int(d.warning[getattr(mujoco.mjtWarning, w)].number) for w in UNSTABLE)


def check_stable(d, seen: int) -> None:
    """Raise :class:`relacc.IntegrationError` when MuJoCo counted an instability since ``seen``: its state may
    still be finite (huge), or reset to qpos0 where auto-reset is on; either way the run has diverged."""
    if unstable_count(d) > seen:
        from relacc.errors import IntegrationError

        stats = [(getattr(mujoco.mjtWarning, w), d.warning[getattr(mujoco.mjtWarning, w)]) for w in UNSTABLE]
        said = [" ".join(mujoco.mju_warningText(kind, int(s.lastinfo)).split()) for kind, s in stats if s.number]
        raise IntegrationError(f"the integration diverged: MuJoCo reports {'; '.join(said)}; reduce the step or use "
                               "an implicit integrator")


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
        with fixture.engine_files() as paths:
            self.routes = {
                "quaternion": _Route(paths["two_body.xml"]),
                "euler": _Route(paths["two_body_euler.xml"]),
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

    def configure(self, effects, route="quaternion"):
        """Make the model apply exactly ``effects`` and nothing else.

        Disabled always: contacts, constraints, equality, friction loss,
        limits, actuation, and the automatic reset on instability (a diverged
        run raises :class:`relacc.IntegrationError` instead of restarting).
        Gravity: ``opt.gravity`` and the gravity flag off
        when absent. Spring and damper on the slides: ``jnt_stiffness``,
        ``qpos_spring``, ``dof_damping``; ball damping: ``dof_damping`` of the
        ball's three dofs; the passive flag off when none is present. Force at
        G2 and torques: ``xfrc_applied`` (applied at each body's center of
        mass, world components). Returns the flags actually set, for reports.
        """
        r = self.routes[route]
        m, d = r.model, r.data
        D = mujoco.mjtDisableBit
        flags = D.mjDSBL_CONTACT | D.mjDSBL_CONSTRAINT | D.mjDSBL_EQUALITY | D.mjDSBL_FRICTIONLOSS \
            | D.mjDSBL_LIMIT | D.mjDSBL_ACTUATION
        if hasattr(D, "mjDSBL_AUTORESET"):  # never restart silently from qpos0 when unstable: we report it
            flags |= D.mjDSBL_AUTORESET
        m.opt.gravity[:] = 0.0 if effects.gravity is None else effects.gravity
        if effects.gravity is None:
            flags |= D.mjDSBL_GRAVITY
        m.jnt_stiffness[:] = 0.0
        m.dof_damping[:] = 0.0
        slides = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"s2_{a}") for a in "xyz"]
        for k, j in enumerate(slides):
            if effects.spring_stiffness is not None:
                m.jnt_stiffness[j] = effects.spring_stiffness[k]
                m.qpos_spring[m.jnt_qposadr[j]] = effects.spring_rest[k]
            if effects.spring_damping is not None:
                m.dof_damping[m.jnt_dofadr[j]] = effects.spring_damping[k]
        if effects.ball_damping is not None:
            if route != "quaternion":
                raise EngineError("ball damping needs the ball joint of the quaternion route")
            ball = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, "B2_ball")
            m.dof_damping[m.jnt_dofadr[ball]:m.jnt_dofadr[ball] + 3] = effects.ball_damping
        active = set(effects.active())
        if hasattr(D, "mjDSBL_SPRING"):  # MuJoCo >= 3.3.3 splits the passive flag in two
            if "spring_stiffness" not in active:
                flags |= D.mjDSBL_SPRING
            if not {"spring_damping", "ball_damping"} & active:
                flags |= D.mjDSBL_DAMPER
        elif not {"spring_stiffness", "spring_damping", "ball_damping"} & active:
            flags |= D.mjDSBL_PASSIVE
        m.opt.disableflags = int(flags)
        d.xfrc_applied[:] = 0.0
        b1 = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "B1")
        if effects.force_G2 is not None:
            d.xfrc_applied[r.body, 0:3] = effects.force_G2
        if effects.torque_B2 is not None:
            d.xfrc_applied[r.body, 3:6] = effects.torque_B2
        if effects.torque_B1 is not None:
            d.xfrc_applied[b1, 3:6] = effects.torque_B1
        return sorted(name[len("mjDSBL_"):].lower() for name, bit in D.__members__.items()
                      if name.startswith("mjDSBL_") and bit and int(flags) & int(bit) == int(bit))

    def applied(self, effects) -> dict:
        """The disable flags :meth:`configure` sets for ``effects``."""
        return {"disabled": self.configure(effects)}

    def _forward(self, q, v, effects):
        """``mj_forward`` at each state under exactly ``effects``; yields ``(i, model, data)``."""
        self.configure(effects)
        r = self.routes["quaternion"]
        m, d = r.model, r.data
        for i in range(q.shape[0]):
            d.qpos[:] = q[i]
            d.qvel[:] = v[i]
            mujoco.mj_forward(m, d)
            yield i, m, d

    def dynamics(self, q, v, effects):
        nv = self.routes["quaternion"].model.nv
        M, f = np.empty((q.shape[0], nv, nv)), np.empty((q.shape[0], nv))
        for i, m, d in self._forward(q, v, effects):
            full_inertia(m, d, M[i])
            f[i] = d.qfrc_smooth  # passive - bias + applied (xfrc_applied included)
        return M, f

    def forward_dynamics(self, q, v, effects):
        out = np.empty((q.shape[0], self.routes["quaternion"].model.nv))
        for i, _, d in self._forward(q, v, effects):
            out[i] = d.qacc
        return out

    ROLLOUT_STEPS = 4096
    """Steps per ``mujoco.rollout`` call (its output holds every step's state: 4096 x nstate doubles)."""

    INTEGRATORS = {"rk4": "mjINT_RK4", "euler": "mjINT_EULER", "implicit": "mjINT_IMPLICIT",
                   "implicitfast": "mjINT_IMPLICITFAST"}

    def stepper(self, effects, dt, integrator, accuracy=None):
        """MuJoCo's own ``mj_step`` with ``opt.integrator`` and ``opt.timestep = dt``.

        Blocks of records run through ``mujoco.rollout`` (MuJoCo's compiled step loop, the same
        ``mj_step``; the scene's forces as ``xfrc_applied`` controls), with at most
        :attr:`ROLLOUT_STEPS` steps per call; ``advance`` steps from Python.
        """
        if integrator not in self.INTEGRATORS:
            raise EngineError(f"MuJoCo integrators: {', '.join(self.INTEGRATORS)}; got {integrator!r}")
        self.fixed_step_only("MuJoCo", accuracy)
        r = self.routes["quaternion"]
        m, d = r.model, r.data
        mujoco.mj_resetData(m, d)
        self.configure(effects)  # after resetData, which clears xfrc_applied
        m.opt.timestep = dt
        m.opt.integrator = getattr(mujoco.mjtIntegrator, self.INTEGRATORS[integrator])

        def advance(x, v, k):
            d.qpos[:], d.qvel[:] = x, v
            seen = unstable_count(d)
            for _ in range(k):
                mujoco.mj_step(m, d)
            check_stable(d, seen)
            return d.qpos.copy(), d.qvel.copy()

        work = [mujoco.MjData(m)]

        def record(x, v, gaps):
            X, V, first_bad, _ = self.rollout(np.asarray(x)[None], np.asarray(v)[None], np.cumsum(gaps), work)
            return X[0], V[0], int(first_bad[0])

        return Stepper(advance, record)

    def work_data(self, threads: int) -> list:
        """``threads`` fresh ``MjData`` of the quaternion route's model, for :meth:`rollout`'s threads."""
        m = self.routes["quaternion"].model
        return [mujoco.MjData(m) for _ in range(max(1, int(threads)))]

    def rollout(self, qpos, qvel, ends, work):
        """Records of ``n`` runs from ``qpos (n, nq)``, ``qvel (n, nv)`` after ``ends[j]`` steps each (ascending; a 0
        records the state as it is), by ``mujoco.rollout`` on the threads of the ``MjData`` list ``work``, in calls
        of at most :attr:`ROLLOUT_STEPS` steps, under the model as :meth:`stepper` configured it.

        Returns:
            ``(X (n, m, nq), V (n, m, nv), first_bad (n,), seconds)``: ``first_bad[i]`` the first record of run ``i``
            that is not finite (``m`` when none is), ``seconds`` the time inside ``mujoco.rollout``.

        Raises:
            IntegrationError: MuJoCo counted an instability (a huge or non-finite acceleration) during a call.
        """
        m = self.routes["quaternion"].model
        xfrc = self.routes["quaternion"].data.xfrc_applied.ravel().copy()[None, None]  # the scene's loads
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        n, nq, nv, count = len(qpos), m.nq, m.nv, len(ends)
        X, V = np.empty((n, count, nq)), np.empty((n, count, nv))
        state = np.zeros((n, mujoco.mj_stateSize(m, spec)))
        state[:, 1:1 + nq], state[:, 1 + nq:1 + nq + nv] = qpos, qvel
        first_bad, seconds, j = np.full(n, count), 0.0, 0
        while j < count:
            if ends[j] == (ends[j - 1] if j else 0):  # a record of the state as it is
                X[:, j], V[:, j] = state[:, 1:1 + nq], state[:, 1 + nq:1 + nq + nv]
                j += 1
                continue
            base = ends[j - 1] if j else 0
            k = j
            while k + 1 < count and ends[k + 1] - base <= self.ROLLOUT_STEPS:
                k += 1
            seen = sum(unstable_count(w) for w in work)
            start = time.perf_counter()
            out, _ = rollout.rollout(m, work, state, xfrc, control_spec=mujoco.mjtState.mjSTATE_XFRC_APPLIED,
                                     nstep=int(ends[k] - base))
            seconds += time.perf_counter() - start
            if sum(unstable_count(w) for w in work) > seen:
                check_stable(next(w for w in work if unstable_count(w)), 0)
            rows = ends[j:k + 1] - base - 1
            X[:, j:k + 1], V[:, j:k + 1] = out[:, rows, 1:1 + nq], out[:, rows, 1 + nq:1 + nq + nv]
            finite = np.all(np.isfinite(X[:, j:k + 1]), axis=2) & np.all(np.isfinite(V[:, j:k + 1]), axis=2)
            bad = ~finite.all(axis=1)
            first_bad[bad] = np.minimum(first_bad[bad], j + np.argmin(finite[bad], axis=1))
            if bad.all():
                break
            state, j = out[:, -1], k + 1
        return X, V, first_bad, seconds

    def body_state(self, q, v):
        return np.array(q, dtype=float), np.array(v, dtype=float)  # qpos, qvel are Case 2's q and u

    def points(self, route, q, v, a):
        r = self.routes[route]
        m, d, site, body = r.model, r.data, r.site, r.body
        n, nv = q.shape[0], m.nv
        pos, J, Jd = np.empty((n, 3)), np.empty((n, 3, nv)), np.empty((n, 3, nv))
        acc = None if a is None else np.empty((n, 3))
        res = np.empty(6)
        # mj_objectAcceleration reports proper acceleration (the world is given -gravity): add it back.
        gravity_on = not m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY
        g = m.opt.gravity.copy() if gravity_on else np.zeros(3)
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
                acc[i] = res[3:] + g  # [angular; linear], world components; proper -> classical
        return PointKinematics(position=pos, J=J, J_dot=Jd, acceleration=acc)
