"""The package's architecture: layers import downward only, no cycles, nothing heavy on import, help that helps."""

import ast
import functools
import subprocess
import sys
from pathlib import Path

import pytest

from relacc.cli.parser import build_parser, subcommands

PACKAGE = Path(__file__).resolve().parents[1] / "relacc"
HEAVY = ("numba", "pinocchio", "mujoco", "matplotlib", "scipy", "jinja2", "pydantic", "hypothesis", "pydrake",
         "dask", "distributed")

BASE = {"errors", "files", "limits", "isolate"}
ABOVE_ENGINES = BASE | {"core", "kernels", "dynamics", "fixtures", "reading", "engines"}
LAYERS = {
    "errors": set(),
    "isolate": set(),
    "files": {"errors"},
    "limits": {"errors"},
    "core": BASE,
    "reading": BASE | {"core"},
    "kernels": BASE | {"core"},
    "dynamics": BASE | {"core", "kernels"},
    "fixtures": BASE | {"core"},
    "engines": BASE | {"core", "kernels", "dynamics", "fixtures", "reading"},
    "simulate": ABOVE_ENGINES,
    "validation": ABOVE_ENGINES,
    "tradeoff": ABOVE_ENGINES | {"simulate", "validation"},
    "report": ABOVE_ENGINES | {"simulate", "validation", "tradeoff"},
    "testing": ABOVE_ENGINES | {"validation"},
    "cluster": ABOVE_ENGINES | {"simulate", "validation"},
    "cli": ABOVE_ENGINES | {"simulate", "validation", "tradeoff", "report", "testing", "cluster"},
}
"""Which layers each layer may import (besides itself). ``cli`` and ``relacc/__init__`` may import any."""

ENGINE_PACKAGES = {"mujoco": "mujoco_", "pinocchio": "pinocchio_", "pydrake": "drake_"}
"""Each engine's Python package and the one adapter package of ``relacc.engines`` that may import it."""

LAZY_ONLY = {("core", "kernels"), ("relacc.core.tree.model", "reading"), ("relacc.core.tree.model", "fixtures")}
"""Imports allowed inside functions only: the core loads the kernels at the first batched call; ``Tree.from_file``
hands a model file to relacc's reading or a chain TOML to the fixtures. The reading imports no engine, not even in
a function (issue 53): relacc computes meshes itself, and an engine offers what it does not
(:data:`relacc.reading.read.MESH_ENGINES`)."""


@functools.cache
def _parse(source: str) -> ast.Module:
    """``ast.parse``, once per source text: the rules below walk the same modules, and only read the trees."""
    return ast.parse(source)


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        yield ".".join(parts), path


def _imports(name, path):
    """``(imported relacc module, at module level?)`` for every import statement of a module."""
    tree = _parse(path.read_text())
    top = set(id(n) for n in tree.body)
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("relacc"):
            for alias in node.names:
                yield f"{node.module}.{alias.name}", id(node) in top
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("relacc"):
                    yield alias.name, id(node) in top


def _resolve(target, modules):
    """The module an import refers to (``relacc.core.tolerances.EPS`` -> ``relacc.core.tolerances``)."""
    while target not in modules and "." in target:
        target = target.rsplit(".", 1)[0]
    return target


def _layer(module):
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "relacc"


def test_layers_import_downward_only():
    """Every import of one relacc layer from another is allowed by the layer table (lazy ones where marked)."""
    modules = dict(_modules())
    bad = []
    for name, path in modules.items():
        here = _layer(name)
        if here in ("relacc", "models", "recorded") or here not in LAYERS:
            continue
        for target, at_top in _imports(name, path):
            there = _layer(_resolve(target, modules))
            if there in (here, "relacc"):
                continue
            allowed = there in LAYERS[here] or (not at_top and ((here, there) in LAZY_ONLY
                                                                 or (name, there) in LAZY_ONLY))
            if not allowed:
                bad.append(f"{name} imports {target} ({'module level' if at_top else 'in a function'})")
    assert bad == []


def test_no_import_cycles():
    """The graph of module-level imports between relacc's modules has no cycle."""
    modules = dict(_modules())
    graph = {name: {_resolve(t, modules) for t, top in _imports(name, path) if top} - {name}
             for name, path in modules.items()}
    for name in graph:  # a package imports its submodules' parents implicitly: not an edge worth counting
        graph[name] = {t for t in graph[name] if t in modules and not name.startswith(t + ".")}
    state, cycle = {}, []

    def visit(node, stack):
        state[node] = 1
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                cycle.append(stack[stack.index(nxt):] + [nxt] if nxt in stack else [node, nxt])
            elif nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node, [node])
    assert cycle == []


def test_no_two_modules_import_each_other_even_lazily():
    """No pair of modules imports each other, counting imports inside functions (issue 37: ``testing/grade`` and
    ``grade_tree``, ``testing/truth`` and ``trees`` did): what both need lives in a third module."""
    modules = dict(_modules())
    graph = {name: {_resolve(t, modules) for t, _ in _imports(name, path)} - {name} for name, path in modules.items()}
    mutual = sorted({tuple(sorted((a, b))) for a in graph for b in graph[a] if b in graph and a in graph[b]
                     and not a.startswith(b + ".") and not b.startswith(a + ".")})
    assert mutual == []


def _loaded_after(code, tmp_path):
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys\nprint('loaded:', *(m for m in "
                          f"{HEAVY!r} if m in sys.modules))"],
                         capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout.splitlines()[-1].split()[1:]


@pytest.mark.slow
def test_import_relacc_loads_nothing_heavy(tmp_path):
    """`import relacc` (from another directory) loads no compiler, engine, plotting or template library."""
    assert _loaded_after("import relacc", tmp_path) == []


@pytest.mark.slow
def test_core_evaluation_on_the_reference_path_loads_no_compiler(tmp_path):
    """The core's reference formulas run without numba: only a batched fast call loads the kernels."""
    code = ("import numpy as np, relacc\nc = relacc.TwoBodyChain(q2=[0, 0, .1], r2=[.1, 0, 0])\n"
            "relacc.g2_kinematics(c, 3, np.zeros(12), np.ones(12), backend='reference')")
    assert _loaded_after(code, tmp_path) == []
    code = code.replace("backend='reference'", "backend='fast'")
    loaded = _loaded_after(code, tmp_path)
    assert "numba" in loaded and set(loaded) <= {"numba", "scipy"}, loaded  # numba itself imports scipy


@pytest.mark.slow
@pytest.mark.parametrize("argv", [["--help"], ["check", "--help"], ["--version"]])
def test_help_loads_nothing_heavy(tmp_path, argv):
    """`relacc --help` and a subcommand's help import no engine, compiler or plotting library."""
    code = f"from relacc.cli import main\nassert main({argv!r}) == 0"
    assert _loaded_after(code, tmp_path) == []


def test_every_subcommand_documents_itself():
    """Each subcommand's --help has a description, an example, the exit codes and choices for enumerations."""
    for name, sub in subcommands(build_parser()).items():
        text = sub.format_help()
        assert sub.description, name
        assert "examples:\n  relacc " + name in text, name
        for code in ("0  success", "1  a disagreement", "2  a usage or input error"):
            assert code in text, (name, code)
        for action in sub._actions:
            if action.dest in ("integrator",):
                assert action.choices, (name, action.dest)


def test_common_flags_mean_the_same_everywhere():
    """--json, --seed, --model and --quiet have one help text each across every subcommand."""
    seen = {}
    for name, sub in subcommands(build_parser()).items():
        for action in sub._actions:
            for flag in ("--json", "--seed", "--model", "--quiet"):
                if flag in action.option_strings:
                    seen.setdefault(flag, {})[name] = action.help.split(" (")[0].split(";")[0]
    for flag, texts in seen.items():
        assert len(set(texts.values())) == 1, (flag, texts)
    assert set(seen["--model"]) >= {"eval", "check", "errata", "fixtures", "report", "tradeoff"}


def engine_imports(name: str, source: str) -> list[str]:
    """Imports of an engine package (``import mujoco``, ``from pydrake.x import y``, anywhere in the module) outside
    that engine's own adapter package, and imports of an adapter's modules from outside ``relacc.engines``."""
    bad = []
    for node in ast.walk(_parse(source)):
        targets = []
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            targets = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        for target in targets:
            top = target.split(".")[0]
            if top in ENGINE_PACKAGES and not name.startswith(f"relacc.engines.{ENGINE_PACKAGES[top]}"):
                bad.append(f"{name}:{node.lineno} imports {target}")
            adapter = [a for a in ENGINE_PACKAGES.values() if target.startswith(f"relacc.engines.{a}")]
            if adapter and not name.startswith("relacc.engines"):
                bad.append(f"{name}:{node.lineno} imports the adapter module {target}")
    return sorted(set(bad))


def private_imports(name: str, source: str) -> list[str]:
    """``from relacc.x import _y`` across modules (dunder names like ``__version__`` are public)."""
    bad = []
    for node in ast.walk(_parse(source)):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("relacc"):
            for alias in node.names:
                if alias.name.startswith("_") and not alias.name.startswith("__") and node.module != name:
                    bad.append(f"{name}:{node.lineno} imports {node.module}.{alias.name}")
    return bad


@pytest.mark.slow
def test_engine_packages_are_imported_only_by_their_adapter():
    """``mujoco``, ``pinocchio`` and ``pydrake`` appear only in their own adapter package under relacc/engines/, and
    nothing outside relacc/engines/ reaches an adapter but through the registry (``relacc.engines.load``)."""
    bad = [b for name, path in _modules() for b in engine_imports(name, path.read_text())]
    assert bad == []


def test_no_private_name_is_imported_across_modules():
    bad = [b for name, path in _modules() for b in private_imports(name, path.read_text())]
    assert bad == []


def test_the_layout_checks_catch_planted_imports():
    """The two checks above fail on a planted ``import mujoco`` in simulate/ and a planted private import."""
    assert engine_imports("relacc.simulate.runs", "def f():\n    import mujoco\n") == [
        "relacc.simulate.runs:2 imports mujoco"]
    assert engine_imports("relacc.simulate.runs", "from relacc.engines.mujoco_.run import rollout\n") == [
        "relacc.simulate.runs:1 imports the adapter module relacc.engines.mujoco_.run",
        "relacc.simulate.runs:1 imports the adapter module relacc.engines.mujoco_.run.rollout"]
    assert engine_imports("relacc.engines.pinocchio_.model", "import pydrake\n") == [
        "relacc.engines.pinocchio_.model:1 imports pydrake"]
    assert engine_imports("relacc.engines.mujoco_.run", "import mujoco\n") == []
    assert private_imports("relacc.simulate.runs", "from relacc.engines.base import _helper\n") == [
        "relacc.simulate.runs:1 imports relacc.engines.base._helper"]


LAZY_ROOT = {"__version__", "_SUBPACKAGES", "_NAMES", "__getattr__", "__dir__"}
"""What ``relacc/__init__.py`` may define besides imports: its version and the lazy re-export of its public names
(PEP 562's module ``__getattr__``), so that ``import relacc`` loads only the errors."""


def init_logic(name, source):
    """Statements of a package's ``__init__.py`` that are not its docstring, an import, ``__all__`` or a constant
    string (an attribute's docstring); and a missing ``__all__``."""
    tree, bad, declared = _parse(source), [], False
    for node in tree.body:
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            continue
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str):
            continue
        targets = node.targets if isinstance(node, ast.Assign) else [node.target] \
            if isinstance(node, ast.AnnAssign) else []
        names = {t.id for t in targets if isinstance(t, ast.Name)}
        if names == {"__all__"}:
            declared = True
            continue
        defined = names or ({node.name} if isinstance(node, (ast.FunctionDef, ast.ClassDef)) else set())
        is_guard = isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING"
        if name == "relacc" and ((defined and defined <= LAZY_ROOT) or is_guard):
            continue
        bad.append(f"{name}:{node.lineno} has {type(node).__name__} {', '.join(sorted(defined))}".rstrip())
    return bad + ([] if declared else [f"{name} declares no __all__"])


def test_packages_only_hand_names_on():
    """Every ``__init__.py`` holds its docstring, imports and ``__all__``, nothing else: the logic lives in modules
    (issue 37 #5); the root package's lazy loader is the one exception (:data:`LAZY_ROOT`)."""
    bad = [b for name, path in _modules() if path.name == "__init__.py" for b in init_logic(name, path.read_text())]
    assert bad == []


def test_the_init_check_catches_planted_logic():
    assert init_logic("relacc.simulate", '"""doc"""\nfrom x import y\n__all__ = ["y"]\n') == []
    assert init_logic("relacc.simulate", '"""doc"""\ndef f():\n    pass\n__all__ = ["f"]\n') == [
        "relacc.simulate:2 has FunctionDef f"]
    assert init_logic("relacc.simulate", "X = 1\n") == ["relacc.simulate:1 has Assign X",
                                                          "relacc.simulate declares no __all__"]
    assert init_logic("relacc", "def __getattr__(name):\n    pass\n__all__ = []\n") == []


ENGINE_NAMES = set(__import__("relacc.engines", fromlist=["ENGINES"]).ENGINES)
"""Every engine's name (its card's), the two of issue 51's round included: the checks below look for each."""


def _names(node) -> bool:
    if isinstance(node, ast.Constant) and node.value in ENGINE_NAMES:
        return True
    return isinstance(node, (ast.Tuple, ast.List, ast.Set)) and any(_names(e) for e in node.elts)


def name_branches(name, source):
    """Comparisons with an engine's name (``engine == "mujoco"``, ``name in ("pinocchio", "mujoco")``) in a module:
    outside ``relacc/engines/`` a caller asks :func:`relacc.engines.traits` what an engine can do instead. An XML
    element's tag (``root.tag != "mujoco"``, MJCF's root element) is not an engine."""
    bad = []
    for node in ast.walk(_parse(source)):
        if isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
            tags = any(isinstance(o, ast.Attribute) and o.attr == "tag" for o in operands)
            if any(_names(o) for o in operands) and not tags:
                bad.append(f"{name}:{node.lineno} {ast.unparse(node)}")
    return bad


def name_uses(name, source):
    """An engine's name as a dict key, a subscript, a call's argument or a parameter's default (``{"mujoco": ...}``,
    ``by["pinocchio"]``, ``load("mujoco", path)``, ``engine="mujoco"``): engine knowledge, which lives in the engine's
    package (its card's :class:`relacc.engines.traits.Traits`, its adapter's capabilities), issue 51 item 2."""
    bad = []
    for node in ast.walk(_parse(source)):
        hits = []
        if isinstance(node, ast.Dict):
            hits = [k for k in node.keys if k is not None and _names(k)]
        elif isinstance(node, ast.Subscript) and _names(node.slice):
            hits = [node]
        elif isinstance(node, ast.Call):
            args = [a.body if isinstance(a, ast.IfExp) else a for a in node.args]  # f(("mujoco",) if x else y)
            hits = [a for a in args if _names(a)] + [k.value for k in node.keywords if _names(k.value)]
        elif isinstance(node, ast.arguments):
            hits = [d for d in [*node.defaults, *node.kw_defaults] if d is not None and _names(d)]
        bad += [f"{name}:{h.lineno} {ast.unparse(h)}" for h in hits]
    return bad


STILL_NAMING_ENGINES: dict[str, str] = {}
"""Modules outside ``engines/`` that still name engines, each with the reason; the test fails on any other, and on an
entry here that no longer names one (so the list only shrinks)."""


def test_no_engine_name_branches_outside_engines():
    """Code outside ``relacc/engines/`` never branches on an engine's name (issue 37 #2)."""
    bad = [b for name, path in _modules() if not name.startswith("relacc.engines")
           for b in name_branches(name, path.read_text())]
    assert bad == []


def test_no_engine_knowledge_outside_engines():
    """Nor keys, subscripts, arguments or defaults by an engine's name (issue 51 item 2), but in the modules
    :data:`STILL_NAMING_ENGINES` lists with their reason."""
    found = {name: name_uses(name, path.read_text()) for name, path in _modules()
             if not name.startswith("relacc.engines")}
    bad = [b for name, hits in found.items() if name not in STILL_NAMING_ENGINES for b in hits]
    assert bad == []
    stale = [name for name in STILL_NAMING_ENGINES if not found.get(name)]
    assert stale == [], f"no longer naming an engine: take them off STILL_NAMING_ENGINES: {stale}"


def test_the_branch_check_catches_planted_branches():
    assert name_branches("relacc.simulate.runs", 'if engine == "drake":\n    pass\n') == [
        "relacc.simulate.runs:1 engine == 'drake'"]
    assert name_branches("relacc.simulate.runs", 'x = [n for n in names if n in ("pinocchio", "mujoco")]\n') == [
        "relacc.simulate.runs:1 n in ('pinocchio', 'mujoco')"]
    assert name_branches("relacc.reading.mjcf", 'if root.tag != "mujoco":\n    pass\n') == []
    assert name_branches("relacc.simulate.runs", 'if name == "relacc":\n    pass\n') == []


def test_the_knowledge_check_catches_planted_names():
    planted = ('COLORS = {"mujoco": "red"}\nx = by["pinocchio"]\nload("drake", path)\n'
               'def f(engine="mujoco"):\n    pass\nload(name, engine="relacc")\n')
    assert name_uses("relacc.report.x", planted) == [
        "relacc.report.x:1 'mujoco'", "relacc.report.x:2 by['pinocchio']", "relacc.report.x:3 'drake'",
        "relacc.report.x:4 'mujoco'"]


def bare_case_comparisons(name, source):
    """``case == 3``-style comparisons: outside the compiled kernels (which take the case as a plain int) a case is
    named by :class:`relacc.Case` (``case == Case.ANGLE_RATES``), issue 37 #3."""
    bad = []
    for node in ast.walk(_parse(source)):
        if isinstance(node, ast.Compare) and isinstance(node.left, ast.Name) and node.left.id in ("case", "c"):
            if any(isinstance(o, ast.Constant) and o.value in (1, 2, 3) for o in node.comparators):
                bad.append(f"{name}:{node.lineno} {ast.unparse(node)}")
    return bad


def test_cases_are_named_outside_the_kernels():
    bad = [b for name, path in _modules() if not name.startswith("relacc.kernels")
           for b in bare_case_comparisons(name, path.read_text())]
    assert bad == []
    assert bare_case_comparisons("relacc.simulate.runs", "x = 1 if case == 3 else 2\n") == [
        "relacc.simulate.runs:1 case == 3"]
    assert bare_case_comparisons("relacc.simulate.runs", "x = 1 if case == Case.ANGLE_RATES else 2\n") == []


def test_the_command_line_finds_the_engines_the_registry_finds():
    """``relacc --help`` names the engines without importing ``relacc.engines`` (it reads each package's card); the
    names and their order are the registry's."""
    from relacc.cli.parser import ENGINE_NAMES
    from relacc.engines import ENGINES

    assert ENGINE_NAMES == ENGINES and len(ENGINES) >= 3


def test_nothing_asks_whether_a_scene_is_the_chain():
    """Issue 51: a scene's kind is asked once, when it picks relacc's side of it (``Scene.evaluator``: the note's chain
    or a model's tree, one interface in relacc.simulate.subjects); no ``is_chain`` branch is left anywhere."""
    found = [f"{path.relative_to(PACKAGE.parent)}:{i}" for path in sorted(PACKAGE.rglob("*.py"))
             for i, line in enumerate(path.read_text().splitlines(), 1) if "is_chain" in line]
    assert found == []
