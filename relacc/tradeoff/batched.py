"""Dynamics and simulation against the engines' batched APIs, and what fresh output memory costs.

Four measurements, the same states and model for everyone (the fixture's chain: free B1, B2 on a
translation and a spherical joint), each at 1 thread and at every core:

* ``dynamics``: forward dynamics of a batch of states with gravity on. relacc:
  :func:`relacc.dynamics.accelerations` with an ``out=`` buffer, per case; Pinocchio:
  ``pin.abaInParallel`` on a ``pin.ModelPool``, inputs prepared in its column-major layout
  before timing (its fastest use). Nanoseconds per state.
* ``step``: one scene (``tumbling``, RK4, its ``dt``), step after step. relacc: the compiled
  stepper of :func:`relacc.dynamics.integrate.stepper`, called once per step from Python and
  once for all steps (its compiled loop); MuJoCo: ``mj_step`` per step from Python and
  ``mujoco.rollout`` of the one state (MuJoCo's compiled loop), RK4 at the same ``dt``.
  Microseconds per step.
* ``ensemble``: the same scene from ``members`` perturbed initial states. relacc:
  :func:`relacc.simulate.ensemble` (integration seconds); MuJoCo: ``mujoco.rollout`` with a
  persistent thread pool, ``skip_checks`` and preallocated output (its fastest use).
  Steps per second.
* ``memory``: ``g2_kinematics`` (full output, case 1) on the first call of the process into fresh
  memory, on later calls that allocate new outputs (every call of a user who keeps each
  result), and with ``out=`` buffers (the steady state). Nanoseconds per state.

Every figure is the median and the minimum of ``repeats`` timings after warm-ups, but the first
call (one timing by definition). Used by ``benchmarks/batched.py`` (the recorded runs) and by the
report's throughput section (a smaller run on the machine the report is made on).
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

import numpy as np

import relacc
from relacc.core.conventions import Route
from relacc.core.states import random_states
from relacc.dynamics import accelerations
from relacc.dynamics.effects import Effects
from relacc.dynamics.integrate import stepper
from relacc.engines import anchor, anchors, load_engine, with_capability
from relacc.engines.capabilities import BatchedForward, Rollout
from relacc.errors import EngineError
from relacc.kernels.jit import threads as numba_threads
from relacc.simulate.ensemble import ensemble
from relacc.simulate.members import perturbed
from relacc.simulate.scenes import Scene
from relacc.tradeoff.throughput import machine, one_thread, wall_times

GRAVITY = Effects(gravity=np.array([0.0, 0.0, -9.81]))
"""The forward-dynamics benchmark's effects (the issue's anchor: gravity on)."""


def tumbling(duration: float, fixture=None) -> Scene:
    """The shipped ``tumbling`` scene (no effect, RK4, dt 1e-3) for ``duration`` s, recording its end only.

    ``fixture``: the chain and models to run it on (default: the scene's own, the shipped chain).
    """
    from relacc.fixtures.shipped import scene_path
    from relacc.simulate.scenes import load as load_scene

    scene = load_scene(scene_path("tumbling"))
    return scene.replace(duration=duration, record_every=max(1, round(duration / scene.dt)),
                         fixture=scene.fixture if fixture is None else fixture)


def thread_counts() -> tuple[int, ...]:
    """1 and every core (just 1 on a one-core machine)."""
    cores = os.cpu_count() or 1
    return (1,) if cores == 1 else (1, cores)


def _row(section, who, threads, seconds, per, unit, **extra):
    median, best = seconds
    return {"section": section, "who": who, "threads": threads, "value": median / per, "value_best": best / per,
            "unit": unit, **extra}


def dynamics_rows(fixture, n_states: int, repeats: int, seed: int) -> list[dict]:
    """Forward dynamics, ns per state: relacc per case and ``pin.abaInParallel``, at each thread count."""
    chain, rows = fixture.chain, []
    for case in (1, 2, 3):
        s = random_states(case, n_states, [seed, case])
        out = np.empty((n_states, 12))
        for t in thread_counts():
            with numba_threads(t):
                secs = wall_times(lambda: accelerations(chain, case, s.q, s.u, GRAVITY, out=out), repeats, warmups=3)
            rows.append(_row("dynamics", "relacc", t, secs, n_states * 1e-9, "ns/state", case=case))
    s = random_states(1, n_states, [seed, 1])
    for name in with_capability(BatchedForward):  # Pinocchio's abaInParallel
        engine = load_engine(name, fixture)
        adapter = engine.adapter
        if not isinstance(adapter, BatchedForward):  # its traits said so: never
            raise EngineError(f"{name}'s adapter offers no batched forward dynamics, though its traits say so")
        x = engine.engine_input(Route.QUATERNION, relacc.Case(1), s.q, s.u, None)
        for t in thread_counts():
            loop = adapter.batched_forward(t, x.q.T, x.v.T, gravity=GRAVITY.gravity)
            secs = wall_times(loop, repeats, warmups=2)
            rows.append(_row("dynamics", anchor(name, "batched_forward"), t, secs, n_states * 1e-9, "ns/state",
                             case=None))
    return rows


def step_rows(scene: Scene, n_steps: int, repeats: int) -> list[dict]:
    """One scene's step, us per step: relacc's stepper and MuJoCo, per step from Python and in compiled loops."""
    rows = []
    run = stepper(scene.chain, scene.case, scene.chain_effects, scene.dt, scene.integrator)
    q0, u0 = scene.q.astype(float), scene.u.astype(float)

    def relacc_python():
        q, u = q0, u0
        for _ in range(n_steps):
            q, u = run.advance(q, u, 1)

    with one_thread():
        rows.append(_row("step", "relacc, step per call", 1, wall_times(relacc_python, repeats), n_steps * 1e-6,
                         "us/step"))
        rows.append(_row("step", "relacc, compiled loop", 1, wall_times(lambda: run.advance(q0, u0, n_steps), repeats),
                         n_steps * 1e-6, "us/step"))
    for name in with_capability(Rollout):  # MuJoCo's mj_step and mujoco.rollout
        engine, adapter = _rollout_engine(name, scene)
        qpos, qvel = _engine_states(engine, scene, q0[None], u0[None])
        rows.append(_row("step", anchor(name, "step"), 1,
                         wall_times(adapter.step_loop(qpos[0], qvel[0], n_steps), repeats), n_steps * 1e-6,
                         "us/step"))
        loop = adapter.rollout_loop(qpos, qvel, n_steps, 1)
        try:
            rows.append(_row("step", anchor(name, "rollout"), 1, wall_times(loop, repeats), n_steps * 1e-6,
                             "us/step"))
        finally:
            loop.close()
    return rows


def _rollout_engine(name: str, scene: Scene) -> tuple:
    """``(chain engine, its adapter)`` of an engine offering :class:`relacc.engines.capabilities.Rollout`, its model
    configured for the scene (flags, dt, integrator)."""
    engine = load_engine(name, scene.fixture)
    adapter = engine.adapter
    if not isinstance(adapter, Rollout):  # its traits said so: never
        raise EngineError(f"{name}'s adapter offers no rollout, though its traits say so")
    adapter.stepper(scene.engine_effects, scene.dt, scene.integrator)
    return engine, adapter


def _engine_states(engine, scene, q0, u0):
    x = engine.engine_input(Route.QUATERNION, relacc.Case(scene.case), q0, u0, None)
    return np.ascontiguousarray(x.q), np.ascontiguousarray(x.v)


def ensemble_rows(scene: Scene, members: int, repeats: int, seed: int) -> list[dict]:
    """Ensembles, steps per second: relacc's and ``mujoco.rollout``'s, at each thread count."""
    rows = []
    q0, u0 = perturbed(scene, members, 0.01, seed)
    n_steps = scene.n_steps
    steps = members * n_steps
    for t in thread_counts():
        ensemble(scene, q0[:2], u0[:2], threads=t)  # thread pool and compiled loop ready
        times = [ensemble(scene, q0, u0, threads=t).seconds for _ in range(repeats)]
        rows.append(_row("ensemble", "relacc", t, (np.median(times), np.min(times)), 1.0, "s", members=members,
                         steps=steps))
    for name in with_capability(Rollout):  # mujoco.rollout
        engine, adapter = _rollout_engine(name, scene)
        qpos, qvel = _engine_states(engine, scene, q0, u0)
        for t in thread_counts():
            loop = adapter.rollout_loop(qpos, qvel, n_steps, t)
            try:
                secs = wall_times(loop, repeats, warmups=1)
            finally:
                loop.close()
            rows.append(_row("ensemble", anchor(name, "rollout"), t, secs, 1.0, "s", members=members, steps=steps))
    for row in rows:  # steps per second from the median and the minimum seconds
        row["value"], row["value_best"], row["unit"] = steps / row["value"], steps / row["value_best"], "steps/s"
    return rows


def memory_rows(fixture, n_states: int, repeats: int, seed: int) -> list[dict]:
    """``g2_kinematics`` (full output, case 1), ns per state: first call, allocating calls, ``out=`` buffers.

    Call this first in a process: the first call's figure is only honest on memory the process
    has not touched yet (the kernel itself is compiled on a small batch before).
    """
    chain, s = fixture.chain, random_states(1, n_states, [seed, 1])
    relacc.g2_kinematics(chain, 1, s.q[:64], s.u[:64], s.udot[:64])  # compiled, thread pool up
    start = time.perf_counter()
    k = relacc.g2_kinematics(chain, 1, s.q, s.u, s.udot)
    first = time.perf_counter() - start
    rows = [_row("memory", "first call, fresh memory", None, (first, first), n_states * 1e-9, "ns/state")]
    kept = []
    secs = wall_times(lambda: kept.append(relacc.g2_kinematics(chain, 1, s.q, s.u, s.udot)), repeats, warmups=0)
    rows.append(_row("memory", "new outputs every call", None, secs, n_states * 1e-9, "ns/state"))
    kept.clear()
    out = tuple(np.empty_like(a) for a in (k.position, k.velocity, k.acceleration, k.V, k.Vdot))
    secs = wall_times(lambda: relacc.g2_kinematics(chain, 1, s.q, s.u, s.udot, out=out), repeats)
    rows.append(_row("memory", "out= buffers", None, secs, n_states * 1e-9, "ns/state"))
    return rows


def run(fixture, scene: Scene, *, n_states: int, n_steps: int, members: int, repeats: int, seed: int = 0) -> dict:
    """Every measurement of the module docstring; plain data with the machine's description."""
    described = machine()
    rows = memory_rows(fixture, n_states, repeats, seed)  # first: its first call needs fresh memory
    rows += dynamics_rows(fixture, n_states, repeats, seed)
    rows += step_rows(scene, n_steps, repeats)
    rows += ensemble_rows(scene, members, repeats, seed)
    return {"machine": described, "n_states": n_states, "n_steps": n_steps, "members": members,
            "ensemble_steps": scene.n_steps, "scene": scene.name,
            "dt": scene.dt, "integrator": scene.integrator, "repeats": repeats, "seed": seed, "rows": rows}


def ratios(result: dict) -> dict:
    """The issue's three goals from one run (medians; ``_best``: minima), at the most threads measured.

    ``dynamics``: ``abaInParallel``'s time over relacc's slowest case; ``ensemble``: relacc's steps per
    second over ``mujoco.rollout``'s; ``step``: ``mj_step``'s time per step from Python over relacc's
    step per call; ``step_loop``: ``mujoco.rollout``'s over relacc's compiled loop (one state).
    """
    rows = result["rows"]
    t = max(r["threads"] or 1 for r in rows)

    def pick(section, who, threads=None):
        return [r for r in rows if r["section"] == section and r["who"] == who
                and (threads is None or r["threads"] == threads)]

    def first(kind, section):
        """The first engine's anchor row of a kind that the run has (one engine offers each today)."""
        return next(who for who in anchors(kind) if pick(section, who))

    forward, step, rollout = first("batched_forward", "dynamics"), first("step", "step"), first("rollout", "step")

    out = {}
    for key in ("value", "value_best"):
        suffix = "" if key == "value" else "_best"
        worst = max(r[key] for r in pick("dynamics", "relacc", t))

        def over(section, a, b, threads=None):
            return pick(section, a, threads)[0][key] / pick(section, b, threads)[0][key]

        out["dynamics" + suffix] = pick("dynamics", forward, t)[0][key] / worst
        out["ensemble" + suffix] = over("ensemble", "relacc", rollout, t)
        out["step" + suffix] = over("step", step, "relacc, step per call")
        out["step_loop" + suffix] = over("step", rollout, "relacc, compiled loop")
    out["threads"] = t
    return out


def recorded_runs(directory: Path | None = None) -> list[dict]:
    """The recorded runs of ``benchmarks/batched.py``, oldest first: ``{"file", "machine", "ratios"}``."""
    if directory is None:
        from relacc.fixtures.shipped import recorded_dir

        directory = recorded_dir()
    directory = Path(directory)
    from relacc.fixtures.shipped import recorded_runs as runs_of

    paths = runs_of("batched", directory)
    return [{"file": p.name, "machine": (d := json.loads(p.read_text()))["machine"], "ratios": ratios(d)}
            for p in paths]


def print_table(result: dict) -> None:
    m = result["machine"]
    print(f"dynamics and simulation; {m['date']}, {m['cpu']}, {m['logical_cpus']} CPUs, commit {m['relacc_commit']}; "
          f"median (minimum) of {result['repeats']} repeats")

    for r in result["rows"]:
        case = "" if r.get("case") is None else f"case {r['case']}"
        label = f"{r['section']:9s} {r['who']:28s} {case:7s}"
        threads = "" if r["threads"] is None else f"{r['threads']} thr"
        print(f"{label} {threads:6s} {r['value']:14,.1f} ({r['value_best']:,.1f}) {r['unit']}")
    for k, v in ratios(result).items():
        print(f"  {k}: {v:.2f}" if k != "threads" else f"  at {v} threads")
