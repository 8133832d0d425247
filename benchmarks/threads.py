"""Threads that help: relacc's tree kernels on one thread and on every core, the same batch, batch sizes 9 to 8192.

``relacc.tree_accelerations``, ``relacc.tree_kinematics`` and ``relacc.tree_kinematics(..., partials=False)`` on
gymnasium's ant and humanoid (case 2, fresh outputs: what a caller without ``out=`` gets), inside
``relacc.kernels.jit.threads(1)`` and ``threads(cores)``: microseconds per call, the best of 5 timings of 10 calls,
and the ratio one thread over all. Each kernel runs its batch on the calling thread unless spreading it pays
(:func:`relacc.kernels.jit.parallel_pays`), so the ratio should not fall below 1 by more than the timing noise.

Run:  python benchmarks/threads.py [--json PATH]
"""

import argparse
import json
import os
import sys
import time

from relacc.files import write_text

SIZES = (9, 32, 64, 128, 256, 1024, 8192)


def _best(fn, calls: int = 10, repeats: int = 5) -> float:
    fn()
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            fn()
        best = min(best, (time.perf_counter() - start) / calls)
    return best * 1e6


def main(argv=None) -> int:
    import relacc
    from relacc.core.tree import random_states
    from relacc.kernels.jit import threads
    from relacc.kernels.tree_dynamics import optimize
    from relacc.tradeoff.throughput import machine
    from relacc.tradeoff.trees import gymnasium_models

    parser = argparse.ArgumentParser(description="one thread against every core, batch by batch")
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    args = parser.parse_args(argv)
    cores = os.cpu_count() or 1
    rows = []
    for model, path in gymnasium_models().items():
        tree = relacc.Tree.from_file(path)
        optimize(tree, 2)  # the lanes' -O2 code from the start: one thread and two compare the same code
        for n in SIZES:
            st = random_states(tree, 2, n, 0)
            calls = {"tree_accelerations": lambda: relacc.tree_accelerations(tree, 2, st.q, st.u),
                     "tree_kinematics": lambda: relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot),
                     "tree_kinematics partials=False":
                         lambda: relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, partials=False)}
            for what, fn in calls.items():
                times = {}
                for t in (1, cores):
                    with threads(t):
                        times[t] = _best(fn)
                rows.append({"model": model, "states": n, "call": what, "one_thread_us": times[1],
                             "all_cores_us": times[cores], "ratio": times[1] / times[cores]})
                print(f"{model:9s} {n:5d} {what:31s} {times[1]:10.1f} {times[cores]:10.1f} "
                      f"{times[1] / times[cores]:5.2f}x")
    worst = min(rows, key=lambda r: r["ratio"])
    print(f"worst ratio one thread / {cores}: {worst['ratio']:.2f} ({worst['model']}, {worst['states']} states, "
          f"{worst['call']})")
    if args.json:
        write_text(args.json, json.dumps({"machine": machine(), "cores": cores, "rows": rows}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
