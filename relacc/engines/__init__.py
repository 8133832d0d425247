"""Engine adapters: one module per engine behind one interface (:class:`Engine`).

* :mod:`relacc.engines.pinocchio_` -- Pinocchio (imports only ``pinocchio``);
* :mod:`relacc.engines.mujoco_` -- MuJoCo (imports only ``mujoco``);
* :mod:`relacc.engines.drake_` -- Drake (imports only ``pydrake``).

Each adapter converts its engine's conventions locally and documents them
beside the code. Layer rule: adapters import the core, the dynamics, the
fixtures and their own engine; nothing imports an adapter but through
:func:`load_engine`, which imports it when it is asked for.
"""

from __future__ import annotations

import importlib
import importlib.util

from relacc.engines.base import ROUTES, Engine
from relacc.errors import EngineError
from relacc.fixtures import Fixture, load

ENGINES = ("pinocchio", "mujoco", "drake")
"""Engine names, in report order."""

_MODULES = {"pinocchio": ("relacc.engines.pinocchio_", "PinocchioEngine", "pinocchio", "pin"),
            "mujoco": ("relacc.engines.mujoco_", "MujocoEngine", "mujoco", "mujoco"),
            "drake": ("relacc.engines.drake_", "DrakeEngine", "pydrake", "drake")}


def installed(name: str) -> bool:
    """Whether an engine's Python package is installed (found without importing it)."""
    return importlib.util.find_spec(_MODULES[name][2]) is not None


def available() -> tuple[str, ...]:
    """The engines installed here, in report order (Drake has wheels for Linux x86_64 only)."""
    return tuple(name for name in ENGINES if installed(name))


def load_engine(name: str, fixture: Fixture | None = None) -> Engine:
    """Load an engine adapter with a fixture (default: the shipped ``two_body.toml``).

    Raises:
        EngineError: unknown engine name, or an engine not installed here.
        FixtureError: unreadable or stale model files.
    """
    if name not in _MODULES:
        raise EngineError(f"unknown engine {name!r}: accepted are {', '.join(ENGINES)}")
    module, cls, package, pip_name = _MODULES[name]
    if not installed(name):
        raise EngineError(f"engine {name} is not installed here (pip install {pip_name}); installed: "
                          f"{', '.join(available()) or 'none'}")
    return getattr(importlib.import_module(module), cls)(fixture if fixture is not None else load())


__all__ = ["ENGINES", "ROUTES", "Engine", "available", "installed", "load_engine"]
