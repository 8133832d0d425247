"""Engine adapters: one module per engine behind one interface (:class:`Engine`).

* :mod:`relacc.engines.mujoco_` -- MuJoCo (imports only ``mujoco``);
* :mod:`relacc.engines.pinocchio_` -- Pinocchio (imports only ``pinocchio``).

Each adapter converts its engine's conventions locally and documents them
beside the code. The core (:mod:`relacc`) never imports this package.
"""

from __future__ import annotations

import importlib

from relacc.engines.base import ROUTES, Engine
from relacc.errors import EngineError
from relacc.fixtures import Fixture, load

ENGINES = ("pinocchio", "mujoco")
"""Engine names, in report order."""

_MODULES = {"pinocchio": ("relacc.engines.pinocchio_", "PinocchioEngine"),
            "mujoco": ("relacc.engines.mujoco_", "MujocoEngine")}


def load_engine(name: str, fixture: Fixture | None = None) -> Engine:
    """Load an engine adapter with a fixture (default ``models/two_body.toml``).

    Raises:
        EngineError: unknown engine name. FixtureError: unreadable model files.
    """
    if name not in _MODULES:
        raise EngineError(f"unknown engine {name!r}: accepted are {', '.join(ENGINES)}")
    module, cls = _MODULES[name]
    return getattr(importlib.import_module(module), cls)(fixture if fixture is not None else load())


__all__ = ["ENGINES", "ROUTES", "Engine", "load_engine"]
