"""Which engines exist and are installed, and the two loaders that import an adapter when asked for one
(the package's docstring states the rule)."""

from __future__ import annotations

import importlib
import importlib.util
import os
import pkgutil
import sys
from collections.abc import Iterable
from types import ModuleType
from typing import TYPE_CHECKING, Any

from relacc.engines.base import Adapter
from relacc.engines.chain import ROUTES, ChainEngine
from relacc.engines.traits import Traits
from relacc.errors import EngineError

if TYPE_CHECKING:
    from relacc.core.tree import Tree
    from relacc.fixtures import Fixture

def _cards() -> dict[str, Traits]:
    """Every engine package's :class:`Traits` (``relacc/engines/<name>_/card.py``), in report order: an engine is its
    package, found here, not a name listed elsewhere."""
    import relacc.engines as package

    found = [card for m in pkgutil.iter_modules(package.__path__) if m.ispkg and m.name.endswith("_")
             for card in _package_cards(importlib.import_module(f"relacc.engines.{m.name}"))]
    return {t.name: t for t in sorted(found, key=lambda t: t.order)}


def _package_cards(module: ModuleType) -> tuple[Traits, ...]:
    """An engine package's cards: its ``CARDS`` (several loadings of one engine), else its one ``TRAITS``."""
    return tuple(getattr(module, "CARDS", (module.TRAITS,)))


TRAITS = _cards()
"""Each engine's :class:`Traits`, in report order."""

ENGINES = tuple(TRAITS)
"""Engine names, in report order."""

CHAIN_ENGINES = tuple(name for name, t in TRAITS.items() if t.chain_routes)
"""The engines that model the note's chain (:attr:`Traits.chain_routes`), in report order: the check's, the chain's
hard cases', its tradeoff studies' and its scenes'."""

MESH_ENGINE = next(name for name, t in TRAITS.items() if t.mesh_source)
"""The engine relacc's reading asks for a mesh's mass properties it does not compute itself (:func:`mesh_inertia`)."""

TRUTH_ENGINE = next(name for name, t in TRAITS.items() if t.truth)
"""The engine the pytest plugin's truth and the tree hard-case search use unless told (:attr:`Traits.truth`)."""


def traits(name: str) -> Traits:
    """An engine's :class:`Traits`.

    Raises:
        EngineError: an unknown engine.
    """
    if name not in TRAITS:
        raise EngineError(f"unknown engine {name!r}: accepted are {', '.join(ENGINES)}")
    return TRAITS[name]


def label(name: str) -> str:
    """How an evaluator is written in sentences: an engine's :attr:`Traits.label`; relacc (or any other evaluator) as
    itself."""
    return TRAITS[name].label if name in TRAITS else name


def with_trait(trait: str, names: Iterable[str] = ENGINES) -> tuple[str, ...]:
    """The engines of ``names`` (default all, in report order) that have ``trait`` (a :class:`Traits` flag)."""
    return tuple(n for n in names if n in TRAITS and getattr(TRAITS[n], trait))


def with_capability(capability: type, names: Iterable[str] = ENGINES) -> tuple[str, ...]:
    """The engines of ``names`` (default all, in report order) whose adapter implements ``capability`` (a class of
    :mod:`relacc.engines.capabilities`), from their traits: nothing is imported."""
    return tuple(n for n in names if n in TRAITS and capability.__name__ in TRAITS[n].capabilities)


def anchor(name: str, kind: str) -> str:
    """A benchmark row's name for engine ``name``'s call of a ``kind`` (:attr:`Traits.calls`): ``"pinocchio
    abaInParallel"``."""
    return f"{name} {TRAITS[name].calls[kind]}"


def anchors(kind: str) -> tuple[str, ...]:
    """The row names of every engine's call of a ``kind`` (those that have one), in report order."""
    return tuple(anchor(n, kind) for n, t in TRAITS.items() if kind in t.calls)


def installed(name: str) -> bool:
    """Whether an engine's Python package is installed (found without importing it)."""
    return importlib.util.find_spec(traits(name).package) is not None


def available() -> tuple[str, ...]:
    """The engines installed here, in report order (Drake has wheels for Linux x86_64 only)."""
    return tuple(name for name in ENGINES if installed(name))


def chain_exports() -> dict[str, dict]:
    """Each chain engine's entry of the chain's exported ``conventions.json`` (:func:`relacc.fixtures.export.
    conventions`), written by its card's ``chain_export`` (``relacc/engines/<name>_/card.py``), in report order;
    imports no engine."""
    return {name: importlib.import_module(f"{TRAITS[name].package_name}.card").chain_export()
            for name in CHAIN_ENGINES}


def chain_engines(names: Iterable[str] | None = None) -> tuple[str, ...]:
    """The engines of ``names`` (default: those installed) that model the note's chain (:attr:`Traits.chain_routes`):
    the check, the chain's hard cases, its tradeoff studies and its scenes run on these."""
    return tuple(n for n in (available() if names is None else names) if n in CHAIN_ENGINES)


def steppers(names: Iterable[str] | None = None) -> tuple[str, ...]:
    """The engines of ``names`` (default: those installed) that step a model (:attr:`Traits.integrators`): a scene's
    engines unless it names them."""
    return tuple(n for n in (available() if names is None else names) if n in TRAITS and TRAITS[n].integrators)


def judges(fmt: str) -> tuple[str, ...]:
    """The engines installed here that ``relacc compare`` and ``relacc check --model`` hold a file of format ``fmt`` to
    unless told (``--engines``): those that read the format and take the file's inertias from it
    (:attr:`Traits.file_inertias`). PyBullet as users load a URDF computes every link's inertia from its collision
    shapes, so every URDF would differ there whatever its author wrote: it is compared when named."""
    return tuple(n for n in available() if reads(n, fmt) and TRAITS[n].file_inertias)


def reads(name: str, fmt: str) -> bool:
    """Whether engine ``name``'s loader reads a description of format ``fmt`` (:attr:`Traits.formats`)."""
    return fmt in traits(name).formats


def adapter_module(name: str) -> ModuleType:
    """The adapter module of an engine, ``relacc.engines.<name>_.adapter`` (imports the engine).

    Raises:
        EngineError: an unknown engine, or one not installed here.
    """
    if not installed(name):
        raise EngineError(f"engine {name} is not installed here (pip install {traits(name).pip}); installed: "
                          f"{', '.join(available()) or 'none'}")
    from relacc.files import PENDING
    from relacc.isolate import captured_output

    # an engine's C++ logs its failed initialization when an interrupt lands while it loads (pydrake: 41 lines): the
    # interrupt is relacc's one line, also when the engine caught it and loaded anyway (its stack and
    # "KeyboardInterrupt" are the interrupt's, not news); what it writes otherwise is passed on
    with captured_output() as lines:
        module = importlib.import_module(f"{traits(name).package_name}.adapter")
    if PENDING[0] is None:
        for line in lines:
            print(line, file=sys.stderr)
    return module


def readings(name: str) -> tuple:
    """An engine's ``ENGINE_READINGS``: the known differences in its algorithms (rather than its reading of a file,
    which :data:`relacc.validation.robots.causes.READINGS` reproduces), each a
    :class:`relacc.engines.base.KnownBehaviour` whose ``change`` rebuilds the adapter without it; MuJoCo: none."""
    adapter_module(name)
    return importlib.import_module(f"{traits(name).package_name}.readings").ENGINE_READINGS


def file_readings(name: str) -> tuple:
    """An engine's ``FILE_READINGS``: how its parsers read a file differently, as changes to relacc's reading
    (:mod:`relacc.engines.known`), without importing the engine."""
    t = traits(name)
    return getattr(importlib.import_module(f"{t.package_name}.readings"), t.readings)


def load(name: str, path: str | os.PathLike, reference: Tree | None = None, **options) -> Adapter:
    """The one loader: model file ``path`` in engine ``name``, matched to ``reference`` (a :class:`relacc.Tree`;
    None: relacc's reading of the file; MuJoCo's adapter takes its own compiled tree, the chain's routes). Options by
    engine: Pinocchio ``urdf=``, ``split=``; Drake ``build=`` (the plant of ``reference`` itself).

    Raises:
        EngineError: an unknown or missing engine. ModelError: the engine cannot read the file.
    """
    return adapter_module(name).load(path, reference, **{**traits(name).options, **options})


def mesh_inertia(mesh: Any) -> Any:
    """MuJoCo's mass properties of one mesh geom of an MJCF (:mod:`relacc.engines.mujoco_.meshes`): what relacc's own
    reading asks an engine for (:func:`relacc.reading.read`; the bodies concerned are named in its ``taken``).

    Raises:
        EngineError: MuJoCo is not installed. ModelError: MuJoCo cannot compile the geom alone.
    """
    adapter_module(MESH_ENGINE)
    return importlib.import_module(f"{TRAITS[MESH_ENGINE].package_name}.meshes").mesh_inertia(mesh)


def _offer_meshes_to_the_reading() -> None:
    """MuJoCo's computation of a mesh geom relacc does not compute itself (a primitive fitted to a mesh), offered to
    relacc's reading (:data:`relacc.reading.read.MESH_ENGINES`), which imports no engine."""
    from relacc.reading.read import MESH_ENGINES

    if mesh_inertia not in MESH_ENGINES:
        MESH_ENGINES.append(mesh_inertia)


_offer_meshes_to_the_reading()


def load_engine(name: str, fixture: Fixture | None = None, **options) -> ChainEngine:
    """The note's chain (``fixture``; default the shipped ``two_body.toml``) in one engine, both routes.

    Raises:
        EngineError: unknown engine name, or an engine not installed here.
        FixtureError: unreadable or stale model files.
    """
    from relacc.engines.chain import chain_engine
    from relacc.fixtures import load as load_fixture

    adapter_module(name)
    return chain_engine(name, fixture if fixture is not None else load_fixture(), **options)


__all__ = ["CHAIN_ENGINES", "ENGINES", "MESH_ENGINE", "ROUTES", "TRAITS", "TRUTH_ENGINE", "Adapter", "ChainEngine",
           "Traits", "adapter_module", "anchor", "anchors", "available", "chain_engines", "file_readings",
           "installed", "judges", "label", "load", "load_engine", "mesh_inertia", "reads", "readings", "steppers",
           "traits", "with_capability", "with_trait"]
