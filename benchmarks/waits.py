"""Where a user waits: ``relacc compare`` on gymnasium's models as a command, and each engine's run of the shipped
chain scenes, warm (numba's and the lanes' caches filled by a first run that is not counted).

* ``compare``: ``relacc compare FILE --json`` as a user types it, in a fresh process each time, from an empty
  temporary directory (engine imports included, as a user waits for them); ``--repeats`` runs, median and best.
* ``simulate``: :func:`relacc.simulate.run` of each shipped chain scene on one engine at a time (its own stepper under
  exactly the scene's effects, the records observed; no cross-check), in this process after one short warm-up run;
  the best of ``--repeats``. MuJoCo applies the scene's effects in its own model; Pinocchio and Drake take them from
  relacc's effect forces at every stage of every step, so their times include that Python callback.

Run:  python benchmarks/waits.py [--repeats 3] [--json benchmarks/results/waits-DATE-runN.json]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from relacc.files import write_text
from relacc.tradeoff.throughput import cpu_model, source_commit

MODELS = ("humanoid.xml", "ant.xml")
"""gymnasium's MuJoCo assets compared (the issue's target: the humanoid at most 2 s)."""


def _gymnasium_asset(name: str) -> Path:
    import gymnasium

    return Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / name


def compare_times(repeats: int, also: list[Path] = ()) -> list[dict]:
    """Seconds of ``relacc compare PATH --json`` per model (and per ``also``: a file, or a directory whose files are
    compared in one process, its per-file time given too), each run a fresh process in an empty directory."""
    relacc = str(Path(sys.executable).with_name("relacc"))
    rows = []
    for name, path in [(f"gymnasium {m}", _gymnasium_asset(m)) for m in MODELS] + [(str(p), p) for p in also]:
        times, code = [], None
        with tempfile.TemporaryDirectory(prefix="relacc-waits-") as tmp:
            subprocess.run([relacc, "compare", str(path), "--json"], cwd=tmp, capture_output=True)  # warm-up
            for _ in range(repeats):
                start = time.perf_counter()
                done = subprocess.run([relacc, "compare", str(path), "--json"], cwd=tmp, capture_output=True)
                times.append(time.perf_counter() - start)
                code = done.returncode
            left = os.listdir(tmp)
        row = {"model": name, "exit": code, "median_s": round(statistics.median(times), 2),
               "best_s": round(min(times), 2), "left_in_directory": left}
        if path.is_dir():
            files = len(json.loads(done.stdout))
            row.update(files=files, median_s_per_file=round(statistics.median(times) / files, 2))
        rows.append(row)
    return rows


def simulate_times(repeats: int) -> list[dict]:
    """Seconds of each engine's run of each shipped chain scene (best of ``repeats``)."""
    from relacc import simulate
    from relacc.fixtures import shipped
    from relacc.simulate import scenes

    rows = []
    for path in shipped.scene_paths("chain"):
        scene = scenes.load(path)
        for engine in scene.engines:
            simulate.run(scene.replace(duration=10 * scene.dt), engines=(engine,), check=False)  # warm-up
            best = float("inf")
            for _ in range(repeats):
                start = time.perf_counter()
                simulate.run(scene, engines=(engine,), check=False)
                best = min(best, time.perf_counter() - start)
            rows.append({"scene": scene.name, "engine": engine, "steps": scene.n_steps, "best_s": round(best, 3)})
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description="time where a user waits: compare, and each engine's scene runs")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", type=Path, help="write the record here")
    parser.add_argument("--also", type=Path, action="append", default=[],
                        help="a model file or a directory of them to time too (repeatable), e.g. gymnasium-robotics' "
                             "Shadow hand from scripts/corpus.py's cache")
    args = parser.parse_args(argv)
    record = {"what": "where a user waits: relacc compare as a command, each engine's run of the chain scenes",
              "date": time.strftime("%Y-%m-%d"), "cpu": cpu_model(), "logical_cpus": os.cpu_count(),
              "python": sys.version.split()[0], "relacc_commit": source_commit(),
              "compare": compare_times(args.repeats, args.also), "simulate": simulate_times(args.repeats)}
    for r in record["compare"]:
        per = f"  ({r['files']} files, {r['median_s_per_file']:.2f} s a file)" if "files" in r else ""
        print(f"compare {r['model']:24s} median {r['median_s']:6.2f} s  best {r['best_s']:6.2f} s  exit {r['exit']}"
              + per)
    for r in record["simulate"]:
        print(f"simulate {r['scene']:16s} {r['engine']:10s} {r['steps']:6d} steps  {r['best_s']:7.3f} s")
    if args.json:
        write_text(args.json, json.dumps(record, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
