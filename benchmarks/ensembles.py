"""Ensembles of a scene on a model: relacc's tree against ``mujoco.rollout`` and Pinocchio, the same members.

The shipped ``ant_tumbling`` scene (gymnasium's ant: springs and dampers on its hips, springs on its ankles, a
sinusoidal torque on its torso; RK4, dt 1 ms) from ``--members`` initial states (the scene's, speeds perturbed by
``numpy.random.default_rng(seed)``), through :func:`relacc.simulate.ensemble.ensemble` on each engine with
``--threads`` threads:

* relacc: RKMK4 on the tree's manifold over every member at once, each stage's forward dynamics by the compiled
  tree kernel with the effects' generalized forces applied (:func:`relacc.tree_accelerations`);
* MuJoCo: ``mujoco.rollout`` (its own threads, one ``MjData`` each), the scene's effects in its model;
* Pinocchio: RKMK4 with every stage's accelerations from ``pin.abaInParallel``.

Timed: the integration alone (``Ensemble.seconds``), member-steps per second. ``first`` is the first call in this
process (numba's cache already on disk: ``benchmarks/first_run.py`` measures compilation), then the median and the
best of ``--repeats`` more. Run it in a fresh process, on a quiet machine.

Run:  python benchmarks/ensembles.py [--members 1000] [--duration 0.1] [--threads 2] [--repeats 5] [--json PATH]
"""

import argparse
import json
import statistics
import sys

import numpy as np

from relacc.files import write_text
from relacc.fixtures.shipped import scenes_dir
from relacc.simulate.ensemble import ensemble
from relacc.simulate.scenes import load
from relacc.tradeoff.throughput import machine

ENGINES = ("relacc", "mujoco", "pinocchio")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="ensembles of the ant scene: relacc, mujoco.rollout, Pinocchio")
    parser.add_argument("--members", type=int, default=1000)
    parser.add_argument("--duration", type=float, default=0.1, help="s of the scene (dt 1 ms)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    args = parser.parse_args(argv)
    scene = load(scenes_dir() / "ant_tumbling.toml").replace(duration=args.duration)
    rng = np.random.default_rng(args.seed)
    q0 = np.repeat(scene.q[None], args.members, axis=0)
    u0 = scene.u[None] + 0.1 * rng.standard_normal((args.members, scene.u.size))
    rows = []
    for engine in ENGINES:
        runs = [ensemble(scene, q0, u0, engine=engine, threads=args.threads) for _ in range(1 + args.repeats)]
        rate = [r.steps_per_second for r in runs]
        rows.append({"engine": engine, "threads": runs[0].threads, "member_steps": runs[0].steps,
                     "first_steps_per_s": rate[0], "median_steps_per_s": statistics.median(rate[1:]),
                     "best_steps_per_s": max(rate[1:])})
    mj = next(r for r in rows if r["engine"] == "mujoco")
    print(f"ant_tumbling, {args.members} members x {scene.n_steps} steps, {args.threads} threads: "
          "member-steps per second (first call; median, best of the rest); ratio to mujoco.rollout's median")
    for r in rows:
        print(f"{r['engine']:10s} {r['first_steps_per_s']:10.4g}  {r['median_steps_per_s']:10.4g} "
              f"{r['best_steps_per_s']:10.4g}  {r['median_steps_per_s'] / mj['median_steps_per_s']:5.2f}x")
    if args.json:
        result = {"machine": machine(), "scene": "ant_tumbling", "members": args.members,
                  "steps": scene.n_steps, "threads": args.threads, "repeats": args.repeats, "seed": args.seed,
                  "rows": rows}
        write_text(args.json, json.dumps(result, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
