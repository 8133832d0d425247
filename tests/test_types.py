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
    planted.write_text("def f(x: int) -> str:\n    return x\n\n\ndef g():\n    y = [1]\n    return y.no_such\n")
    out, _, status = api.run(["--config-file", str(ROOT / "pyproject.toml"), "--cache-dir", str(tmp_path / "c"),
                              str(planted)])
    assert status == 1 and "Incompatible return value type" in out
    assert '"list[int]" has no attribute "no_such"' in out  # an unannotated body is checked too (check_untyped_defs)


def test_the_public_api_is_annotated():
    """Every function a package of relacc hands on (its ``__all__``), and every public method of the classes it hands
    on, has its parameters and return annotated, so the type checker checks it and a user's editor can show it."""
    import importlib
    import inspect

    packages = ("relacc", "relacc.testing", "relacc.engines", "relacc.core.tree", "relacc.dynamics", "relacc.simulate",
                "relacc.reading", "relacc.validation.robots", "relacc.fixtures", "relacc.tradeoff", "relacc.cluster",
                "relacc.report")
    missing = []
    for module in map(importlib.import_module, packages):
        for name in module.__all__:
            obj = getattr(module, name)
            obj = inspect.unwrap(obj)  # a context manager's generator function
            functions = [(name, obj)] if inspect.isfunction(obj) else [
                (f"{name}.{k}", v) for k, v in vars(obj).items()
                if inspect.isfunction(v) and not k.startswith("_")] if inspect.isclass(obj) else []
            for label, f in functions:
                sig = inspect.signature(f)
                bare = [p.name for p in sig.parameters.values() if p.name not in ("self", "cls")
                        and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD) and p.annotation is inspect.Parameter.empty]
                if bare or sig.return_annotation is inspect.Signature.empty:
                    missing.append(f"{module.__name__}.{label}: {bare or 'return'}")
    assert missing == []
