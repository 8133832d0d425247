"""The first compilation of each command: the seconds numba takes for each of relacc's kernels on a cold cache.

Runs each command below in a fresh process with an empty ``NUMBA_CACHE_DIR`` (so that every kernel it needs is
compiled), from a temporary directory, and records for each of relacc's kernels (``module.qualname``) the seconds
of its own compilation: from numba's compile event's start to its end, less the relacc kernels compiled inside it
(numba's own helpers compiled inside count with the kernel that needed them), and, for each outermost kernel (a
root: what a command calls), the kernels compiled under it. The command line's compile bar
(:func:`relacc.cli.progress.compile_bar`) reads the latest record's roots, shipped in the wheel as
``relacc.recorded``, for its estimate of the compilation under way, scaled by the pace of the run it is in.

Run:  python benchmarks/first_compile.py [--json benchmarks/results/compile-seconds-DATE-runN.json]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from relacc.files import write_text
from relacc.tradeoff.throughput import cpu_model

ROOT = Path(__file__).resolve().parents[1]
MODEL = str(ROOT / "models" / "two_body.xml")
COMMANDS = {
    "check": ["check", "--states", "20", "--quiet"],
    "check --model": ["check", "--model", MODEL, "--states", "20", "--quiet"],
    "errata": ["errata", "--states", "20", "--quiet"],
    "simulate": ["simulate", "tumbling", "--duration", "0.05", "--quiet", "--out", "{tmp}/sim"],
    "simulate --model": ["simulate", "--model", MODEL, "--duration", "0.05", "--quiet", "--out", "{tmp}/simm"],
    "tradeoff": ["tradeoff", "--quick", "--quiet"],
    "tradeoff --model": ["tradeoff", "--model", MODEL, "--quick", "--quiet"],
    "report": ["report", "--quick", "--quiet", "--out", "{tmp}/r.html"],
    "report --model": ["report", "--model", MODEL, "--quick", "--quiet", "--out", "{tmp}/rm.html"],
    "compare": ["compare", MODEL, "--states", "5", "--quiet"],
}
"""The commands that compile kernels (``eval`` and ``fixtures`` compile none): between them, every root."""

LISTENER = r"""
import json, sys, time
from numba.core import event
own, stack, roots, under = {}, [], {}, {}
class Timed(event.Listener):
    def on_start(self, ev):
        stack.append([time.perf_counter(), 0.0])
    def on_end(self, ev):
        start, inner = stack.pop()
        fn = ev.data["dispatcher"].py_func
        name = f"{fn.__module__}.{fn.__qualname__}"
        took = time.perf_counter() - start
        if name.startswith("relacc."):
            own[name] = own.get(name, 0.0) + took - inner
            under[name] = own[name]
            if stack:
                stack[-1][1] += took
            else:
                roots[name] = dict(under)
                under.clear()
event.register("numba:compile", Timed())
from relacc.cli.main import main
code = main(sys.argv[1:])
print(json.dumps({"exit": code, "kernels": own, "roots": roots}), file=sys.__stderr__)
"""


def first_compile(argv: list[str], tmp: str) -> dict:
    """The kernels ``relacc ARGV`` compiles on a cold cache, with the seconds of each, and the command's wall time."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(Path(tmp) / "numba-cache")}
    start = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", LISTENER, *[a.format(tmp=tmp) for a in argv]], cwd=tmp, env=env,
                         capture_output=True, text=True, timeout=1800)
    wall = time.perf_counter() - start
    record = json.loads(out.stderr.strip().splitlines()[-1])
    kernels = {k: round(v, 3) for k, v in sorted(record["kernels"].items())}
    roots = {r: {k: round(v, 3) for k, v in sorted(under.items())} for r, under in record["roots"].items()}
    shown = [str(Path(a).relative_to(ROOT)) if a == MODEL else a for a in argv]  # no local path in the record
    return {"argv": shown, "exit": record["exit"], "wall_seconds": round(wall, 1),
            "seconds": round(sum(kernels.values()), 1), "kernels": kernels, "roots": roots}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="time each command's first compilation on a cold numba cache")
    parser.add_argument("--json", type=Path, help="write the record here")
    args = parser.parse_args(argv)
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], check=True,
                            capture_output=True, text=True).stdout.strip()
    commands = {}
    for key, command in COMMANDS.items():
        with tempfile.TemporaryDirectory(prefix="relacc-first-compile-") as tmp:
            commands[key] = first_compile(command, tmp)
        row = commands[key]
        print(f"{key:18s} {row['seconds']:6.1f} s compiling, {len(row['kernels']):3d} kernels, "
              f"{row['wall_seconds']:6.1f} s in all (exit {row['exit']})", flush=True)
    roots: dict = {}  # each outermost kernel's fullest record (another command may have compiled part of it first)
    for row in commands.values():
        for root, under in row.pop("roots").items():
            if sum(under.values()) > sum(roots.get(root, {}).values()):
                roots[root] = under
    record = {"what": "each command's first compilation on a cold numba cache, seconds per relacc kernel; for each "
                      "outermost kernel (roots), the seconds of each kernel compiled under it",
              "date": time.strftime("%Y-%m-%d"), "cpu": cpu_model(), "logical_cpus": os.cpu_count(),
              "python": sys.version.split()[0], "relacc_commit": commit, "commands": commands, "roots": roots}
    if args.json:
        write_text(args.json, json.dumps(record, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
