"""Cluster scaling: relacc check on a LocalCluster of 1 and 2 workers, task overhead, scheduler time per task.

What is timed (each figure the median of --repeats runs, minimum in the JSON):

* ``check``: case 1 of ``relacc check`` over --states states with --engines, split as the cluster sweep
  splits it (tasks of relacc.cluster.sweeps.CHECK_STATES), on a LocalCluster of 1 and of 2 single-threaded
  worker processes; states per second of the sweep, cluster start-up (processes and relacc's worker
  plugin: imports, compiled kernels from numba's cache) timed apart;
* ``round trip``: one empty task submitted and its result fetched, one at a time;
* ``scheduler``: 2,000 empty tasks submitted at once; seconds per task at the scheduler's pace.

Run:  python benchmarks/cluster.py [--states N] [--engines mujoco,pinocchio] [--repeats R] [--json PATH]
"""

import argparse
import json
import math
import statistics
import sys
import time


def _noop(*_):
    return None


def measure(states: int, engines: tuple, repeats: int) -> dict:
    from relacc.cluster import connect, run
    from relacc.cluster.sweeps import CHECK_STATES, _check_by_case, _merge_by_case
    from relacc.fixtures import load
    from relacc.fixtures.model import inline
    from relacc.tradeoff.throughput import machine
    from relacc.validation.check import CHUNK

    fixture = load()
    fixture = inline(fixture.name, fixture.chain)
    n_chunks = math.ceil(states / CHUNK)
    per_task = math.ceil(CHECK_STATES / CHUNK)
    tasks = [(fixture, engines, states, 0, 1, k, min(k + per_task, n_chunks), False)
             for k in range(0, n_chunks, per_task)]
    out = {"machine": machine(), "states": states, "engines": list(engines), "tasks": len(tasks),
           "states_per_task": CHECK_STATES, "repeats": repeats, "workers": {}}
    for workers in (1, 2):
        start = time.perf_counter()
        with connect(f"local:{workers}") as client:
            startup = time.perf_counter() - start
            run(client, _check_by_case, tasks[:1], _merge_by_case)  # the workers' harnesses loaded (engines)
            sweeps = []
            for _ in range(repeats):
                t = time.perf_counter()
                run(client, _check_by_case, tasks, _merge_by_case)
                sweeps.append(time.perf_counter() - t)
            trips = []
            for _ in range(50):
                t = time.perf_counter()
                client.submit(_noop, pure=False).result()
                trips.append(time.perf_counter() - t)
            bursts = []
            for _ in range(repeats):
                t = time.perf_counter()
                client.gather(client.map(_noop, range(2000), pure=False))
                bursts.append((time.perf_counter() - t) / 2000)
        out["workers"][workers] = {
            "startup_seconds": startup, "sweep_seconds": statistics.median(sweeps), "sweep_seconds_min": min(sweeps),
            "states_per_second": states / statistics.median(sweeps),
            "round_trip_seconds": statistics.median(trips), "scheduler_seconds_per_task": statistics.median(bursts)}
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="relacc check on a local Dask cluster: scaling and overheads")
    parser.add_argument("--states", type=int, default=400_000)
    parser.add_argument("--engines", default="mujoco,pinocchio")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    args = parser.parse_args(argv)
    result = measure(args.states, tuple(args.engines.split(",")), args.repeats)
    m = result["machine"]
    print(f"cluster scaling; {m['date']}, {m['cpu']}, {m['logical_cpus']} CPUs, commit {m['relacc_commit']}; "
          f"check case 1, {result['states']} states, engines {','.join(result['engines'])}, {result['tasks']} tasks")
    for w, r in result["workers"].items():
        print(f"  {w} worker(s): {r['states_per_second']:10,.0f} states/s (sweep {r['sweep_seconds']:.2f} s, "
              f"start-up {r['startup_seconds']:.2f} s); round trip {1e3 * r['round_trip_seconds']:.2f} ms; "
              f"scheduler {1e3 * r['scheduler_seconds_per_task']:.3f} ms/task")
    if args.json:
        from relacc.files import write_text

        write_text(args.json, json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
