"""The first run on a clean clone: the README's main command, step by step, cold and warm.

Clones this repository's HEAD into a temporary directory (with ``../shared`` beside it, as CI has it), runs the
README's Quick-start main command there verbatim, one ``&&`` step at a time (so the install and the report are
timed apart), then the report again (warm: numba's cache is beside the clone's package), then ``relacc check``
on an empty numba cache and again on the filled one, and ``relacc compare`` of the shipped MJCF likewise (a
pre-commit hook's first run in a fresh environment: exit 1 is its verdict on Pinocchio's reading of that file, not a
failure). Every run writes into the temporary directory only.

Run:  python benchmarks/first_run.py [--json benchmarks/results/first-run-DATE-runN.json]

The budgets (2 cores; issue 52): the whole first command (venv, install and the cold report) at most 90 s, the
report at most 30 s warm; ``check`` at most 20 s cold and 10 s warm; ``compare`` of a model at most 2 s warm (the
humanoid's budget) and, cold, within 2 s of it.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from relacc.files import write_text
from relacc.tradeoff.throughput import cpu_model

ROOT = Path(__file__).resolve().parents[1]
BUDGET = {"first command": 90.0, "report warm": 30.0, "check cold": 20.0, "check warm": 10.0, "compare cold": 4.0,
          "compare warm": 2.0}
"""Seconds, from the issue."""


def main_command(readme: Path) -> str:
    """The first command of the README's Quick start (its code block's first line)."""
    block = re.search(r"## Quick start.*?```\n(.*?)```", readme.read_text(), re.S)
    if block is None:
        raise SystemExit(f"{readme}: no Quick start code block")
    return block.group(1).splitlines()[0].strip()


def timed(command: str, cwd: Path, env: dict, verdicts=(0,)) -> float:
    """Seconds of one shell command; its output is kept, and shown (the last 2,000 characters) if it exits with a
    code outside ``verdicts``."""
    start = time.perf_counter()
    done = subprocess.run(command, shell=True, cwd=cwd, env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode not in verdicts:
        raise SystemExit(f"{command!r} exited {done.returncode}:\n{done.stdout[-2000:]}\n{done.stderr[-2000:]}")
    return seconds


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="time the README's main command on a clean clone")
    parser.add_argument("--json", type=Path, help="write the timings here")
    args = parser.parse_args(argv)
    command = main_command(ROOT / "README.md")
    env = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "VIRTUAL_ENV", "PYTHON"))}
    env["PATH"] = os.pathsep.join(p for p in env.get("PATH", "").split(os.pathsep) if ".venv" not in p)
    with tempfile.TemporaryDirectory(prefix="relacc-first-run-") as tmp:
        clone = Path(tmp) / "relacc"
        subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
        commit = subprocess.run(["git", "-C", str(clone), "rev-parse", "--short", "HEAD"], check=True,
                                capture_output=True, text=True).stdout.strip()  # what ran, whatever imports this
        shared = ROOT.parent / "shared"
        if shared.exists():
            (Path(tmp) / "shared").symlink_to(shared)
        steps = [s.strip() for s in command.split("&&")]
        times = {}
        for step in steps:
            label = "install" if "pip install" in step else "report cold" if "relacc report" in step else "venv"
            times[label] = timed(step, clone, env)
        times["first command"] = sum(times.values())
        times["report warm"] = timed(steps[-1], clone, env)
        cache = Path(tmp) / "numba-cache"
        check = ".venv/bin/relacc check --quiet"
        times["check cold"] = timed(check, clone, {**env, "NUMBA_CACHE_DIR": str(cache)})
        times["check warm"] = timed(check, clone, {**env, "NUMBA_CACHE_DIR": str(cache)})
        compare = ".venv/bin/relacc compare models/two_body.xml --states 5 --quiet"
        fresh = {**env, "NUMBA_CACHE_DIR": str(Path(tmp) / "numba-cache-compare")}
        times["compare cold"] = timed(compare, clone, fresh, verdicts=(0, 1))
        times["compare warm"] = timed(compare, clone, fresh, verdicts=(0, 1))
    record = {"what": "the README's main command on a clean clone, step by step", "command": command,
              "date": time.strftime("%Y-%m-%d"), "cpu": cpu_model(), "logical_cpus": os.cpu_count(),
              "python": sys.version.split()[0], "relacc_commit": commit,
              "seconds": {k: round(v, 1) for k, v in times.items()}, "budget_seconds": BUDGET}
    for k, v in record["seconds"].items():
        budget = BUDGET.get(k)
        print(f"{k:12s} {v:7.1f} s" + (f"  (budget {budget:g} s: {'met' if v <= budget else 'missed'})"
                                       if budget else ""))
    if args.json:
        write_text(args.json, json.dumps(record, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
