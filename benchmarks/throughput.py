"""Throughput benchmark: relacc's batched kernels against looping Pinocchio and MuJoCo.

See :mod:`relacc.tradeoff.throughput` for what is timed and how. Results of recorded
runs are in ``docs/benchmarks.md``.

Run:  python benchmarks/throughput.py [--states N] [--repeats R] [--json PATH]
"""

import argparse
import json
import sys
from pathlib import Path

from relacc.tradeoff.throughput import print_table, run


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="relacc throughput against engine loops")
    parser.add_argument("--states", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=15)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", help="also write the results to this JSON file")
    args = parser.parse_args(argv)
    result = run(args.states, args.repeats, args.seed)
    print_table(result)
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
