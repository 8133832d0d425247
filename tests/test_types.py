"""The type checker CI runs (issue 37 #3): mypy over the package, in the mode ``pyproject.toml``'s ``[tool.mypy]``
states (every annotated function checked; numba's dispatchers and pydrake's stubs excepted where they cannot
describe relacc's calls). Its cache goes to a temporary directory, never the repository."""

from pathlib import Path

import pytest
from mypy import api

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_mypy_passes(tmp_path):
    out, err, status = api.run(["--config-file", str(ROOT / "pyproject.toml"), "--cache-dir", str(tmp_path),
                                "--no-error-summary", str(ROOT / "relacc")])
    errors = [line for line in out.splitlines() if ": error:" in line]
    assert status == 0 and errors == [], "\n".join(errors[:40]) + err


@pytest.mark.slow
def test_mypy_catches_a_planted_error(tmp_path):
    """The check can fail: a planted wrong type in an annotated function is an error."""
    planted = tmp_path / "planted.py"
    planted.write_text("def f(x: int) -> str:\n    return x\n")
    out, _, status = api.run(["--config-file", str(ROOT / "pyproject.toml"), "--cache-dir", str(tmp_path / "c"),
                              str(planted)])
    assert status == 1 and "Incompatible return value type" in out
