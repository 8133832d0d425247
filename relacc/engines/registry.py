"""Which engines exist and are installed, and the two loaders that import an adapter when asked for one
(the package's docstring states the rule)."""

from __future__ import annotations

import importlib
import importlib.util
import sys

from relacc.engines.base import Adapter
from relacc.engines.chain import ROUTES, ChainEngine
from relacc.errors import EngineError

ENGINES = ("pinocchio", "mujoco", "drake")
"""Engine names, in report order."""

_PACKAGES = {"pinocchio": ("pinocchio", "pin"), "mujoco": ("mujoco", "mujoco"), "drake": ("pydrake", "drake")}
"""Each engine's Python package and its pip name."""


def installed(name: str) -> bool:
    """Whether an engine's Python package is installed (found without importing it)."""
    return importlib.util.find_spec(_PACKAGES[name][0]) is not None


def available() -> tuple[str, ...]:
    """The engines installed here, in report order (Drake has wheels for Linux x86_64 only)."""
    return tuple(name for name in ENGINES if installed(name))


def adapter_module(name: str):
    """The adapter package of an engine (imports the engine).

    Raises:
        EngineError: an unknown engine, or one not installed here.
    """
    if name not in _PACKAGES:
        raise EngineError(f"unknown engine {name!r}: accepted are {', '.join(ENGINES)}")
    if not installed(name):
        raise EngineError(f"engine {name} is not installed here (pip install {_PACKAGES[name][1]}); installed: "
                          f"{', '.join(available()) or 'none'}")
    from relacc.isolate import captured_stderr

    with captured_stderr() as lines:  # an engine's C++ logs its failed initialization when an interrupt lands while
        module = importlib.import_module(f"relacc.engines.{name}_")  # it loads (pydrake: 41 lines): the interrupt
    for line in lines:  # is relacc's one line; what it writes when it loads is passed on
        print(line, file=sys.stderr)
    return module


def readings(name: str) -> tuple:
    """An engine's ``ENGINE_READINGS``: the known differences in its algorithms (rather than its reading of a file,
    which :data:`relacc.validation.robots.causes.READINGS` reproduces), each ``(key, text, applies(adapter),
    rebuild(adapter))``; MuJoCo: none."""
    if name == "mujoco":
        return ()
    return importlib.import_module(f"{adapter_module(name).__name__}.readings").ENGINE_READINGS


def load(name: str, path, reference=None, **options) -> Adapter:
    """The one loader: model file ``path`` in engine ``name``, matched to ``reference`` (a :class:`relacc.Tree`;
    default: MuJoCo's reading of the same file). Options by engine: Pinocchio ``urdf=``, ``split=``; Drake
    ``build=`` (the plant of ``reference`` itself).

    Raises:
        EngineError: an unknown or missing engine. ModelError: the engine cannot read the file.
    """
    module = adapter_module(name)
    if reference is None and name != "mujoco":
        reference = load("mujoco", path).reference
    return module.load(path, reference, **options)


def mesh_inertia(mesh):
    """MuJoCo's mass properties of one mesh geom of an MJCF (:mod:`relacc.engines.mujoco_.meshes`): what relacc's own
    reading asks an engine for (:func:`relacc.reading.read`; the bodies concerned are named in its ``taken``).

    Raises:
        EngineError: MuJoCo is not installed. ModelError: MuJoCo cannot compile the geom alone.
    """
    module = adapter_module("mujoco")
    return importlib.import_module(f"{module.__name__}.meshes").mesh_inertia(mesh)


def load_engine(name: str, fixture=None, **options) -> ChainEngine:
    """The note's chain (``fixture``; default the shipped ``two_body.toml``) in one engine, both routes.

    Raises:
        EngineError: unknown engine name, or an engine not installed here.
        FixtureError: unreadable or stale model files.
    """
    from relacc.engines.chain import chain_engine
    from relacc.fixtures import load as load_fixture

    adapter_module(name)
    return chain_engine(name, fixture if fixture is not None else load_fixture(), **options)


__all__ = ["ENGINES", "ROUTES", "Adapter", "ChainEngine", "adapter_module", "available", "installed", "load",
           "load_engine", "mesh_inertia", "readings"]
