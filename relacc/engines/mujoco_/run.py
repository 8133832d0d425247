"""MuJoCo applying exactly a scene's effects, and stepping: ``mj_step`` from Python and ``mujoco.rollout``.

Imports only ``mujoco``. :func:`configure` makes a model apply exactly the given effects and nothing else from its
file: contacts, constraints, equality, friction loss, limits, actuators, tendon and joint springs and dampers, fluid
forces, gravity compensation and the automatic reset on instability are off; gravity is the effects' (or the
model's own); joint springs and dampers are ``jnt_stiffness``, ``qpos_spring``, ``dof_damping`` of the named joints;
body loads are ``xfrc_applied`` (a force at the body's centre of mass and a torque, world components). A
sinusoidal load is set at every stage of every step from ``d.time`` by MuJoCo's control callback, which MuJoCo calls
only with actuation on: actuation then stays on with every actuator's gain and bias zeroed.
"""

from __future__ import annotations

import contextlib
import time

import mujoco
import numpy as np
from mujoco import rollout as mj_rollout

from relacc.dynamics.steps import Stepper
from relacc.engines.base import fixed_step_only
from relacc.engines.mujoco_.spec import TYPES
from relacc.errors import EngineError, IntegrationError

SPLIT_PASSIVE = hasattr(mujoco.mjtDisableBit, "mjDSBL_SPRING")
"""From MuJoCo 3.3.6 the passive-force disable flag is two, ``mjDSBL_SPRING`` and ``mjDSBL_DAMPER`` (3.3.1 to 3.3.5
have ``mjDSBL_PASSIVE``; measured release by release)."""

UNSTABLE = ("mjWARN_BADQACC", "mjWARN_BADQVEL", "mjWARN_BADQPOS")
"""MuJoCo's warnings that a simulation became unstable (NaN, inf or a huge value in qacc, qvel or qpos)."""

INTEGRATORS = {"rk4": "mjINT_RK4", "euler": "mjINT_EULER", "implicit": "mjINT_IMPLICIT",
               "implicitfast": "mjINT_IMPLICITFAST"}

ROLLOUT_STEPS = 4096
"""Steps per ``mujoco.rollout`` call (its output holds every step's state: 4096 x nstate doubles)."""


def unstable_count(d) -> int:
    """How many instability warnings MuJoCo has counted on ``d`` so far."""
    return sum(int(d.warning[getattr(mujoco.mjtWarning, w)].number) for w in UNSTABLE)


def check_stable(d, seen: int) -> None:
    """Raise :class:`relacc.IntegrationError` when MuJoCo counted an instability since ``seen``: its state may
    still be finite (huge), or reset to qpos0 where auto-reset is on; either way the run has diverged."""
    if unstable_count(d) > seen:
        stats = [(getattr(mujoco.mjtWarning, w), d.warning[getattr(mujoco.mjtWarning, w)]) for w in UNSTABLE]
        said = [" ".join(mujoco.mju_warningText(kind, int(s.lastinfo)).split()) for kind, s in stats if s.number]
        raise IntegrationError(f"the integration diverged: MuJoCo reports {'; '.join(said)}; reduce the step or use "
                               "an implicit integrator")


class Original:
    """The model's own values of what :func:`configure` overwrites, kept to restore its own reading."""

    def __init__(self, m):
        self.gravity, self.flags = m.opt.gravity.copy(), int(m.opt.disableflags)
        self.density, self.viscosity, self.wind = float(m.opt.density), float(m.opt.viscosity), m.opt.wind.copy()
        self.gain, self.bias = m.actuator_gainprm.copy(), m.actuator_biasprm.copy()


def configure(adapter, effects, t: float = 0.0) -> list[str]:
    """Make ``adapter``'s model apply exactly ``effects`` (None: its own gravity) at time ``t``; returns the disable
    flags set, for reports (see the module docstring).

    Raises:
        InputError: a joint or body the model does not have.
    """
    m, d, own = adapter.model, adapter.data, adapter.original
    D = mujoco.mjtDisableBit
    timed = effects is not None and any(load.frequency for load in effects.bodies.values())
    flags = D.mjDSBL_CONTACT | D.mjDSBL_CONSTRAINT | D.mjDSBL_EQUALITY | D.mjDSBL_FRICTIONLOSS | D.mjDSBL_LIMIT
    flags |= 0 if timed else D.mjDSBL_ACTUATION
    flags |= D.mjDSBL_AUTORESET  # never restart silently from qpos0 when unstable: we report it
    gravity = None if effects is None else effects.gravity
    if gravity is None:
        m.opt.gravity[:] = own.gravity
        flags |= own.flags & D.mjDSBL_GRAVITY
    else:
        m.opt.gravity[:] = gravity
        flags |= D.mjDSBL_GRAVITY if not np.any(gravity) else 0
    m.opt.density = m.opt.viscosity = 0.0
    m.opt.wind[:] = 0.0
    m.body_gravcomp[:] = 0.0
    m.tendon_stiffness[:] = 0.0
    m.tendon_damping[:] = 0.0
    m.jnt_stiffness[:] = 0.0
    m.dof_damping[:] = 0.0
    m.actuator_gainprm[:] = 0.0 if timed else own.gain
    m.actuator_biasprm[:] = 0.0 if timed else own.bias
    springs = dampers = False
    if effects is not None:
        for name, eff in effects.joints.items():
            k = adapter.joint_id(name)
            kind = TYPES[int(m.jnt_type[k])]
            qa, da = int(m.jnt_qposadr[k]), int(m.jnt_dofadr[k])
            nv = {"free": 6, "ball": 3}.get(kind, 1)
            if eff.stiffness:
                m.jnt_stiffness[k] = eff.stiffness
                rest = eff.rest if eff.rest is not None else ((1.0, 0.0, 0.0, 0.0) if kind == "ball" else 0.0)
                m.qpos_spring[qa:qa + (4 if kind == "ball" else 1)] = rest
                springs = True
            if eff.damping:
                m.dof_damping[da:da + nv] = eff.damping
                dampers = True
    if SPLIT_PASSIVE:  # the passive flag in two
        flags |= (0 if springs else D.mjDSBL_SPRING) | (0 if dampers else D.mjDSBL_DAMPER)
    elif not (springs or dampers):
        flags |= D.mjDSBL_PASSIVE
    m.opt.disableflags = int(flags)
    set_loads(adapter, effects, t, d)
    return sorted(name[len("mjDSBL_"):].lower() for name, bit in D.__members__.items()
                  if name.startswith("mjDSBL_") and bit and int(flags) & int(bit) == int(bit))


def set_loads(adapter, effects, t, d) -> None:
    """``d.xfrc_applied``: each named body's load at time ``t`` (force at its centre of mass, torque), else zero."""
    d.xfrc_applied[:] = 0.0
    if effects is None:
        return
    for name, load in effects.bodies.items():
        b = adapter.body_id(name)
        s = float(load.factor(t))
        d.xfrc_applied[b, 0:3] = s * load.force
        d.xfrc_applied[b, 3:6] = s * load.torque


@contextlib.contextmanager
def timed_loads(adapter, effects):
    """MuJoCo's control callback setting the loads at every stage's ``d.time``, while the block runs."""
    if effects is None or not any(load.frequency for load in effects.bodies.values()):
        yield
        return
    mujoco.set_mjcb_control(lambda m, d: set_loads(adapter, effects, d.time, d))
    try:
        yield
    finally:
        mujoco.set_mjcb_control(None)


def stepper(adapter, effects, dt, integrator, accuracy=None) -> Stepper:
    """MuJoCo's own ``mj_step`` with ``opt.integrator`` and ``opt.timestep = dt`` under exactly ``effects``.

    Blocks of records run through ``mujoco.rollout`` (MuJoCo's compiled step loop, the same ``mj_step``; constant
    loads as ``xfrc_applied`` controls) at most :data:`ROLLOUT_STEPS` steps per call; ``advance`` and runs with
    sinusoidal loads step from Python. Time runs on from one call to the next, from 0.
    """
    if integrator not in INTEGRATORS:
        raise EngineError(f"MuJoCo integrators: {', '.join(INTEGRATORS)}; got {integrator!r}")
    fixed_step_only("MuJoCo", accuracy)
    m, d = adapter.model, adapter.data
    mujoco.mj_resetData(m, d)
    configure(adapter, effects)
    m.opt.timestep = dt
    m.opt.integrator = getattr(mujoco.mjtIntegrator, INTEGRATORS[integrator])
    timed = effects is not None and any(load.frequency for load in effects.bodies.values())

    def advance(x, v, k):
        d.qpos[:], d.qvel[:] = x, v
        seen = unstable_count(d)
        with timed_loads(adapter, effects):
            for _ in range(k):
                mujoco.mj_step(m, d)
        check_stable(d, seen)
        return d.qpos.copy(), d.qvel.copy()

    if timed:
        return Stepper(advance)
    work = [mujoco.MjData(m)]

    def record(x, v, gaps):
        X, V, first_bad, _ = rollout(adapter, np.asarray(x)[None], np.asarray(v)[None], np.cumsum(gaps), work)
        return X[0], V[0], int(first_bad[0])

    return Stepper(advance, record)


def rollout(adapter, qpos, qvel, ends, work):
    """Records of ``n`` runs from ``qpos (n, nq)``, ``qvel (n, nv)`` after ``ends[j]`` steps each (ascending; a 0
    records the state as it is), by ``mujoco.rollout`` on the threads of the ``MjData`` list ``work``, in calls
    of at most :data:`ROLLOUT_STEPS` steps, under the model as :func:`stepper` configured it (constant loads).

    Returns:
        ``(X (n, m, nq), V (n, m, nv), first_bad (n,), seconds)``: ``first_bad[i]`` the first record of run ``i``
        that is not finite (``m`` when none is), ``seconds`` the time inside ``mujoco.rollout``.

    Raises:
        IntegrationError: MuJoCo counted an instability (a huge or non-finite acceleration) during a call.
    """
    m = adapter.model
    xfrc = adapter.data.xfrc_applied.ravel().copy()[None, None]  # the scene's loads
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
        while k + 1 < count and ends[k + 1] - base <= ROLLOUT_STEPS:
            k += 1
        seen = sum(unstable_count(w) for w in work)
        start = time.perf_counter()
        out, _ = mj_rollout.rollout(m, work, state, xfrc, control_spec=mujoco.mjtState.mjSTATE_XFRC_APPLIED,
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
