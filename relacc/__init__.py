"""relacc: the note's relative-coordinate method, for its two-body chain and for any kinematic tree,
checked against engines.

``import relacc`` loads its errors only; a public name loads the engine-free core (numpy and the standard library)
at first use, the compiled kernels load at the first batched call, an engine when one is asked for, the report and
the plots when a report is made.

Layers, one folder each (the rule of each is in its package docstring):

* :mod:`relacc.core`: the note's mathematics, the error model;
* :mod:`relacc.kernels`: fused numba kernels behind the core's batch calls;
* :mod:`relacc.dynamics`: Kane's equations and effects; :mod:`relacc.simulate`: scenes and runs;
* :mod:`relacc.engines`: one adapter per engine behind one interface;
* :mod:`relacc.validation`: cross-validation, errata, hard cases;
* :mod:`relacc.fixtures`: the TOML source of truth, engine files, shipped models;
* :mod:`relacc.report`, :mod:`relacc.tradeoff`, :mod:`relacc.cli`.
"""

import importlib
from typing import TYPE_CHECKING

from relacc.errors import (
    AccuracyWarning,
    CaseError,
    EngineError,
    FixtureError,
    InputError,
    IntegrationError,
    ModelError,
    NotARobot,
    OutputError,
    RelaccError,
    SingularityError,
    VariantError,
)

if TYPE_CHECKING:  # what the names below resolve to, for readers and type checkers
    from relacc.core.cases import Case
    from relacc.core.chain import TwoBodyChain
    from relacc.core.checked import (
        matrix_from_123,
        matrix_from_quaternion,
        omega_partials_123,
        omega_partials_123_dot,
        quaternion_exp,
        quaternion_from_123,
        quaternion_multiply,
        tilde,
    )
    from relacc.core.kinematics import G2Kinematics, g2_acceleration, g2_kinematics
    from relacc.core.note.equations import EQUATIONS
    from relacc.core.tree import Body, Joint, Point, Tree, TreeKinematics, tree_kinematics
    from relacc.dynamics.tree import TreeDynamics, tree_accelerations, tree_dynamics
    from relacc.dynamics.tree_effects import BodyLoad, JointEffect, TreeEffects

__version__ = "0.2.0"

_SUBPACKAGES = ("core", "reading", "kernels", "dynamics", "simulate", "engines", "validation", "fixtures", "report",
                "tradeoff", "testing", "cluster", "cli")


_NAMES = {
    **dict.fromkeys(("Case",), "relacc.core.cases"),
    **dict.fromkeys(("TwoBodyChain",), "relacc.core.chain"),
    **dict.fromkeys(("matrix_from_123", "matrix_from_quaternion", "omega_partials_123", "omega_partials_123_dot",
                     "quaternion_exp", "quaternion_from_123", "quaternion_multiply", "tilde"), "relacc.core.checked"),
    **dict.fromkeys(("G2Kinematics", "g2_acceleration", "g2_kinematics"), "relacc.core.kinematics"),
    **dict.fromkeys(("EQUATIONS",), "relacc.core.note.equations"),
    **dict.fromkeys(("Body", "Joint", "Point", "Tree", "TreeKinematics", "tree_kinematics"), "relacc.core.tree"),
    **dict.fromkeys(("TreeDynamics", "tree_accelerations", "tree_dynamics"), "relacc.dynamics.tree"),
    **dict.fromkeys(("BodyLoad", "JointEffect", "TreeEffects"), "relacc.dynamics.tree_effects"),
}
"""The public names and their modules, loaded at first use: ``import relacc`` itself loads only the errors, so the
command line can take signals from its first instructions (numpy and the core load in the next milliseconds)."""


def __getattr__(name):
    """Public names and subpackages on first use: ``relacc.Tree``, ``relacc.dynamics.accelerations(...)``."""
    if name in _NAMES:
        value = getattr(importlib.import_module(_NAMES[name]), name)
        globals()[name] = value
        return value
    if name in _SUBPACKAGES:
        return importlib.import_module(f"relacc.{name}")
    raise AttributeError(f"module 'relacc' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_NAMES) | set(_SUBPACKAGES))


__all__ = [
    "Body",
    "BodyLoad",
    "Case",
    "CaseError",
    "AccuracyWarning",
    "EQUATIONS",
    "EngineError",
    "FixtureError",
    "G2Kinematics",
    "InputError",
    "Joint",
    "JointEffect",
    "IntegrationError",
    "ModelError",
    "NotARobot",
    "OutputError",
    "Point",
    "RelaccError",
    "SingularityError",
    "Tree",
    "TreeDynamics",
    "TreeEffects",
    "TreeKinematics",
    "TwoBodyChain",
    "VariantError",
    "g2_acceleration",
    "g2_kinematics",
    "matrix_from_123",
    "matrix_from_quaternion",
    "omega_partials_123",
    "omega_partials_123_dot",
    "quaternion_exp",
    "quaternion_from_123",
    "quaternion_multiply",
    "tilde",
    "tree_accelerations",
    "tree_dynamics",
    "tree_kinematics",
    "__version__",
]
