"""One state at a time: a single forward-dynamics call, and one trajectory of a scene, on gymnasium's ant and humanoid.

* **One call.** ``relacc.tree_accelerations(tree, 2, q, u)`` with ``q (nq,)``, ``u (nv,)`` against ``pin.aba`` on
  Pinocchio's model of the same file (what a user calls for one state), microseconds per call: the first call in the
  process (numba's cache already on disk: ``benchmarks/first_run.py`` measures compilation) and the median and best
  of ``--repeats`` timings of ``--calls`` calls, relacc's and Pinocchio's repeats interleaved (this VM's speed drifts
  by up to 2x over seconds), and pin.aba's median over relacc's.
* **One trajectory.** The shipped ``ant_tumbling`` scene and a humanoid scene built here (springs and dampers on every
  hinge, a damper on the free root, a sinusoidal force on the torso and a constant one on a hand; no gravity; RK4 at
  1 ms, 1 s, a record every 10 steps): relacc's compiled stepper (:func:`relacc.simulate.subjects.tree_stepper`,
  what ``relacc simulate`` runs) against ``mujoco.rollout`` with one member and one thread (MuJoCo's own step loop
  in C, its RK4, the scene's effects in its model), both the integration alone, seconds per run (first run, then
  median and best of ``--repeats``); and relacc's Python stepper of before (RKMK4 in numpy calling
  ``tree_accelerations`` at every stage, still the path of cases 1 and 3) on the first 0.1 s, scaled to the run.

Run it in a fresh process, on a quiet machine.

Run:  python benchmarks/single.py [--calls 20000] [--repeats 5] [--json PATH]
"""

import argparse
import json
import statistics
import sys
import time
from importlib.util import find_spec
from pathlib import Path

import numpy as np

from relacc.files import write_text

MODELS = ("ant", "humanoid")


def _assets() -> Path:
    return Path(find_spec("gymnasium").origin).parent / "envs" / "mujoco" / "assets"


def one_call(name: str, calls: int, repeats: int) -> dict:
    import pinocchio as pin

    import relacc
    from relacc.core.tree import reference_q
    from relacc.engines import load
    from relacc.kernels.tree_dynamics import optimize

    path = _assets() / f"{name}.xml"
    tree = relacc.Tree.from_file(path)
    optimize(tree, 2)  # the steady state: the lanes' -O2 code (the same bits as the first, -O0)
    q = reference_q(tree, 2)
    u = np.random.default_rng(0).standard_normal(tree.nv)
    robot = load("pinocchio", path, tree=tree)
    states_e = robot.to_engine(q[None], u[None])
    qe, ve = states_e.q, states_e.v
    model, data = robot.model, robot.model.createData()
    qp, vp, tau = np.ascontiguousarray(qe[0]), np.ascontiguousarray(ve[0]), np.zeros(model.nv)
    ours, theirs = _paired(lambda: relacc.tree_accelerations(tree, 2, q, u), lambda: pin.aba(model, data, qp, vp, tau),
                           calls, repeats)
    return {"model": name, "nv": tree.nv, "relacc": ours, "pinocchio_aba": theirs,
            "ratio": theirs["median_us"] / ours["median_us"]}


def _paired(fa, fb, calls: int, repeats: int) -> tuple[dict, dict]:
    """us per call of two calls: each one's first call, then the median and best of ``repeats`` timings of ``calls``
    calls, the repeats interleaved (a, b, a, b, ...): this VM's speed drifts by up to 2x over seconds, and
    interleaving puts both under the same drift."""
    first = []
    for fn in (fa, fb):
        start = time.perf_counter()
        fn()
        first.append((time.perf_counter() - start) * 1e6)
    runs: tuple[list, list] = ([], [])
    for _ in range(repeats):
        for fn, out in zip((fa, fb), runs):
            start = time.perf_counter()
            for _ in range(calls):
                fn()
            out.append((time.perf_counter() - start) / calls * 1e6)
    return tuple({"first_us": f, "median_us": statistics.median(r), "best_us": min(r)}  # type: ignore[return-value]
                 for f, r in zip(first, runs))


def humanoid_scene():
    """gymnasium's humanoid tumbling on springs: every hinge a spring (2 N m/rad) and a damper (0.05 N m s/rad), the
    free root a damper (0.02), a force of 5 N along y at 2 Hz on the torso and 1 N along z on the left forearm."""
    from relacc.dynamics.tree_effects import BodyLoad, JointEffect, TreeEffects
    from relacc.simulate.scenes import model_scene

    base = model_scene(_assets() / "humanoid.xml", seed=1, duration=1.0, dt=1e-3, engines=("relacc", "mujoco"))
    joints = {j.name: JointEffect(stiffness=2.0, damping=0.05) for _, j in base.tree.joints if j.type == "hinge"}
    joints.update({j.name: JointEffect(damping=0.02) for _, j in base.tree.joints if j.type == "free"})
    bodies = {"torso": BodyLoad(force=(0.0, 5.0, 0.0), frequency=2.0),
              "left_lower_arm": BodyLoad(force=(0.0, 0.0, 1.0))}
    return base.replace(name="humanoid_springs", effects=TreeEffects(gravity=np.zeros(3), joints=joints,
                                                                     bodies=bodies), record_every=10)


def one_trajectory(scene, repeats: int) -> dict:
    from relacc.dynamics.integrate import TreeSpace, space_stepper
    from relacc.dynamics.steps import collect
    from relacc.dynamics.tree import tree_accelerations
    from relacc.kernels.jit import threads
    from relacc.simulate.ensemble import ensemble
    from relacc.simulate.subjects import tree_stepper

    def relacc_run():
        stepper = tree_stepper(scene.tree, 2, scene.effects, scene.dt, "rk4")
        start = time.perf_counter()
        _, X, _ = collect(stepper, scene.q, scene.u, scene.dt, scene.n_steps, scene.record_every, who="relacc",
                          integrator="rk4")
        return time.perf_counter() - start, X[-1]

    def mujoco_run():
        e = ensemble(scene, scene.q[None], scene.u[None], engine="mujoco", threads=1)
        return e.seconds, e.q[0, -1]

    with threads(1):
        rel = [relacc_run() for _ in range(1 + repeats)]
    mj = [mujoco_run() for _ in range(1 + repeats)]

    def derivs(q, u, t):
        return u, np.asarray(tree_accelerations(scene.tree, 2, q, u, effects=scene.effects, t=t))

    before = space_stepper(TreeSpace(scene.tree, 2), derivs, scene.dt, "rk4")
    k = max(1, scene.n_steps // 10)
    start = time.perf_counter()
    with threads(1):
        before.advance(scene.q, scene.u, k)
    python = (time.perf_counter() - start) * scene.n_steps / k
    out = {"scene": scene.name, "steps": scene.n_steps, "dt": scene.dt}
    for key, runs in (("relacc", rel), ("mujoco_rollout", mj)):
        secs = [s for s, _ in runs]
        out[key] = {"first_s": secs[0], "median_s": statistics.median(secs[1:]), "best_s": min(secs[1:])}
    out["python_stepper_s"] = python
    out["final_q_difference"] = float(np.abs(rel[0][1] - mj[0][1]).max())
    out["ratio_to_mujoco"] = out["mujoco_rollout"]["median_s"] / out["relacc"]["median_s"]
    out["ratio_to_python_stepper"] = python / out["relacc"]["median_s"]
    return out


def main(argv=None) -> int:
    from relacc.fixtures.shipped import scenes_dir
    from relacc.simulate.scenes import load
    from relacc.tradeoff.throughput import machine

    parser = argparse.ArgumentParser(description="one state at a time: a call, a trajectory")
    parser.add_argument("--calls", type=int, default=20000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    args = parser.parse_args(argv)
    calls = [one_call(name, args.calls, args.repeats) for name in MODELS]
    print("one call (us): first, median, best")
    for r in calls:
        print(f"  {r['model']:9s} relacc {r['relacc']['first_us']:9.1f} {r['relacc']['median_us']:7.2f} "
              f"{r['relacc']['best_us']:7.2f}   pin.aba {r['pinocchio_aba']['median_us']:7.2f} "
              f"{r['pinocchio_aba']['best_us']:7.2f}   pin.aba's median over relacc's {r['ratio']:.2f}")
    runs = [one_trajectory(load(scenes_dir() / "ant_tumbling.toml"), args.repeats),
            one_trajectory(humanoid_scene(), args.repeats)]
    print("one trajectory (s): first, median, best; ratios of medians")
    for r in runs:
        print(f"  {r['scene']:17s} relacc {r['relacc']['first_s']:.4f} {r['relacc']['median_s']:.4f} "
              f"{r['relacc']['best_s']:.4f}  mujoco.rollout {r['mujoco_rollout']['median_s']:.4f} "
              f"{r['mujoco_rollout']['best_s']:.4f}  python stepper {r['python_stepper_s']:.3f}  "
              f"x{r['ratio_to_mujoco']:.2f} MuJoCo, x{r['ratio_to_python_stepper']:.0f} before; "
              f"final q differ by {r['final_q_difference']:.2g}")
    if args.json:
        write_text(args.json, json.dumps({"machine": machine(), "calls": args.calls, "repeats": args.repeats,
                                          "one_call": calls, "one_trajectory": runs}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
