"""Which engines exist and are installed, and the two loaders that import an adapter when asked for one
(the package's docstring states the rule)."""

from __future__ import annotations

import importlib
import importlib.util
import os
import sys
from collections.abc import Iterable
from dataclasses import dataclass
from types import ModuleType
from typing import TYPE_CHECKING, Any

from relacc.engines.base import Adapter
from relacc.engines.chain import ROUTES, ChainEngine
from relacc.errors import EngineError

if TYPE_CHECKING:
    from relacc.core.tree import Tree
    from relacc.fixtures import Fixture

ENGINES = ("pinocchio", "mujoco", "drake")
"""Engine names, in report order."""


@dataclass(frozen=True)
class Traits:
    """What an engine is and can do, declared without importing it: callers outside ``engines/`` ask this instead of
    branching on an engine's name (the layout test holds them to it).

    Attributes:
        package: its Python package. pip: its distribution's name.
        own_urdf: reads a URDF given beside an MJCF with its own parser (``compare --urdf``), and is then compared
            on that file's reading.
        compiled_loops: its per-state evaluations (points, Jacobians) run as loops in its own compiled code, so
            their time is the engine's (the throughput tables time these; a loop through Python per state is not).
        error_controlled: integrates with error-controlled integrators of its own, named in a scene's
            ``[simulate.<engine>]`` table with an accuracy, rather than relacc's fixed-step schemes only.
        own_steppers: steps a model with integrators in its own compiled code (``mj_step``, Drake's ``Simulator``),
            not relacc's integrators around its dynamics.
        mesh_source: relacc's reading asks its compiler for a mesh's mass properties (:data:`MESH_ENGINE`), so its
            terms on those bodies cannot judge it.
    """

    package: str
    pip: str
    own_urdf: bool = False
    compiled_loops: bool = False
    error_controlled: bool = False
    own_steppers: bool = False
    mesh_source: bool = False


TRAITS = {
    "pinocchio": Traits("pinocchio", "pin", own_urdf=True, compiled_loops=True),
    "mujoco": Traits("mujoco", "mujoco", compiled_loops=True, own_steppers=True, mesh_source=True),
    "drake": Traits("pydrake", "drake", error_controlled=True, own_steppers=True),
}
"""Each engine's :class:`Traits`, in :data:`ENGINES`' order."""

MESH_ENGINE = next(name for name, t in TRAITS.items() if t.mesh_source)
"""The engine relacc's reading asks for a mesh's mass properties (:func:`mesh_inertia`)."""


def traits(name: str) -> Traits:
    """An engine's :class:`Traits`.

    Raises:
        EngineError: an unknown engine.
    """
    if name not in TRAITS:
        raise EngineError(f"unknown engine {name!r}: accepted are {', '.join(ENGINES)}")
    return TRAITS[name]


def with_trait(trait: str, names: Iterable[str] = ENGINES) -> tuple[str, ...]:
    """The engines of ``names`` (default all, in report order) that have ``trait`` (a :class:`Traits` flag)."""
    return tuple(n for n in names if n in TRAITS and getattr(TRAITS[n], trait))


def installed(name: str) -> bool:
    """Whether an engine's Python package is installed (found without importing it)."""
    return importlib.util.find_spec(traits(name).package) is not None


def available() -> tuple[str, ...]:
    """The engines installed here, in report order (Drake has wheels for Linux x86_64 only)."""
    return tuple(name for name in ENGINES if installed(name))


def adapter_module(name: str) -> ModuleType:
    """The adapter package of an engine (imports the engine).

    Raises:
        EngineError: an unknown engine, or one not installed here.
    """
    if not installed(name):
        raise EngineError(f"engine {name} is not installed here (pip install {traits(name).pip}); installed: "
                          f"{', '.join(available()) or 'none'}")
    from relacc.files import PENDING
    from relacc.isolate import captured_output

    with captured_output() as lines:  # an engine's C++ logs its failed initialization when an interrupt lands while
        module = importlib.import_module(f"relacc.engines.{name}_")  # it loads (pydrake: 41 lines): the interrupt
    if PENDING[0] is None:  # is relacc's one line, also when the engine caught it and loaded anyway (its stack and
        for line in lines:  # "KeyboardInterrupt" are the interrupt's, not news); what it writes otherwise is passed on
            print(line, file=sys.stderr)
    return module


def readings(name: str) -> tuple:
    """An engine's ``ENGINE_READINGS``: the known differences in its algorithms (rather than its reading of a file,
    which :data:`relacc.validation.robots.causes.READINGS` reproduces), each a
    :class:`relacc.engines.base.KnownBehaviour` whose ``change`` rebuilds the adapter without it; MuJoCo: none."""
    return importlib.import_module(f"{adapter_module(name).__name__}.readings").ENGINE_READINGS


def load(name: str, path: str | os.PathLike, reference: Tree | None = None, **options) -> Adapter:
    """The one loader: model file ``path`` in engine ``name``, matched to ``reference`` (a :class:`relacc.Tree`;
    None: relacc's reading of the file; MuJoCo's adapter takes its own compiled tree, the chain's routes). Options by
    engine: Pinocchio ``urdf=``, ``split=``; Drake ``build=`` (the plant of ``reference`` itself).

    Raises:
        EngineError: an unknown or missing engine. ModelError: the engine cannot read the file.
    """
    return adapter_module(name).load(path, reference, **options)


def mesh_inertia(mesh: Any) -> Any:
    """MuJoCo's mass properties of one mesh geom of an MJCF (:mod:`relacc.engines.mujoco_.meshes`): what relacc's own
    reading asks an engine for (:func:`relacc.reading.read`; the bodies concerned are named in its ``taken``).

    Raises:
        EngineError: MuJoCo is not installed. ModelError: MuJoCo cannot compile the geom alone.
    """
    module = adapter_module(MESH_ENGINE)
    return importlib.import_module(f"{module.__name__}.meshes").mesh_inertia(mesh)


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


__all__ = ["ENGINES", "MESH_ENGINE", "ROUTES", "TRAITS", "Adapter", "ChainEngine", "Traits", "adapter_module",
           "available", "installed", "load", "load_engine", "mesh_inertia", "readings", "traits", "with_trait"]
