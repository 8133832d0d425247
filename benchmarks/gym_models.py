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
``shared_speeds`` say so. For a tree of hinges and slides (no free or ball joint), Pinocchio is also timed on a model
built from relacc's reading through Pinocchio's own API (:func:`same_model`: the same bodies, joints, anchors, masses,
armature and gravity; axis-aligned joint kinds where Pinocchio's parsers choose them), after checking that its
accelerations are relacc's to ``SAME_MODEL`` (relative): there the two times are of the same robot even where
Pinocchio's reading of the file is another one, and that ratio is the one the floor is judged on (``ratio_same_model``).

Run:  python benchmarks/gym_models.py [--states 20000] [--repeats 7] [--json PATH]
"""

import argparse
import json
import sys
from importlib.util import find_spec
from pathlib import Path

import numpy as np

from relacc.files import write_text

SAME_MODEL = 1e-10
"""Largest relative difference of the accelerations on the built model: eps x the condition of the mass matrix
(reacher's 1.6e-13 is the largest seen on gymnasium's models), far below any reading difference (1e-7 and more)."""


def _joint_model(hinge: bool, axis):
    """Pinocchio's joint for a hinge (slide) about (along) ``axis``: the axis-aligned kind its own parsers choose for a
    coordinate axis (``RX`` ... ``PZ``, fewer operations), else the unaligned one."""
    import pinocchio as pin

    for k, e in enumerate(np.eye(3)):
        if np.array_equal(axis, e):
            return getattr(pin, f"JointModel{'R' if hinge else 'P'}{'XYZ'[k]}")()
    return (pin.JointModelRevoluteUnaligned if hinge else pin.JointModelPrismaticUnaligned)(np.asarray(axis))


def same_model(tree):
    """Pinocchio's ``Model`` of relacc's tree, built joint by joint (hinges and slides only; ``None`` otherwise).

    A body's joints are applied in order, each hinge about its anchor (``Joint.pos``) in the body frame as moved by
    the joints before it, as MuJoCo and relacc do; a body with several joints gets one ``JointModelComposite``, as
    Pinocchio's own MJCF parser builds it (one body in its recursions, not one per joint). Pinocchio's coordinate is
    relacc's minus the joint's ``ref``.
    """
    import pinocchio as pin

    if any(j.type not in ("hinge", "slide") for _, j in tree.joints):
        return None
    model = pin.Model()
    model.gravity.linear = np.asarray(tree.gravity, dtype=float)
    frames = {-1: (0, pin.SE3.Identity())}  # body: (Pinocchio joint it rides on, its frame in that joint's)
    armature = []
    for i, body in enumerate(tree.bodies):
        joint, frame = frames[body.parent]
        w, x, y, z = body.quat
        frame = frame * pin.SE3(pin.Quaternion(w, x, y, z).toRotationMatrix(), np.asarray(body.pos))
        if body.joints:
            parts, before = [], np.zeros(3)  # (joint model, placement after the one before)
            for j in body.joints:
                anchor = np.asarray(j.pos) if j.type == "hinge" else np.zeros(3)
                parts.append((_joint_model(j.type == "hinge", j.axis), pin.SE3(np.eye(3), anchor - before)))
                before = anchor
                armature.extend(j.armature)
            if len(parts) == 1:
                kind, placement = parts[0][0], frame * parts[0][1]
            else:  # each part placed after the one before; the first in the composite's frame
                kind, placement = pin.JointModelComposite(), frame
                for part, after in parts:
                    kind.addJoint(part, after)
            joint = model.addJoint(joint, kind, placement, body.joints[0].name)
            frame = pin.SE3(np.eye(3), -before)
        model.appendBodyToJoint(joint, pin.Inertia(body.mass, np.asarray(body.com), np.asarray(body.inertia)), frame)
        frames[i] = (joint, frame)
    model.armature = np.asarray(armature)
    return model


def _time_pinocchio(model, q, v, repeats: int):
    """(median, best) seconds of ``pin.abaInParallel`` on one thread over states ``q (n, nq)``, ``v (n, nv)``, in
    Pinocchio's coordinates, and its accelerations ``(n, nv)``."""
    import pinocchio as pin

    from relacc.tradeoff.throughput import wall_times

    qe, ve = np.asfortranarray(q.T), np.asfortranarray(v.T)
    tau, a = np.zeros_like(ve), np.zeros_like(ve)
    pool = pin.ModelPool(model, 1)
    times = wall_times(lambda: pin.abaInParallel(1, pool, qe, ve, tau, a), repeats)
    return times, a.T


def one_model(path: Path, n: int, repeats: int) -> dict:
    import relacc
    from relacc.core.tree import random_states
    from relacc.engines import load
    from relacc.kernels.jit import threads
    from relacc.kernels.tree_dynamics import algorithm_used, optimize
    from relacc.tradeoff.throughput import wall_times

    tree = relacc.Tree.from_file(path)
    engine = load("pinocchio", path, tree)
    s = random_states(tree, 2, n, 0)
    x = engine.to_engine(s.q, s.u)
    optimize(tree, 2)  # the steady state: the lanes' -O2 code (the same bits as the first, -O0)
    with threads(1):
        mine = wall_times(lambda: relacc.tree_accelerations(tree, 2, s.q, s.u), repeats)  # (median, best) s
        a_mine = np.asarray(relacc.tree_accelerations(tree, 2, s.q, s.u))
    theirs, a_pin = _time_pinocchio(engine.model, x.q, x.v, repeats)
    mapped = engine.to_engine(s.q, s.u, a_mine).a  # relacc's accelerations in Pinocchio's speeds
    difference = float(np.max(np.abs(mapped - a_pin)) / max(np.max(np.abs(a_pin)), 1e-300))
    r = {"model": path.name, "nv": tree.nv, "bodies": tree.nb, "method": algorithm_used(tree, 2),
         "pinocchio_nv": int(engine.model.nv), "shared_speeds": len(engine.dofs),
         "relacc_us": {"median": mine[0] / n * 1e6, "best": mine[1] / n * 1e6},
         "abaInParallel_us": {"median": theirs[0] / n * 1e6, "best": theirs[1] / n * 1e6},
         "relative_difference": difference}
    r["ratio_of_medians"] = r["abaInParallel_us"]["median"] / r["relacc_us"]["median"]
    built = same_model(tree)
    if built is not None:
        ref = np.array([j.ref for _, j in tree.joints])  # one speed a joint: hinges and slides
        same, a_same = _time_pinocchio(built, s.q - ref, s.u, repeats)
        gap = float(np.max(np.abs(a_same - a_mine)) / max(np.max(np.abs(a_mine)), 1e-300))
        if not gap <= SAME_MODEL:
            raise AssertionError(f"{path.name}: Pinocchio's model built from relacc's reading differs by {gap:.1e}")
        r["same_model"] = {"abaInParallel_us": {"median": same[0] / n * 1e6, "best": same[1] / n * 1e6},
                           "relative_difference": gap}
        r["ratio_same_model"] = r["same_model"]["abaInParallel_us"]["median"] / r["relacc_us"]["median"]
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
        print(f"  {r['model']:28s} nv {r['nv']:3d} {r['method']:5s}  relacc {r['relacc_us']['median']:6.2f} "
              f"({r['relacc_us']['best']:.2f})  abaInParallel {r['abaInParallel_us']['median']:6.2f} "
              f"({r['abaInParallel_us']['best']:.2f})  x{r['ratio_of_medians']:.2f}  {r['relative_difference']:.1e}"
              + ("" if r["pinocchio_nv"] == r["nv"] == r["shared_speeds"] and r["relative_difference"] < 1e-6 else
                 f"  (Pinocchio reads another model: nv {r['pinocchio_nv']}, {r['shared_speeds']} shared speeds)")
              + (f"\n  {'':28s} on the model built from relacc's reading: abaInParallel "
                 f"{r['same_model']['abaInParallel_us']['median']:6.2f}  x{r['ratio_same_model']:.2f}  "
                 f"{r['same_model']['relative_difference']:.1e}" if "same_model" in r else ""))
    for name, why in skipped.items():
        print(f"  {name}: not compared: {why}")
    if args.json:
        write_text(args.json, json.dumps({"machine": machine(), "states": args.states, "repeats": args.repeats,
                                          "rows": rows, "skipped": skipped}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
