"""Forward dynamics on every gymnasium MuJoCo model: relacc's ``tree_accelerations`` against ``pin.abaInParallel``.

Issue 35's floor: relacc's forward dynamics never below 1x Pinocchio's on any gymnasium model. For each model file
of gymnasium's MuJoCo assets that relacc and Pinocchio both read: ``--states`` random case-2 states of relacc's tree
(:func:`relacc.core.tree.random_states`), relacc's compiled kernel (the algorithm its plan picks) against
``pin.abaInParallel`` on a ``pin.ModelPool`` of Pinocchio's model of the same file, the states mapped to Pinocchio's
coordinates and laid out column-major before timing; one thread each (the same threads: issue 35), microseconds per
state, median and best of ``--repeats``, and the largest difference of the two accelerations in Pinocchio's speeds
(relative to their largest entry). That difference is not an error of either: it is large exactly where Pinocchio's
reading of the file is another model (bodies it leaves out, ``settotalmass`` ignored, geoms left out of the masses:
``relacc compare`` names each), and then the two times are not of the same work; ``pinocchio_nv`` and
``shared_speeds`` say so.

Run:  python benchmarks/gym_models.py [--states 20000] [--repeats 7] [--json PATH]
"""

import argparse
import json
import sys
from importlib.util import find_spec
from pathlib import Path

import numpy as np

from relacc.files import write_text


def one_model(path: Path, n: int, repeats: int) -> dict:
    import pinocchio as pin

    import relacc
    from relacc.core.tree import random_states
    from relacc.engines import load
    from relacc.kernels.jit import threads
    from relacc.kernels.tree_dynamics import method
    from relacc.tradeoff.throughput import wall_times

    tree = relacc.Tree.from_file(path)
    engine = load("pinocchio", path, tree)
    s = random_states(tree, 2, n, 0)
    x = engine.to_engine(s.q, s.u)
    qe, ve = np.asfortranarray(x.q.T), np.asfortranarray(x.v.T)
    tau, a_pin = np.zeros_like(ve), np.zeros_like(ve)
    pool = pin.ModelPool(engine.model, 1)
    with threads(1):
        mine = wall_times(lambda: relacc.tree_accelerations(tree, 2, s.q, s.u), repeats)  # (median, best) s
        a_mine = np.asarray(relacc.tree_accelerations(tree, 2, s.q, s.u))
    theirs = wall_times(lambda: pin.abaInParallel(1, pool, qe, ve, tau, a_pin), repeats)
    mapped = engine.to_engine(s.q, s.u, a_mine).a  # relacc's accelerations in Pinocchio's speeds
    difference = float(np.max(np.abs(mapped - a_pin.T)) / max(np.max(np.abs(a_pin)), 1e-300))
    r = {"model": path.name, "nv": tree.nv, "bodies": tree.nb, "method": method(tree),
         "pinocchio_nv": int(engine.model.nv), "shared_speeds": len(engine.dofs),
         "relacc_us": {"median": mine[0] / n * 1e6, "best": mine[1] / n * 1e6},
         "abaInParallel_us": {"median": theirs[0] / n * 1e6, "best": theirs[1] / n * 1e6},
         "relative_difference": difference}
    r["ratio_of_medians"] = r["abaInParallel_us"]["median"] / r["relacc_us"]["median"]
    return r


def main(argv=None) -> int:
    from relacc.errors import RelaccError
    from relacc.tradeoff.throughput import machine

    parser = argparse.ArgumentParser(description="forward dynamics on every gymnasium model against abaInParallel")
    parser.add_argument("--states", type=int, default=20_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    args = parser.parse_args(argv)
    assets = Path(find_spec("gymnasium").origin).parent / "envs" / "mujoco" / "assets"
    rows, skipped = [], {}
    for path in sorted(assets.glob("*.xml")):
        try:
            rows.append(one_model(path, args.states, args.repeats))
        except RelaccError as exc:  # a file relacc or Pinocchio does not read: said, not hidden
            skipped[path.name] = str(exc)
    print("one thread, us per state: median (best); ratio of medians; largest relative difference")
    for r in rows:
        print(f"  {r['model']:28s} nv {r['nv']:3d} {r['method']}  relacc {r['relacc_us']['median']:6.2f} "
              f"({r['relacc_us']['best']:.2f})  abaInParallel {r['abaInParallel_us']['median']:6.2f} "
              f"({r['abaInParallel_us']['best']:.2f})  x{r['ratio_of_medians']:.2f}  {r['relative_difference']:.1e}"
              + ("" if r["pinocchio_nv"] == r["nv"] == r["shared_speeds"] and r["relative_difference"] < 1e-6 else
                 f"  (Pinocchio reads another model: nv {r['pinocchio_nv']}, {r['shared_speeds']} shared speeds)"))
    for name, why in skipped.items():
        print(f"  {name}: not compared: {why}")
    if args.json:
        write_text(args.json, json.dumps({"machine": machine(), "states": args.states, "repeats": args.repeats,
                                          "rows": rows, "skipped": skipped}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
