"""The test command's time: the fast tier in one process (``pytest -m "not slow" -n 0``) and, with ``--all``, the
README's test command (``pytest -n 2``), each in a fresh process from this checkout, warm (numba's and the lanes'
caches as the checkout has them: run once before to time the warm suite, or on a clean clone to time CI's cold one).

Wall seconds and pytest's counts, with the machine, date and commit (issue 52: the fast tier at most 45 s in one
process, the test command at most 5 min on a clean clone).

Run:  python benchmarks/tiers.py [--all] [--json benchmarks/results/tiers-DATE-runN.json]
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from pathlib import Path

from relacc.files import write_text
from relacc.tradeoff.throughput import machine

ROOT = Path(__file__).resolve().parents[1]
TIERS = {"fast, one process": ["-m", "not slow", "-n", "0"], "all, two workers": ["-n", "2"]}


def run(name: str) -> dict:
    start = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "pytest", "-q", *TIERS[name]], cwd=ROOT,
                         capture_output=True, text=True)
    seconds = time.perf_counter() - start
    last = out.stdout.strip().splitlines()[-1] if out.stdout.strip() else ""
    counts = {k: int(v) for v, k in re.findall(r"(\d+) (passed|failed|errors?|skipped|xfailed|deselected)", last)}
    return {"tier": name, "seconds": round(seconds, 1), "exit": out.returncode, "counts": counts, "summary": last}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="the test command's time")
    parser.add_argument("--all", action="store_true", help="also the whole suite on two workers")
    parser.add_argument("--json", help="also write the results to this JSON file (atomically)")
    args = parser.parse_args(argv)
    rows = [run(name) for name in TIERS if args.all or name.startswith("fast")]
    for r in rows:
        print(f"  {r['tier']:18s} {r['seconds']:7.1f} s  {r['summary']}")
    if args.json:
        write_text(args.json, json.dumps({"machine": machine(), "rows": rows}, indent=2) + "\n")
    return 0 if all(r["exit"] == 0 for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
