"""The chain's compiled form against the general tree kernels on the chain's own tree (issue 37: the fused chain
kernels stay only if the general ones cannot match them).

The note's two-body chain is one tree (:func:`relacc.core.tree.model.chain_tree`: B1 free; B2 on three slides and a
ball). relacc integrates it two ways, the same RK4 (RKMK4 on the rotations in cases 1 and 2, RK4 on the angles in
case 3) from the same state under the same effects (gravity, the slides' spring and damper, the ball's damper):

* the chain's compiled form (:func:`relacc.dynamics.integrate.stepper`, :mod:`relacc.kernels.dynamics`: Newton-Euler
  block by block, fused for this shape), what ``relacc simulate`` runs for a chain scene;
* the general tree stepper (:func:`relacc.dynamics.integrate.tree_stepper_compiled`, :mod:`relacc.kernels.tree_step`:
  the tree's forward dynamics at every stage), what it runs for any model.

Microseconds per step of one trajectory (one thread: a single state), median and best of ``--repeats`` runs of
``--steps`` steps, and the largest difference of the two final states (they must agree to rounding).

Then the forward dynamics alone (issue 51: keep the fused kernels only if, re-measured against the lanes kernel on
the chain's tree, they are still clearly faster): microseconds a state over ``--batch`` seeded states and for one
state (a loop of calls), one thread, the chain's ``relacc.dynamics.accelerations`` against
``relacc.tree_accelerations`` on its tree, under gravity alone (the lanes kernel's path in every case) and under the
trajectory's effects (the ball's damper takes the tree's reference path in cases 1 and 3), with the largest
difference of the two answers; and the note's ``relacc.g2_kinematics`` of one state with its acceleration, and its
kernels over the batch (every output, and the acceleration alone) into outputs made once.

Run:  python benchmarks/chain_form.py [--steps 5000] [--repeats 5] [--json PATH]
"""

import argparse
import json
import statistics
import sys
import time

import numpy as np

from relacc.files import write_text


def _per_step(stepper, q, u, steps: int, repeats: int) -> tuple[dict, np.ndarray]:
    gaps = np.full(50, steps // 50, dtype=np.int64)
    runs, last = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        Q, U, _ = stepper.record(q, u, gaps)
        runs.append((time.perf_counter() - start) / steps * 1e6)
        last = np.concatenate([Q[-1], U[-1]])
    return {"median_us": statistics.median(runs), "best_us": min(runs)}, last


def run(steps: int, repeats: int) -> list[dict]:
    from relacc.core.states import random_states
    from relacc.core.tree.model import chain_tree
    from relacc.dynamics import Effects
    from relacc.dynamics.integrate import stepper, tree_stepper_compiled
    from relacc.dynamics.tree import tree_accelerations
    from relacc.fixtures import load
    from relacc.kernels.jit import threads

    chain = load().chain
    tree = chain_tree(chain)
    effects = Effects(gravity=(0, 0, -9.81), spring_stiffness=(10, 10, 10), spring_damping=(1, 1, 1),
                      ball_damping=0.1)
    tree_effects = effects.for_tree()
    out = []
    with threads(1):
        for case in (1, 2, 3):
            s = random_states(case, 1, 0)
            q, u = s.q[0], s.u[0]
            fused = stepper(chain, case, effects, 1e-3, "rk4")
            general = tree_stepper_compiled(tree, tree_effects, 1e-3, "rk4",
                                            lambda x, v, t: tree_accelerations(tree, case, x, v, effects=tree_effects,
                                                                               t=t), case)
            a, end_a = _per_step(fused, q, u, steps, repeats)
            b, end_b = _per_step(general, q, u, steps, repeats)
            out.append({"case": case, "chain_compiled": a, "tree_kernels": b,
                        "ratio_of_medians": b["median_us"] / a["median_us"],
                        "final_state_difference": float(np.max(np.abs(end_a - end_b)))})
    return out


def _us(fn, repeats: int, calls: int) -> float:
    runs = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            fn()
        runs.append((time.perf_counter() - start) / calls * 1e6)
    return statistics.median(runs)


def forward(batch: int, repeats: int) -> list[dict]:
    import relacc
    from relacc.core.states import random_states
    from relacc.core.tree.model import chain_tree
    from relacc.dynamics import Effects
    from relacc.dynamics.kane import accelerations
    from relacc.dynamics.tree import tree_accelerations
    from relacc.fixtures import load
    from relacc.kernels import kinematics as g2
    from relacc.kernels.jit import threads

    chain = load().chain
    tree = chain_tree(chain)
    out = []
    for label, effects in (("gravity", Effects(gravity=(0, 0, -9.81))),
                           ("gravity, springs and dampers",
                            Effects(gravity=(0, 0, -9.81), spring_stiffness=(10, 10, 10), spring_damping=(1, 1, 1),
                                    ball_damping=0.1))):
        te = effects.for_tree()
        with threads(1):
            for case in (1, 2, 3):
                s = random_states(case, batch, 0)
                q1, u1 = s.q[0].copy(), s.u[0].copy()
                a = accelerations(chain, case, s.q, s.u, effects)
                b = tree_accelerations(tree, case, s.q, s.u, effects=te)
                row = {"effects": label, "case": case, "difference": float(np.max(np.abs(a - b)))}
                if label == "gravity":  # the note's G2 kernels over the batch, into outputs made once
                    q2p, r2p = np.asarray(chain.q2, float), np.asarray(chain.r2, float)
                    outs = tuple(np.empty(shape) for shape in ((batch, 3),) * 3 + ((batch, 3, 12),) * 2)
                    row["note_g2_batch_us"] = _us(lambda: g2.kinematics(case, s.q, s.u, s.udot, q2p, r2p, out=outs),
                                                  repeats, 3) / batch
                    row["note_acceleration_batch_us"] = _us(
                        lambda: g2.acceleration(case, s.q, s.u, s.udot, q2p, r2p, out=outs[2]), repeats, 3) / batch
                for key, fn in (("chain_batch_us", lambda: accelerations(chain, case, s.q, s.u, effects)),
                                ("tree_batch_us", lambda: tree_accelerations(tree, case, s.q, s.u, effects=te))):
                    row[key] = _us(fn, repeats, 3) / batch
                d1 = s.udot[0].copy()
                for key, fn in (("chain_single_us", lambda: accelerations(chain, case, q1, u1, effects)),
                                ("note_g2_single_us", lambda: relacc.g2_kinematics(chain, case, q1, u1, d1)),
                                ("tree_single_us", lambda: tree_accelerations(tree, case, q1, u1, effects=te))):
                    fn()
                    row[key] = _us(fn, repeats, 200)
                out.append(row)
    return out


def main(argv=None) -> int:
    from relacc.tradeoff.throughput import machine

    parser = argparse.ArgumentParser(description="the chain's compiled form against the tree kernels on its tree")
    parser.add_argument("--steps", type=int, default=5000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--batch", type=int, default=4096)
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    args = parser.parse_args(argv)
    rows = run(args.steps, args.repeats)
    print("us per RK4 step, one trajectory, one thread: median (best)")
    for r in rows:
        a, b = r["chain_compiled"], r["tree_kernels"]
        print(f"  case {r['case']}: chain's compiled form {a['median_us']:6.2f} ({a['best_us']:.2f})   tree kernels "
              f"{b['median_us']:6.2f} ({b['best_us']:.2f})   x{r['ratio_of_medians']:.1f}   final states differ by "
              f"{r['final_state_difference']:.2g}")
    fd = forward(args.batch, args.repeats)
    print(f"forward dynamics, us a state, one thread: {args.batch} states (one state)")
    for r in fd:
        if "note_g2_batch_us" in r:
            print(f"  the note's G2, case {r['case']}: every output {r['note_g2_batch_us']:.3f}, the acceleration "
                  f"alone {r['note_acceleration_batch_us']:.3f}")
        print(f"  {r['effects']:28s} case {r['case']}: chain's kernel {r['chain_batch_us']:7.3f} "
              f"({r['chain_single_us']:7.2f})   tree {r['tree_batch_us']:7.3f} ({r['tree_single_us']:7.2f})   "
              f"differ by {r['difference']:.2g}   one state's G2 {r['note_g2_single_us']:.2f}")
    if args.json:
        write_text(args.json, json.dumps({"machine": machine(), "steps": args.steps, "repeats": args.repeats,
                                          "batch": args.batch, "rows": rows, "forward": fd}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
