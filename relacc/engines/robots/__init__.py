"""Robot models loaded in each engine, for ``relacc compare``: one module per engine behind :class:`Robot`.

* :mod:`relacc.engines.robots.mujoco_` -- the reference (MuJoCo reads MJCF natively; its coordinates
  are the common ones);
* :mod:`relacc.engines.robots.pinocchio_` -- Pinocchio's MJCF parser, or a URDF;
* :mod:`relacc.engines.robots.drake_` -- Drake's MJCF parser.

Each module imports only its own engine and converts its conventions there
(:mod:`relacc.engines.robots.base` states the common ones).
"""

from __future__ import annotations

import importlib

from relacc.engines import installed
from relacc.engines.robots.base import Dynamics, Joint, Link, LinkKinematics, Robot, Structure
from relacc.errors import EngineError

ROBOT_ENGINES = ("mujoco", "pinocchio", "drake")
"""Engines ``relacc compare`` loads a model in; MuJoCo first: it is the reference."""

_CLASSES = {"mujoco": ("relacc.engines.robots.mujoco_", "MujocoRobot"),
            "pinocchio": ("relacc.engines.robots.pinocchio_", "PinocchioRobot"),
            "drake": ("relacc.engines.robots.drake_", "DrakeRobot")}


def robot_class(name: str):
    """The adapter class of one engine (imports the engine).

    Raises:
        EngineError: an unknown engine or one not installed here.
    """
    if name not in _CLASSES:
        raise EngineError(f"unknown engine {name!r}: accepted are {', '.join(ROBOT_ENGINES)}")
    if not installed(name):
        raise EngineError(f"engine {name} is not installed here")
    module, cls = _CLASSES[name]
    return getattr(importlib.import_module(module), cls)


__all__ = ["ROBOT_ENGINES", "Dynamics", "Joint", "Link", "LinkKinematics", "Robot", "Structure", "robot_class"]
