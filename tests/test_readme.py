"""The README runs: its Python example prints what it shows, its scene loads, its tables are the schemas."""

import contextlib
import io
import re
from pathlib import Path

from relacc.fixtures.schema import ChainFile, SceneFile, markdown_table
from relacc.simulate import scenes
from tests.trees import rk4_as_textbook

REPO = Path(__file__).resolve().parents[1]
README = (REPO / "README.md").read_text()
GUIDE = (REPO / "docs" / "guide.md").read_text()
"""The tour the README links: the scene example and the schema tables live there."""


def _blocks(lang: str, text: str = README):
    """``(code, the plain block right after it or None)`` for every fenced block of ``lang``."""
    pattern = re.compile(r"```" + lang + r"\n(.*?)```\n(?:\n```\n(.*?)```)?", re.S)
    return [(m.group(1), m.group(2)) for m in pattern.finditer(text)]


def test_python_examples_print_what_the_readme_shows():
    """Every ```python block followed by an output block prints exactly that output."""
    blocks = [(code, out) for code, out in _blocks("python") if out is not None]
    assert blocks, "no Python example with its output in the README"
    for code, expected in blocks:
        buffer = io.StringIO()
        with contextlib.redirect_stdout(buffer):
            exec(compile(code, "README.md", "exec"), {"__name__": "readme"})
        assert buffer.getvalue() == expected


@rk4_as_textbook()
def test_the_scene_in_the_readme_loads_and_runs(tmp_path):
    """The guide's scene TOML is a valid scene (unit quaternions included) and runs on every engine."""
    (toml,) = [code for code, _ in _blocks("toml", GUIDE)]
    path = tmp_path / "readme_scene.toml"
    path.write_text(toml)
    scene = scenes.load(path)
    from relacc import simulate

    pos, _, _ = simulate.run(scene.replace(duration=0.01)).differences()
    assert pos < 1e-9


def test_schema_tables_are_the_declared_schemas():
    """The guide's schema tables are exactly what relacc.fixtures.schema declares."""
    for name, schema in (("chain", ChainFile), ("scene", SceneFile)):
        m = re.search(rf"<!-- schema:{name} -->\n(.*?)\n<!-- /schema:{name} -->", GUIDE, re.S)
        assert m, name
        assert m.group(1) == markdown_table(schema), f"the guide's {name} table is stale: scripts/readme_tables.py"


def test_quick_start_has_two_commands_and_ci_runs_the_test_command():
    """The Quick start holds exactly two commands; .ci/run runs the second verbatim."""
    section = README.split("## Quick start", 1)[1].split("##", 1)[0]
    (block,) = re.findall(r"```\n(.*?)```", section, re.S)
    commands = [line for line in block.splitlines() if line.strip()]
    assert len(commands) == 2 and "relacc report" in commands[0] and "pytest" in commands[1]
    assert commands[1] in (REPO / ".ci" / "run").read_text()


def test_every_test_the_guarantees_name_exists():
    """Each test named in docs/guarantees.md exists in the suite (a promise without a test is not listed)."""
    text = (REPO / "docs" / "guarantees.md").read_text()
    named = set(re.findall(r"`tests/(test_\w+\.py)(?:::(\w+))?`", text))
    named |= {(None, t) for t in re.findall(r"`(test_\w+)`", text)}
    suite = {p.name: p.read_text() for p in (REPO / "tests").glob("test_*.py")}
    for module, test in named:
        if module:
            assert module in suite, module
        if test:
            where = [suite[module]] if module else suite.values()
            assert any(f"def {test}(" in src for src in where), test


def test_the_benchmarks_table_is_the_latest_recorded_runs():
    """docs/benchmarks.md's table is what scripts/benchmarks_table.py writes from the recorded results (JSON files it
    reads, no benchmark run here): one row per benchmark, its latest run (the latest date, then the highest run
    number), with machine, date and commit."""
    import runpy

    script = runpy.run_path(str(REPO / "scripts" / "benchmarks_table.py"))
    text = (REPO / "docs" / "benchmarks.md").read_text()
    m = re.search(r"<!-- latest-runs -->\n(.*?)\n<!-- /latest-runs -->", text, re.S)
    assert m and m.group(1) == script["table"](), "docs/benchmarks.md's table is stale: scripts/benchmarks_table.py"
    rows = m.group(1).splitlines()[2:]
    assert len(rows) == len(script["BENCHMARKS"]) >= 10
    # the latest run is the latest date, then the highest run number (run23 after run9, which sorts after it)
    runs = [(p.name[6:16], int(p.stem.rsplit("run", 1)[1])) for p in (REPO / "benchmarks" / "results").glob("trees-*")]
    chosen = script["latest"]("trees")
    assert (chosen.name[6:16], int(chosen.stem.rsplit("run", 1)[1])) == max(runs)
