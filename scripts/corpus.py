"""Run ``relacc compare`` over other people's robot descriptions, from their pip packages, and print one row per
file: its exit code, the engines that took part, how many audit and dynamics differences, how many without a known
cause, and what stderr held (docs/compare.md's "Real robot descriptions" sections were read off this).

Each file runs in its own process (``python -m relacc compare FILE --states N --json``) from an empty temporary
directory, which is checked empty afterwards. Not run by the tests: the three wheels are 131, 157 and 26 MB and the
150 files take about 15 minutes on 2 cores.

Run:  pip install --no-deps example-robot-data robosuite gymnasium-robotics
      python scripts/corpus.py [--states 5] [--json corpus.json]
"""

import argparse
import importlib.util
import json
import subprocess
import sys
import tempfile
from pathlib import Path

PACKAGES = {  # package: (module whose location is found, folders under it, patterns)
    "example-robot-data": ("cmeel", None, ("*.urdf",)),
    "robosuite": ("robosuite", ("models/assets/robots", "models/assets/grippers", "models/assets/bases"), ("*.xml",)),
    "gymnasium-robotics": ("gymnasium_robotics", ("envs/assets",), ("*.xml",)),
}


def files(package: str) -> list[Path]:
    """The description files of an installed package (empty when it is not installed)."""
    module, folders, patterns = PACKAGES[package]
    spec = importlib.util.find_spec(module)
    if spec is None or not spec.submodule_search_locations:
        return []
    root = Path(list(spec.submodule_search_locations)[0])
    if package == "example-robot-data":  # cmeel installs it under site-packages/cmeel.prefix
        roots = [root.parent / "cmeel.prefix" / "share" / "example-robot-data" / "robots"]
    else:
        roots = [root / f for f in folders]
    return sorted(p for r in roots if r.is_dir() for pattern in patterns for p in r.rglob(pattern))


def row(path: Path, states: int) -> dict:
    with tempfile.TemporaryDirectory(prefix="relacc-corpus-") as work:
        run = subprocess.run([sys.executable, "-m", "relacc", "compare", str(path), "--states", str(states), "--json"],
                             capture_output=True, text=True, cwd=work, timeout=900)
        left = sorted(p.name for p in Path(work).iterdir())
    out = {"file": str(path), "exit": run.returncode, "stderr_lines": len(run.stderr.splitlines()),
           "left_in_cwd": left}
    if run.returncode == 2 or not run.stdout.strip():
        return {**out, "message": run.stderr.strip()[-400:]}
    data = json.loads(run.stdout)
    bad = [r for q in data["dynamics"].values() for r in q["engines"].values() if not r["ok"]]
    unexplained = sum("not explained" in r["cause"] for r in bad) + sum("not explained" in a["cause"]
                                                                          for a in data["audit"])
    return {**out, "compared": data["compared"], "audit": len(data["audit"]), "dynamics": len(bad),
            "unexplained": unexplained,
            "not_taking_part": {k: e["error"] for k, e in data["engines"].items() if not e["loaded"]}}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--states", type=int, default=5)
    parser.add_argument("--json", help="also write every row to this JSON file")
    parser.add_argument("--package", action="append", choices=sorted(PACKAGES), help="only these (repeatable)")
    args = parser.parse_args(argv)
    rows = []
    print("| package | file | exit | compared | audit | dynamics | not explained | stderr lines |")
    print("|---|---|---|---|---|---|---|---|")
    for package in args.package or list(PACKAGES):
        found = files(package)
        if not found:
            print(f"| {package} | not installed | | | | | | |")
        for path in found:
            r = {**row(path, args.states), "package": package}
            rows.append(r)
            print(f"| {package} | {path.parent.name}/{path.name} | {r['exit']} | "
                  f"{', '.join(r.get('compared', [])) or '-'} | "
                  f"{r.get('audit', '-')} | {r.get('dynamics', '-')} | {r.get('unexplained', '-')} | "
                  f"{r['stderr_lines']} |", flush=True)
    if args.json:
        from relacc.files import write_text

        write_text(args.json, json.dumps(rows, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
