"""Ensembles: one scene from many initial states, on relacc and the engines' batched APIs.

* ``relacc``: its side of the scene (:class:`relacc.simulate.subjects.NoteChain`: the chain's compiled
  integrators of :mod:`relacc.kernels.dynamics`, in parallel over the members, each member's steps in one
  compiled loop; :class:`relacc.simulate.subjects.ModelTree`: the tree stepper on every member at once);
* an engine whose adapter offers :class:`relacc.engines.capabilities.Rollout`
  (MuJoCo: ``mujoco.rollout``, its own threaded rollouts, one ``MjData`` per
  thread, the scene's forces as ``xfrc_applied`` controls): that loop;
* one that offers :class:`relacc.engines.capabilities.ThreadedStepper`
  (Pinocchio: RKMK4 on its manifold with every stage's accelerations from
  ``pin.abaInParallel`` over the members): its stepper on every member at once;
* any other engine (Drake), or an integrator or effect those paths do not take:
  its own stepper, member after member.

Records follow the one recording rule (:func:`relacc.dynamics.steps.recorded_steps`):
``t = 0``, every ``record_every``-th step, ``t = duration``. G2's position,
velocity and classical acceleration at every record are computed afterwards,
in batches, by each engine (relacc: its formulas).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from relacc.core.cases import check_int
from relacc.dynamics.steps import recorded_steps
from relacc.errors import EngineError, IntegrationError
from relacc.limits import require_memory
from relacc.simulate.scenes import SIM_ENGINES, Scene
from relacc.simulate.subjects import adapter, batched, check_done, reference_state


@dataclass(frozen=True, eq=False)
class Ensemble:
    """An ensemble's run on one engine.

    Attributes:
        engine: who ran it. t: ``(m,)`` s.
        q, u: ``(N, m, nq)``, ``(N, m, 12)``: the members' states in the scene's case coordinates
            (relacc) or the engine's own (``columns`` say which).
        position, velocity, acceleration: ``(N, m, 3)``: G2 in R, fixed components (m, m/s, m/s^2;
            classical acceleration).
        seconds: wall time of the integration alone; steps: ``N x n_steps``.
        threads: threads the integration used.
    """

    engine: str
    t: np.ndarray
    q: np.ndarray = field(repr=False)
    u: np.ndarray = field(repr=False)
    position: np.ndarray = field(repr=False)
    velocity: np.ndarray = field(repr=False)
    acceleration: np.ndarray = field(repr=False)
    seconds: float
    steps: int
    threads: int

    @property
    def steps_per_second(self) -> float:
        return self.steps / self.seconds if self.seconds > 0 else float("inf")


def require_ensemble_memory(scene: Scene, n: int) -> None:
    """Refuse up front an ensemble of ``n`` members whose records cannot fit in memory: every member's state,
    point and energy at every record, twice (the run and its comparison).

    Raises:
        InputError: the estimate, what is available, and what to reduce.
    """
    m = len(recorded_steps(scene.n_steps, scene.record_every))
    require_memory(8.0 * n * m * (scene.q.size + scene.u.size + 9) * 2, f"an ensemble of {n} members x {m} records",
                   "use record_every > 1, or fewer members per call")


def ensemble(scene: Scene, q0: np.ndarray, u0: np.ndarray, *, engine: str = "relacc", threads: int | None = None
             ) -> Ensemble:
    """Run the scene from every initial state ``q0 (N, nq)``, ``u0 (N, 12)`` (its case's coordinates) on one engine.

    Args:
        threads: threads for relacc, MuJoCo and Pinocchio (default: numba's, i.e. the cores).

    Raises:
        EngineError: an unknown engine or an integrator it lacks. IntegrationError: a member diverged
            (which one, and when). InputError: bad initial states; a request that cannot fit in memory.
    """
    if engine not in SIM_ENGINES:
        raise EngineError(f"unknown engine {engine!r}: accepted are {', '.join(SIM_ENGINES)}")
    q0, u0 = _checked(scene, q0, u0)
    if q0.ndim != 2 or u0.ndim != 2 or len(q0) != len(u0):
        raise EngineError(f"q0 and u0 must be (N, nq) and (N, nv) with the same N, got {q0.shape}, {u0.shape}")
    steps = recorded_steps(scene.n_steps, scene.record_every)
    require_ensemble_memory(scene, len(q0))
    if threads is None:
        from relacc.kernels.jit import numba

        threads = numba.get_num_threads() if numba is not None else 1
    threads = check_int("threads", threads, minimum=1)
    if engine == "relacc":
        return _relacc(scene, q0.astype(float), u0.astype(float), steps, threads, engine)
    return _engine(scene, q0.astype(float), u0.astype(float), steps, threads, engine)


def _checked(scene, q0, u0):
    """Initial states checked as the scene's case takes them on its tree (the chain's too)."""
    from relacc.core.tree.coordinates import check_q, check_u

    return check_q(scene.subject_tree, scene.case, q0), check_u(scene.subject_tree, "u0", u0)


def _relacc(scene, q0, u0, steps, threads, name):
    """relacc's own ensemble: its side of the scene (:attr:`Scene.evaluator`: the note's chain on its fused kernels, a
    model's tree on its stepper) integrates every member, then gives the point at every record."""
    Q, U, seconds = scene.evaluator.integrate(scene, q0, u0, steps, threads)
    n, m = Q.shape[:2]
    pos, vel, acc = scene.evaluator.point(scene, Q.reshape(n * m, -1), U.reshape(n * m, -1),
                                          np.tile(steps * scene.dt, n))
    return Ensemble("relacc", steps * scene.dt, Q, U, pos.reshape(n, m, 3), vel.reshape(n, m, 3),
                    acc.reshape(n, m, 3), seconds, n * int(steps[-1]), threads)


def _engine_states(engine, scene, q0, u0):
    """Members' states in an engine's coordinates (its adapter's, from the reference's)."""

    states_e = engine.to_engine(*reference_state(scene, q0, u0))

    qe, ve = states_e.q, states_e.v
    return np.ascontiguousarray(qe), np.ascontiguousarray(ve)


def _observed(engine_name, engine, scene, Q, V, steps, seconds, threads):
    """The point at every record of an engine's ensemble, by the engine itself (its own forward dynamics)."""
    n, m = Q.shape[:2]
    flat_q, flat_v = Q.reshape(n * m, -1), V.reshape(n * m, -1)
    t = np.tile(steps * scene.dt, n)
    pts = engine.points(flat_q, flat_v, engine.forward(flat_q, flat_v, scene.engine_effects, t), [scene.point])
    velocity = np.einsum("nij,nj->ni", pts.J[:, 0], flat_v)
    return Ensemble(engine_name, steps * scene.dt, Q, V, pts.position[:, 0].reshape(n, m, 3),
                    velocity.reshape(n, m, 3), pts.acceleration[:, 0].reshape(n, m, 3), seconds, n * int(steps[-1]),
                    threads)


def _engine(scene, q0, u0, steps, threads, name):
    """An engine's fastest path its adapter offers (module docstring)."""
    from relacc.engines.capabilities import Rollout, ThreadedStepper

    engine = adapter(scene, name)
    integrator, accuracy = scene.integrator_for(name)
    if isinstance(engine, Rollout) and accuracy is None:
        stepper = engine.stepper(scene.engine_effects, scene.dt, integrator)  # configures the model
        if stepper.records_blocks:  # not with sinusoidal loads (a control callback): member after member then
            qpos, qvel = _engine_states(engine, scene, q0, u0)
            try:
                Q, V, first_bad, seconds = engine.rollout(qpos, qvel, np.asarray(steps), engine.work_data(threads))
            except IntegrationError as exc:
                raise IntegrationError(f"{name}: {exc} (dt = {scene.dt} s)") from None
            check_done(first_bad, len(steps), steps, scene, name)
            return _observed(name, engine, scene, Q, V, steps, seconds, threads)
    if isinstance(engine, ThreadedStepper) and integrator in engine.THREADED_INTEGRATORS and accuracy is None:
        x, v = _engine_states(engine, scene, q0, u0)
        stepper = engine.stepper(scene.engine_effects, scene.dt, integrator, threads=threads)
        Q, V, seconds = batched(stepper, x, v, steps, scene, name)
        return _observed(name, engine, scene, Q, V, steps, seconds, threads)
    return _one_by_one(scene, q0, u0, steps, threads, name, engine)


def _one_by_one(scene, q0, u0, steps, threads, name, engine=None):
    """Any engine's own stepper, member after member (one thread); ``engine``: its adapter, if loaded already."""
    from relacc.dynamics.steps import blocks

    engine = adapter(scene, name) if engine is None else engine
    integrator, accuracy = scene.integrator_for(name)
    x0, v0 = _engine_states(engine, scene, q0, u0)
    n, m = len(q0), len(steps)
    Q, V = np.empty((n, m, x0.shape[1])), np.empty((n, m, v0.shape[1]))
    seconds = 0.0
    for i in range(n):
        stepper = engine.stepper(scene.engine_effects, scene.dt, integrator, accuracy)
        start = time.perf_counter()
        at = 0
        for chunk, X, Vb in blocks(stepper, x0[i], v0[i], steps, who=f"{name} member {i}", dt=scene.dt,
                                   integrator=integrator):
            Q[i, at:at + len(chunk)], V[i, at:at + len(chunk)] = X, Vb
            at += len(chunk)
        seconds += time.perf_counter() - start
    return _observed(name, engine, scene, Q, V, steps, seconds, 1)
