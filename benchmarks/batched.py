"""Dynamics and simulation benchmark: relacc against Pinocchio's and MuJoCo's batched APIs.

See :mod:`relacc.tradeoff.batched` for what is timed and how; recorded runs and their discussion
are in ``docs/benchmarks.md``. Run it in a fresh process: its first-call figure needs memory the
process has not touched.

Run:  python benchmarks/batched.py [--states N] [--steps N] [--members N] [--duration S]
                                   [--repeats R] [--json PATH]
"""

import argparse
import sys

from relacc.files import write_text
from relacc.fixtures import load
from relacc.tradeoff.batched import print_table, run, tumbling


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="relacc's dynamics and simulation against the engines' batched APIs")
    parser.add_argument("--states", type=int, default=100_000, help="states per forward-dynamics batch")
    parser.add_argument("--steps", type=int, default=2000, help="steps of the one-scene timing")
    parser.add_argument("--members", type=int, default=1000, help="ensemble members")
    parser.add_argument("--duration", type=float, default=0.5, help="ensemble duration, s (tumbling: dt 1e-3)")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    args = parser.parse_args(argv)
    result = run(load(), tumbling(args.duration), n_states=args.states, n_steps=args.steps, members=args.members,
                 repeats=args.repeats, seed=args.seed)
    print_table(result)
    if args.json:
        import json

        write_text(args.json, json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
