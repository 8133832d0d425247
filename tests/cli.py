"""Running relacc's command line as a user does (a subprocess), and what every command's failure looks like."""

import subprocess
import sys
from pathlib import Path


def run_relacc(*argv, cwd, timeout=300, env=None) -> subprocess.CompletedProcess:
    """``python -m relacc ARGV`` in ``cwd``, its output captured as text."""
    return subprocess.run([sys.executable, "-m", "relacc", *argv], capture_output=True, text=True, cwd=cwd,
                          timeout=timeout, env=env)


def one_line(out: subprocess.CompletedProcess, code: int = 2) -> str:
    """The one line a failed command prints on stderr (asserting the exit code, one line, no traceback)."""
    assert out.returncode == code, (out.returncode, out.stdout[-500:], out.stderr[-2000:])
    lines = [line for line in out.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in out.stderr, out.stderr
    return lines[0]


def formula_module(tmp_path, body: str, name: str = "formula") -> str:
    """A user's module ``name.py`` with ``body`` (numpy imported) and its ``MODULE:fn`` spec for ``relacc grade``."""
    path = tmp_path / f"{name}.py"
    path.write_text("import numpy as np\n" + body)
    return f"{path}:fn"


def borrowed_site_dirs() -> list[str]:
    """This environment's site directories: those on ``sys.path`` under ``sys.prefix`` (site-packages and the ones its
    own ``.pth`` files add, such as cmeel's prefix for Pinocchio), for a new environment that installs relacc alone
    and borrows its dependencies. The checkout's editable hook is not among them: ``.pth`` files are not read from a
    directory named on ``PYTHONPATH`` or in another ``.pth``."""
    return [p for p in sys.path if p.startswith(sys.prefix) and Path(p).is_dir()]
