"""``relacc compare`` over other people's robot descriptions, from their pip wheels: docs/compare.md's corpus table.

The three packages are pinned (:data:`PINS`). Their wheels are fetched with ``pip download --no-deps`` (none of
their dependencies is needed: relacc reads the description files, never imports the packages) and only the folders
holding descriptions and their meshes are unpacked, into a cache directory. Each file is compared in its own
process (``python -m relacc compare FILE --states 5 --json``) from an empty temporary directory, which must stay
empty. One row per file: its exit code, the engines that took part, the audit's and the dynamics' differences, how
many have no reproduced cause, and for exit 2 the one line it printed. tests/test_corpus.py checks that every row of
docs/compare.md is what relacc gives now.

Run:  python scripts/corpus.py [--cache DIR] [--jobs 2] [--write] [--json rows.json]
"""

from __future__ import annotations

import argparse
import contextlib
import fcntl
import json
import os
import subprocess
import sys
import tempfile
import zipfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from relacc.files import write_text

DOC = Path(__file__).resolve().parents[1] / "docs" / "compare.md"
STATES = 5
PINS = {"example-robot-data": "6.0.0", "robosuite": "1.5.2", "gymnasium-robotics": "1.4.2"}
"""The packages and versions the table is of."""
FOLDERS = {  # package: (wheel folder holding its descriptions and their meshes, patterns of the descriptions)
    "example-robot-data": ("cmeel.prefix/share/example-robot-data/robots/", ("**/*.urdf",)),
    "robosuite": ("robosuite/models/assets/", ("robots/**/*.xml", "grippers/**/*.xml", "bases/**/*.xml")),
    "gymnasium-robotics": ("gymnasium_robotics/envs/assets/", ("**/*.xml",)),
}
BEGIN, END = "<!-- corpus -->", "<!-- /corpus -->"
HEADER = ("| package | file | exit | compared | audit | dynamics | not explained | what it printed |\n"
          "|---|---|---|---|---|---|---|---|")


def default_cache() -> Path:
    return Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "relacc-corpus"


@contextlib.contextmanager
def _locked(cache: Path):
    """One fetch at a time (pytest-xdist's workers share the cache)."""
    cache.mkdir(parents=True, exist_ok=True)
    with open(cache / ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def fetch(cache: Path) -> dict[str, Path]:
    """``{package: folder}``: each pinned wheel's description folder, unpacked under ``cache`` (downloaded once)."""
    roots = {}
    with _locked(cache):
        for package, version in PINS.items():
            folder, _ = FOLDERS[package]
            target = cache / f"{package}-{version}"
            if not target.is_dir():
                wheels = cache / "wheels"
                subprocess.run([sys.executable, "-m", "pip", "download", "-q", "--no-deps", "--only-binary=:all:",
                                f"{package}=={version}", "-d", str(wheels)], check=True, capture_output=True)
                wheel = next(wheels.glob(f"{package.replace('-', '_')}-{version}-*.whl"))
                partial = Path(tempfile.mkdtemp(dir=cache, prefix=".partial-"))
                with zipfile.ZipFile(wheel) as z:
                    z.extractall(partial, [m for m in z.namelist() if m.startswith(folder)])
                partial.rename(target)  # whole or not at all
                wheel.unlink()
            roots[package] = target / folder
    return roots


def files(package: str, root: Path) -> list[tuple[str, Path]]:
    """``(shown name, path)`` of a package's descriptions: the name relative to its folder, sorted."""
    _, patterns = FOLDERS[package]
    found = sorted({p for pattern in patterns for p in root.glob(pattern) if p.is_file()})
    return [(p.relative_to(root).as_posix(), p) for p in found]


def summarize(code: int, stdout: str, stderr: str, root: Path) -> dict:
    """The row of one run, from its exit code and output (the package's folder written as ``...``)."""
    from relacc.cli.progress import COMPILE_LABEL

    # numba's first compilation in a process shows a bar (a line rewritten after each \r): a word about this
    # machine, not about the file
    lines = [line for line in stderr.split("\n") if not line.split("\r")[-1].startswith(COMPILE_LABEL)]
    if lines and lines[-1] == "":  # the newline ending the last line (splitlines would split at \r too)
        lines.pop()
    stderr = "\n".join(lines)
    row = {"exit": code, "stderr_lines": len(lines), "traceback": "Traceback" in stderr}
    if code == 2 or not stdout.strip():
        row["message"] = " ".join(stderr.split()).replace(str(root) + "/", ".../")
        return row
    data = json.loads(stdout)
    bad = [r for q in data["dynamics"].values() for r in q["engines"].values() if not r["ok"]]
    row.update(compared=data["compared"], audit=len(data["audit"]), dynamics=len(bad),
               unexplained=sum(r["cause_kind"] == "not explained" for r in bad)
               + sum("not explained" in a["cause_kind"] for a in data["audit"]),
               absent=sorted(k for k, e in data["engines"].items() if not e["loaded"]),
               findings=len(data["findings"]))
    return row


def run(path: Path, root: Path, states: int = STATES) -> dict:
    """``relacc compare`` on one file in its own process, from an empty directory (checked empty after)."""
    with tempfile.TemporaryDirectory(prefix="relacc-corpus-") as work:
        done = subprocess.run([sys.executable, "-m", "relacc", "compare", str(path), "--states", str(states),
                               "--json"], capture_output=True, text=True, cwd=work, timeout=900)
        left = sorted(p.name for p in Path(work).iterdir())
    return {**summarize(done.returncode, done.stdout, done.stderr, root), "left_in_cwd": left}


def line(package: str, shown: str, row: dict) -> str:
    """One Markdown row of the table."""
    if "message" in row:
        what = row["message"].replace("|", "\\|")
        return f"| {package} | `{shown}` | {row['exit']} | - | - | - | - | {what} |"
    said = [f"findings: {row['findings']}"] if row.get("findings") else []
    said += [f"not taking part: {', '.join(row['absent'])}"] if row["absent"] else []
    return (f"| {package} | `{shown}` | {row['exit']} | {', '.join(row['compared'])} | {row['audit']} | "
            f"{row['dynamics']} | {row['unexplained']} | {'; '.join(said)} |")


def shown_rows(text: str) -> dict[tuple[str, str], str]:
    """``{(package, shown name): row}`` of the table in docs/compare.md's text."""
    block = text.split(BEGIN, 1)[1].split(END, 1)[0]
    rows = {}
    for row in block.strip().splitlines()[2:]:
        cells = [c.strip() for c in row.strip("|").split("|")]
        rows[(cells[0], cells[1].strip("`"))] = row
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cache", type=Path, default=default_cache(), help="where the wheels are unpacked")
    parser.add_argument("--jobs", type=int, default=2, help="files compared at once")
    parser.add_argument("--write", action="store_true", help="rewrite docs/compare.md's table")
    parser.add_argument("--json", type=Path, help="also write every row to this JSON file")
    args = parser.parse_args(argv)
    roots = fetch(args.cache.resolve())  # each file runs in a temporary directory: paths must be absolute
    todo = [(package, shown, path) for package, root in roots.items() for shown, path in files(package, root)]
    with ThreadPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(lambda t: run(t[2], roots[t[0]]), todo))
    lines = [line(package, shown, r) for (package, shown, _), r in zip(todo, rows)]
    print(HEADER + "\n" + "\n".join(lines))
    if args.write:
        text = DOC.read_text()
        head, rest = text.split(BEGIN, 1)
        write_text(DOC, head + BEGIN + "\n" + HEADER + "\n" + "\n".join(lines) + "\n" + END + rest.split(END, 1)[1])
    if args.json:
        write_text(args.json, json.dumps([{"package": p, "file": s, **r} for (p, s, _), r in zip(todo, rows)],
                                         indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
