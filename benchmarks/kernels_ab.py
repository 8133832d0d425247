"""The note's G2 kernels of this checkout against another checkout's, in one process, calls interleaved.

Timings taken in two processes on this project's VM drift by 10-30% with the hour; loading the other checkout's
``relacc/kernels/kinematics.py`` as a second module (its helpers are this checkout's ``perstate``) and alternating
the calls holds both to the same moment. One thread, outputs made once; nanoseconds a state, median and best of
``--repeats`` calls, every output (``kinematics``) and the acceleration alone (``acceleration``), each case.

Run:  python benchmarks/kernels_ab.py --old ../other/relacc/kernels/kinematics.py [--states 20000] [--json PATH]
"""

import argparse
import importlib.util
import json
import statistics
import sys
import time

import numpy as np

from relacc.files import write_text


def run(old_path: str, n: int, repeats: int) -> list[dict]:
    from relacc.core.states import random_states
    from relacc.fixtures import load
    from relacc.kernels import kinematics as new
    from relacc.kernels.jit import threads

    spec = importlib.util.spec_from_file_location("relacc_old_kinematics", old_path)
    old = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(old)
    chain = load().chain
    q2p, r2p = np.asarray(chain.q2, float), np.asarray(chain.r2, float)
    outs = (np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3, 12)), np.empty((n, 3, 12)))
    rows = []
    with threads(1):
        for case in (1, 2, 3):
            s = random_states(case, n, 0)
            calls = {(who, what): (lambda m=m, what=what: m.kinematics(case, s.q, s.u, s.udot, q2p, r2p, out=outs)
                                   if what == "every output" else
                                   m.acceleration(case, s.q, s.u, s.udot, q2p, r2p, out=outs[2]))
                     for who, m in (("old", old), ("new", new)) for what in ("every output", "acceleration")}
            times: dict = {k: [] for k in calls}
            for fn in calls.values():
                fn()
            for _ in range(repeats):
                for k, fn in calls.items():
                    start = time.perf_counter()
                    fn()
                    times[k].append((time.perf_counter() - start) / n * 1e9)
            rows += [{"case": case, "checkout": who, "what": what, "median_ns": statistics.median(t), "best_ns": min(t)}
                     for (who, what), t in times.items()]
    return rows


def main(argv=None) -> int:
    from relacc.tradeoff.throughput import machine

    parser = argparse.ArgumentParser(description="the note's G2 kernels against another checkout's, interleaved")
    parser.add_argument("--old", required=True, help="the other checkout's relacc/kernels/kinematics.py")
    parser.add_argument("--states", type=int, default=20000)
    parser.add_argument("--repeats", type=int, default=25)
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    args = parser.parse_args(argv)
    rows = run(args.old, args.states, args.repeats)
    for r in rows:
        print(f"  case {r['case']} {r['checkout']:3s} {r['what']:12s} {r['median_ns']:6.0f} ns ({r['best_ns']:.0f})")
    if args.json:
        write_text(args.json, json.dumps({"machine": machine(), "old": args.old, "states": args.states,
                                          "repeats": args.repeats, "rows": rows}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
