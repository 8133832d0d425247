"""Every name README.md and docs/*.md give in code spans exists (issue 51): each dotted ``relacc.`` name imports and
resolves, each repository path (``relacc/...``, ``tests/...``, ``scripts/...``, ...) is a file or directory, each
``relacc COMMAND`` is a subcommand and each ``--flag`` after it one of that subcommand's options. A name that no longer
exists (a renamed class, a moved module, a dropped flag) fails here, with the document that names it.

This replaces ``tests/test_readme.py::test_every_name_the_readme_and_docs_give_exists``, which looked only at spans
that begin with a name, skipped brace patterns and never checked a flag."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import pytest

from relacc.cli.parser import build_parser, subcommands

ROOT = Path(__file__).resolve().parent.parent
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SPANS = [(doc.relative_to(ROOT), span) for doc in DOCUMENTS for span in re.findall(r"`([^`\n]+)`", doc.read_text())]
TOP = ("relacc", "tests", "scripts", "benchmarks", "examples", "models", "docs")


def _resolves(name: str) -> bool:
    parts = name.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for attribute in parts[i:]:
            if not hasattr(obj, attribute):
                return False
            obj = getattr(obj, attribute)
        return True
    return False


def test_the_documents_name_things_at_all():
    """The checks below can fail: the documents do name modules, paths and commands (counted here), and a planted
    wrong name is caught by each check."""
    dotted = [d for _, s in SPANS for d in re.findall(r"\brelacc(?:\.\w+)+", s)]
    assert len(dotted) >= 50 and len(SPANS) >= 500, (len(dotted), len(SPANS))
    assert _resolves("relacc.validation.diff.Diff") and not _resolves("relacc.validation.diff.NoSuchThing")
    assert not _resolves("relacc.engines.PinocchioEngine")  # a name issue 51 found in the docs, long gone


def test_every_dotted_name_resolves():
    missing = sorted({(str(doc), d) for doc, s in SPANS for d in re.findall(r"\brelacc(?:\.[A-Za-z_]\w*)+", s)
                      if not _resolves(d)})
    assert missing == [], missing


def _expanded(path: str) -> list[str]:
    """A documented path with its shell braces expanded (``run{1..3}.json``, ``{a,b}``) and each ``<placeholder>`` a
    glob's ``*``."""
    path = re.sub(r"<[^>]*>", "*", path)
    m = re.search(r"\{([^{}]*)\}", path)
    if not m:
        return [path]
    inner = m.group(1)
    if r := re.fullmatch(r"(\d+)\.\.(\d+)", inner):
        choices = [str(i) for i in range(int(r.group(1)), int(r.group(2)) + 1)]
    else:
        choices = inner.split(",")
    return [x for c in choices for x in _expanded(path[:m.start()] + c + path[m.end():])]


def test_braces_and_placeholders_expand():
    assert _expanded("b/run{1..3}.json") == ["b/run1.json", "b/run2.json", "b/run3.json"]
    assert _expanded("relacc/engines/<engine>_/{a,b}.py") == ["relacc/engines/*_/a.py", "relacc/engines/*_/b.py"]


def test_every_repository_path_exists():
    pattern = re.compile(r"(?<![\w/.-])(?:" + "|".join(TOP) + r")/[\w./{},<>*-]*[\w/}*>]")
    missing = sorted({(str(doc), p) for doc, s in SPANS for p in pattern.findall(s)
                      if not all(any(ROOT.glob(x)) if "*" in x else (ROOT / x).exists() for x in _expanded(p))})
    assert missing == [], missing


@pytest.fixture(scope="module")
def options() -> dict:
    parser = build_parser()
    return {name: {o for action in sub._actions for o in action.option_strings}
            for name, sub in subcommands(parser).items()}


def test_every_command_and_flag_exists(options):
    wrong = []
    for doc, span in SPANS:
        for m in re.finditer(r"(?:^|\$ |&& )relacc ([a-z][\w-]*)\b([^|;&]*)", span):
            command, rest = m.group(1), m.group(2)
            if command not in options:
                wrong.append((str(doc), span, f"no command {command}"))
                continue
            wrong += [(str(doc), span, flag) for flag in re.findall(r"(?<![\w-])--[a-z][\w-]*", rest)
                      if flag not in options[command]]
    assert wrong == [], wrong
