"""The house rules, checked: tolerances that say both parts, package rules, true docs, no trace in the user's
directory."""

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

from relacc.cli.parser import build_parser, subcommands

ROOT = Path(__file__).resolve().parents[1]
CLOSE = {"allclose", "isclose", "assert_allclose"}


def _calls(source: str):
    """``(call node, the called function's name)`` of every call in ``source``."""
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call):
            yield node, node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")


def loose_tolerances(source: str, name: str = "<source>") -> list[str]:
    """``file:line`` of every ``allclose``/``isclose``/``assert_allclose`` call without ``rtol=`` (numpy's default
    hides a relative 1e-5 or 1e-7) and every ``approx`` call with neither ``abs=`` nor ``rel=`` (pytest's default is a
    relative 1e-6)."""
    bad = []
    for node, func in _calls(source):
        keys = {k.arg for k in node.keywords}
        if (func in CLOSE and "rtol" not in keys) or (func == "approx" and not keys & {"abs", "rel"}):
            bad.append(f"{name}:{node.lineno}")
    return bad


def test_every_tolerance_states_both_parts():
    bad = [b for path in sorted((ROOT / "tests").glob("*.py")) for b in loose_tolerances(path.read_text(), path.name)]
    assert bad == []


HEAVY = re.compile(r"\bsubprocess\.|\bPopen\b|sync_playwright|\bchromium\b|LocalCluster|benchmarks/")
"""What makes a test slow by rule: a subprocess, a browser, a Dask cluster, a benchmark script."""


def unmarked_heavy_tests(source: str, name: str = "<source>") -> list[str]:
    """``file::test`` of every test function that (itself, or a module-level helper it calls by name) starts a
    subprocess, a browser, a cluster or a benchmark, without ``@pytest.mark.slow`` (or a module-wide ``pytestmark``
    saying so): the fast tier (``pytest -m "not slow"``) runs in-process only."""
    tree = ast.parse(source)
    if any(isinstance(n, ast.Assign) and any(getattr(t, "id", "") == "pytestmark" for t in n.targets)
           and "mark.slow" in ast.unparse(n) for n in tree.body):
        return []
    helpers = {n.name: ast.get_source_segment(source, n) for n in tree.body
               if isinstance(n, ast.FunctionDef) and not n.name.startswith("test_")}

    def heavy(n) -> bool:
        called = {c.func.id for c in ast.walk(n) if isinstance(c, ast.Call) and isinstance(c.func, ast.Name)}
        return bool(HEAVY.search(ast.get_source_segment(source, n) + "".join(helpers.get(c, "") for c in called)))

    # a module's fixture that starts one (a cluster's scheduler and workers) makes every test taking it heavy
    fixtures = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)
                and any("fixture" in ast.unparse(d) for d in n.decorator_list) and heavy(n)}
    bad = []
    for n in tree.body:
        if not (isinstance(n, ast.FunctionDef) and n.name.startswith("test_")):
            continue
        takes = {a.arg for a in n.args.args} & fixtures
        if (heavy(n) or takes) and not any("mark.slow" in ast.unparse(d) for d in n.decorator_list):
            bad.append(f"{name}::{n.name}")
    return bad


@pytest.mark.slow
def test_the_slow_marker_follows_its_rule():
    """Every test that starts a subprocess, a browser, a cluster or a benchmark is marked slow (issue 37)."""
    bad = [b for path in sorted((ROOT / "tests").glob("test_*.py"))
           for b in unmarked_heavy_tests(path.read_text(), path.name)]
    assert bad == []
    call = "sub" + "process.run(['x'])"  # split: this test's own source starts no subprocess
    planted = f"import subprocess\ndef run():\n    {call}\ndef test_a():\n    run()\n"
    assert unmarked_heavy_tests(planted) == ["<source>::test_a"]
    assert unmarked_heavy_tests("import pytest\n@pytest.mark.slow\n" + planted.split("\n", 3)[3].replace(
        "def test_a", "def test_b")) == []
    by_fixture = (f"import pytest, subprocess\n@pytest.fixture\ndef server():\n    {call}\n"
                  "def test_c(server):\n    pass\n")
    assert unmarked_heavy_tests(by_fixture) == ["<source>::test_c"]


def unexplained_tolerances(source: str, name: str = "<source>") -> list[str]:
    """``file:line`` of every ``allclose``/``isclose``/``assert_allclose`` whose ``atol``/``rtol`` is a bare number
    (a float in (0, 1)) with neither a name from :mod:`relacc.core.tolerances` (an upper-case constant) in it nor a
    comment beside it (the call's lines or the two above): each tolerance comes from the error model or says why."""
    lines, bad = source.splitlines(), []
    for node, func in _calls(source):
        if func not in CLOSE:
            continue
        for kw in node.keywords:
            if kw.arg not in ("atol", "rtol"):
                continue
            numbers = [c for c in ast.walk(kw.value) if isinstance(c, ast.Constant) and isinstance(c.value, float)
                       and 0 < c.value < 1]
            named = any(n.id.isupper() for n in ast.walk(kw.value) if isinstance(n, ast.Name))
            near = lines[max(0, node.lineno - 3):node.end_lineno]
            if numbers and not named and not any("#" in line for line in near):
                bad.append(f"{name}:{node.lineno}")
    return bad


def test_every_tolerance_comes_from_the_error_model_or_says_why():
    bad = [b for path in sorted((ROOT / "tests").glob("*.py"))
           for b in unexplained_tolerances(path.read_text(), path.name)]
    assert bad == []


def test_the_tolerance_lint_catches_a_planted_one():
    assert loose_tolerances("import numpy as np\nassert np.allclose(a, b, atol=1e-14)\n") == ["<source>:2"]
    assert loose_tolerances("x == pytest.approx(1.0)\n") == ["<source>:1"]
    assert loose_tolerances("np.testing.assert_allclose(a, b, rtol=0, atol=1e-14)\n") == []
    assert unexplained_tolerances("np.testing.assert_allclose(a, b, rtol=0, atol=1e-14)\n") == ["<source>:1"]
    assert unexplained_tolerances("np.testing.assert_allclose(a, b, rtol=0, atol=64 * EPS)\n") == []
    assert unexplained_tolerances("# two roundings\nnp.testing.assert_allclose(a, b, rtol=0, atol=1e-15)\n") == []


def test_every_package_docstring_states_the_rule_the_layout_test_enforces():
    """Each package's "Layer rule:" paragraph names every layer tests/test_layout.py lets it import (the CLI may
    import anything and says so): the documented rule and the enforced one are the same rule."""
    from tests.test_layout import BASE, LAYERS

    missing = {}
    for init in sorted((ROOT / "relacc").glob("*/__init__.py")):
        doc = ast.get_docstring(ast.parse(init.read_text())) or ""
        rule = re.search(r"Layer rule:(.*?)(?:\n\n|$)", doc, re.S)
        if rule is None:
            missing[init.parent.name] = "no 'Layer rule:' paragraph"
            continue
        if init.parent.name == "cli":
            assert "anything" in rule.group(1)
            continue
        absent = [n for n in sorted(LAYERS[init.parent.name] - BASE) if not re.search(rf"\b{n}", rule.group(1))]
        if absent:
            missing[init.parent.name] = absent
    assert missing == {}


def test_every_subcommand_is_in_the_readme_command_table():
    readme = (ROOT / "README.md").read_text()
    table = readme[readme.index("## Commands"):]
    table = table[:table.index("\n\n", table.index("| command |"))]
    missing = [name for name in subcommands(build_parser()) if f"`relacc {name}" not in table]
    assert missing == []


def test_every_doc_is_linked_from_the_readme():
    readme = (ROOT / "README.md").read_text()
    missing = [p.name for p in sorted((ROOT / "docs").glob("*.md")) if f"docs/{p.name}" not in readme]
    assert missing == []


COMMANDS = [
    ["eval", "--case", "1", "--q", "0,0,0,1,0,0,0,0,0,0,1,0,0,0", "--u", "0,0,0,0,0,0,0,0,0,0,0,0"],
    ["check", "--states", "20", "--quiet"],
    ["errata", "--states", "20"],
    ["simulate", "tumbling", "--duration", "0.02"],
    ["fixtures", "--check"],
    ["compare", "MODELS/two_body.xml", "--states", "2"],
    ["compare", "MODELS/two_body_euler.urdf", "--states", "2"],
    ["check", "--model", "MODELS/two_body.xml", "--states", "2", "--quiet"],
    ["grade", "ROOT/examples/student_correct.py:velocity", "--quantity", "velocity", "--case", "1", "--states", "5"],
]
"""Every command but the report, which tests/test_report.py's ``quick_report`` runs from an empty directory."""


@pytest.mark.slow
@pytest.mark.parametrize("argv", COMMANDS, ids=lambda a: " ".join(a[:2]))
def test_every_command_leaves_the_working_directory_empty(tmp_path, argv):
    """Run from an empty directory, every command writes only where it is told (MuJoCo's log included)."""
    work, elsewhere = tmp_path / "work", tmp_path / "elsewhere"
    work.mkdir()
    elsewhere.mkdir()
    argv = [a.replace("MODELS", str(ROOT / "models")).replace("ROOT", str(ROOT)).replace("ELSEWHERE", str(elsewhere))
            for a in argv]
    out = subprocess.run([sys.executable, "-m", "relacc", *argv], capture_output=True, text=True, cwd=work,
                         timeout=600)
    assert out.returncode in (0, 1, 2), out.stderr[-2000:]
    if out.returncode == 2:  # refused: one line, never a traceback
        assert len(out.stderr.strip().splitlines()) == 1, out.stderr[-2000:]
    assert list(work.iterdir()) == []


def test_every_package_reaches_the_wheel():
    """pyproject.toml lists its packages by hand (relacc.models lives outside relacc/): every package is there."""
    import tomllib

    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = {".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "relacc").rglob("__init__.py")}
    assert found - listed == set()
