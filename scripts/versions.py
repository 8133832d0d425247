"""relacc at the lowest versions it declares: a fresh virtual environment resolved with uv's ``lowest-direct``
(every direct dependency at the lowest version its bound allows that installs), then the test suite there.

    python scripts/versions.py [--venv DIR] [--mujoco X.Y.Z] [pytest arguments...]

``--mujoco`` replaces MuJoCo by another release inside the declared range (3.3.7: the URDF inertial rotation bug,
google-deepmind/mujoco#3559; 3.10.0: ``mj_fullM``'s new signature), to run the suite against a known engine bug.
Prints the versions installed, then pytest's summary; exits with pytest's code. Writes only the environment
(default: a new temporary directory, removed at the end unless --venv names one) and numba's cache of the run, in
that temporary directory: another numba over the same source tree would otherwise replace the working copy's
compiled kernels beside the package (the next run in the development venv then compiles cold).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHOWN = ("numpy", "pin", "mujoco", "drake", "pybullet", "idyntree", "numba", "llvmlite", "scipy", "matplotlib",
         "jinja2", "hypothesis", "pydantic", "dask", "pytest", "gymnasium")


def run(*argv, **kw) -> subprocess.CompletedProcess:
    print("$", " ".join(str(a) for a in argv), flush=True)
    return subprocess.run([str(a) for a in argv], check=kw.pop("check", True), **kw)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--venv", type=Path, help="the environment's directory (kept); default: a temporary one")
    parser.add_argument("--mujoco", help="a MuJoCo release to install over the lowest one")
    args, pytest_args = parser.parse_known_args()
    with tempfile.TemporaryDirectory(prefix="relacc-lowest-") as scratch:
        venv = args.venv or Path(scratch) / "venv"
        python = venv / "bin" / "python"
        if not python.exists():
            run(sys.executable, "-m", "venv", venv)
            run(python, "-m", "pip", "install", "-q", "uv")
        uv = venv / "bin" / "uv"
        run(uv, "pip", "install", "-q", "--python", python, "--resolution", "lowest-direct", "-e", f"{ROOT}[test]")
        if args.mujoco:
            run(uv, "pip", "install", "-q", "--python", python, f"mujoco=={args.mujoco}")
        listed = run(uv, "pip", "list", "--python", python, capture_output=True, text=True).stdout.splitlines()
        print("\n".join(line for line in listed if line.split(" ")[0].lower() in SHOWN), flush=True)
        tests = pytest_args or ["-n", "2", "-q", "-m", "not slow", "tests"]
        env = {**os.environ, "NUMBA_CACHE_DIR": str(Path(scratch) / "numba-cache")}  # not the working copy's cache
        return run(python, "-m", "pytest", *tests, check=False, cwd=ROOT, env=env).returncode


if __name__ == "__main__":
    sys.exit(main())
