"""Trees benchmark: relacc's tree kernels against Pinocchio's and MuJoCo's, on ant, humanoid and a 30-link chain,
and the cost against the number of bodies and speeds.

See :mod:`relacc.tradeoff.trees` for what is timed and how; recorded runs and their discussion are in
``docs/benchmarks.md``. Run it in a fresh process, on a quiet machine.

Run:  python benchmarks/trees.py [--states N] [--repeats R] [--json PATH] [--plot PATH]
"""

import argparse
import json
import sys

from relacc.files import write_text
from relacc.tradeoff.trees import print_table, run


def plot(result, path) -> None:
    """Cost per state against the number of bodies, hinge and ball chains, kinematics and dynamics."""
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from relacc.files import write_bytes

    fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
    rows = [r for r in result["rows"] if r["section"] == "scaling"]
    for joint, style in (("hinge chain", "-"), ("ball chain", "--")):
        for who, marker in (("relacc tree_kinematics out=", "o"), ("relacc tree_accelerations", "s")):
            pts = sorted((r["bodies"], r["value"]) for r in rows if r["model"] == joint and r["who"] == who)
            ax.plot(*zip(*pts), style, marker=marker, label=f"{who.split()[1]}, {joint}")
    ax.set_xlabel("bodies (after a free root: one hinge, or one ball, each)")
    ax.set_ylabel("microseconds per state")
    ax.set_title("relacc's tree kernels against the tree's size (2 threads)")
    ax.grid(alpha=0.3)
    ax.legend()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    write_bytes(path, buf.getvalue())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="relacc's tree kernels against the engines")
    parser.add_argument("--states", type=int, default=20_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    parser.add_argument("--plot", help="write the scaling figure to this PNG file")
    args = parser.parse_args(argv)
    result = run(n_states=args.states, repeats=args.repeats, seed=args.seed)
    print_table(result)
    if args.json:
        write_text(args.json, json.dumps(result, indent=2))
    if args.plot:
        plot(result, args.plot)
    return 0


if __name__ == "__main__":
    sys.exit(main())
