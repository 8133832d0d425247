"""Throughput: relacc's batched kernels against looping Pinocchio and MuJoCo from Python.

One run, the same states for everyone, per case and per output:

* ``acceleration``: G2's classical acceleration only. Pinocchio:
  ``forwardKinematics(q, v, a)`` + ``updateFramePlacement`` +
  ``getFrameClassicalAcceleration`` per state. MuJoCo: ``mj_kinematics``,
  ``mj_comPos``, ``mj_comVel``, ``mj_rnePostConstraint``,
  ``mj_objectAcceleration`` per state.
* ``full``: position, velocity, acceleration, V and Vdot. Pinocchio adds
  ``computeJointJacobians``, ``computeJointJacobiansTimeVariation``,
  ``getFrameJacobian``, ``getFrameJacobianTimeVariation`` (LOCAL_WORLD_ALIGNED);
  MuJoCo adds ``mj_jac`` and ``mj_jacDot``.

Every loop stores its results into preallocated arrays. relacc is also timed
on one thread (``relacc-1-thread``), like for like with the single-threaded
engine loops; its default uses every core numba is given. Engine coordinates
are prepared before timing (cases 1-2: the quaternion fixture; case 3: the
Euler fixtures, whose coordinates are case 3's own), and the engines return
Jacobians in their own velocity coordinates: the comparison favours the
engines. Times are medians (headline) and minima of repeats after full-size warm-ups
(:func:`wall_times`).

Used by ``benchmarks/throughput.py`` (the recorded runs) and by the report's
throughput section (a smaller run on the machine the report is made on).
"""

from __future__ import annotations

import datetime as dt
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

import relacc
from relacc.core.cases import Case
from relacc.core.conventions import Route
from relacc.core.states import random_states
from relacc.engines import adapter_module, load_engine, with_trait
from relacc.engines.chain import G2
from relacc.fixtures import load
from relacc.kernels import jit
from relacc.kernels import kinematics as fast
from relacc.kernels.jit import threads

TIMED = with_trait("compiled_loops")
"""The engines whose per-state loops run in their own compiled code (Pinocchio, MuJoCo): the ones timed here."""


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def source_commit() -> str | None:
    """The git commit relacc is imported from (``+dirty`` with local changes), or None outside a checkout."""
    root = Path(relacc.__file__).resolve().parent.parent
    try:
        head = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10, check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return head + ("+dirty" if dirty else "") if head else None


def machine() -> dict:
    return {
        "date": dt.date.today().isoformat(),
        "cpu": cpu_model(),
        "logical_cpus": os.cpu_count(),
        "system": f"{platform.system()} {platform.release()} {platform.machine()}",
        "python": sys.version.split()[0],
        "numpy": np.__version__,
        "numba": jit.numba.__version__ if jit.HAVE_NUMBA else None,
        "relacc_backend": fast.BACKEND,
        **{name: adapter_module(name).version() for name in TIMED},
        "relacc": relacc.__version__,
        "relacc_commit": source_commit(),
    }


def one_thread():
    """numba's parallel loops on one thread inside the block (no-op on the numpy backend)."""
    return threads(1)


def wall_times(fn, repeats: int, warmups: int = 2) -> tuple[float, float]:
    """``(median, minimum)`` wall time (s) of ``repeats`` calls after ``warmups`` full-size warm-up calls.

    The median is the headline; the minimum is the cost without interference (on a shared
    2-vCPU VM interference only adds time, and it hits relacc's two threads harder than the
    single-threaded engine loops), the estimator ``timeit`` recommends.
    """
    for _ in range(warmups):  # compilation, thread pool, first-touch memory
        fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times)), float(np.min(times))


def run(n_states: int, repeats: int, seed: int = 0, fixture=None) -> dict:
    """Time every row (see the module docstring); returns plain data with the machine's description."""
    described = machine()  # before timing: the commit as it was when the run started
    fixture = fixture if fixture is not None else load()
    chain = fixture.chain
    engines = {name: load_engine(name, fixture) for name in TIMED}
    states = {case: random_states(case, n_states, [seed, case]) for case in (1, 2, 3)}
    timings: dict[tuple, tuple[float, ...]] = {}
    # relacc first, every case, so its timings never follow seconds of single-threaded engine loops
    many = max(repeats, 30)  # relacc's calls take milliseconds: more of them, after more warm-ups
    for case, s in states.items():
        timings[(case, "relacc", "acceleration")] = wall_times(
            lambda: relacc.g2_acceleration(chain, case, s.q, s.u, s.udot), many, warmups=5)
        timings[(case, "relacc", "full")] = wall_times(
            lambda: relacc.g2_kinematics(chain, case, s.q, s.u, s.udot), many, warmups=5)
        with one_thread():  # like for like with the single-threaded engine loops
            timings[(case, "relacc-1-thread", "acceleration")] = wall_times(
                lambda: relacc.g2_acceleration(chain, case, s.q, s.u, s.udot), many, warmups=5)
            timings[(case, "relacc-1-thread", "full")] = wall_times(
                lambda: relacc.g2_kinematics(chain, case, s.q, s.u, s.udot), many, warmups=5)
        small = slice(0, max(n_states // 10, 1))  # the note's reference implementation, for information
        timings[(case, "relacc-reference", "full")] = wall_times(
            lambda: relacc.g2_kinematics(chain, case, s.q[small], s.u[small], s.udot[small], backend="reference"),
            repeats)
        timings[(case, "relacc-reference", "full")] = tuple(
            x * n_states / len(s.q[small]) for x in timings[(case, "relacc-reference", "full")])
    for case, s in states.items():
        route = Route.EULER if case == Case.ANGLE_RATES else Route.QUATERNION
        c = relacc.Case(case)
        for name in TIMED:
            e = engines[name]
            x = e.engine_input(route, c, s.q, s.u, s.udot)
            adapter = e.routes[route]
            for output in ("acceleration", "full"):
                timings[(case, name, output)] = wall_times(
                    adapter.point_loop(x.q, x.v, x.a, G2, output == "full"), max(1, repeats // 3))
    rows: list[dict[str, Any]] = [
        {"case": case, "who": who, "output": output, "seconds": median, "seconds_min": best,
         "states_per_second": n_states / median, "states_per_second_best": n_states / best,
         "engine_route": (Route.EULER if case == Case.ANGLE_RATES else Route.QUATERNION) if who in TIMED else None}
        for (case, who, output), (median, best) in sorted(timings.items())
    ]
    for row in rows:
        base = next(r for r in rows if r["case"] == row["case"] and r["output"] == row["output"]
                    and r["who"] == "relacc")
        row["relacc_speedup_over_this"] = row["seconds"] / base["seconds"]
        row["relacc_speedup_over_this_best"] = row["seconds_min"] / base["seconds_min"]
    return {"machine": described, "n_states": n_states, "repeats": repeats, "seed": seed, "rows": rows}


def recorded_runs(directory: Path | None = None) -> list[dict]:
    """The recorded throughput runs, oldest first: plain data for the report.

    Each is ``{"file", "machine", "n_states", "ratios"}`` with ``ratios[(case, output)]`` a dict of
    relacc's speed-up over ``pinocchio`` and ``mujoco`` and, when recorded, relacc on one thread
    over Pinocchio (``one_thread_over_pinocchio``). An empty list when no run is recorded.
    """
    if directory is None:
        from relacc.fixtures.shipped import recorded_dir

        directory = recorded_dir()
    directory = Path(directory)
    runs = []
    from relacc.fixtures.shipped import recorded_runs as runs_of

    for path in runs_of("throughput", directory):
        data = json.loads(path.read_text())
        rows = {(r["case"], r["who"], r["output"]): r for r in data["rows"]}
        ratios = {}
        for (case, who, output), r in rows.items():
            if who in TIMED:
                ratios.setdefault((case, output), {})[who] = r["relacc_speedup_over_this"]
                if "relacc_speedup_over_this_best" in r:
                    ratios[(case, output)][who + "_best"] = r["relacc_speedup_over_this_best"]
                one = rows.get((case, "relacc-1-thread", output))
                if one:
                    ratios[(case, output)][f"one_thread_over_{who}"] = r["seconds"] / one["seconds"]
        runs.append({"file": path.name, "machine": data["machine"], "n_states": data["n_states"], "ratios": ratios})
    return runs


def print_table(result: dict) -> None:
    m = result["machine"]
    print(f"throughput, {result['n_states']} states per case, median of {result['repeats']} repeats; "
          f"{m['date']}, {m['cpu']}, {m['logical_cpus']} CPUs, relacc backend {m['relacc_backend']}")
    print(f"{'case':4s} {'output':13s} {'who':17s} {'states/s':>12s} {'relacc is x faster':>19s} "
          f"{'best states/s':>14s} {'x (best)':>9s}")
    for r in result["rows"]:
        print(f"{r['case']:<4d} {r['output']:13s} {r['who']:17s} {r['states_per_second']:12,.0f} "
              f"{r['relacc_speedup_over_this']:19.1f} {r['states_per_second_best']:14,.0f} "
              f"{r['relacc_speedup_over_this_best']:9.1f}")
