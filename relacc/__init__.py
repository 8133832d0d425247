"""relacc: the relative-coordinate formulas of a two-body chain, checked against engines.

The core (this package minus :mod:`relacc.engines`) imports no engine.
"""

from relacc.cases import Case
from relacc.chain import TwoBodyChain
from relacc.errors import (
    CaseError,
    EngineError,
    FixtureError,
    InputError,
    IntegrationError,
    RelaccError,
    SingularityError,
    VariantError,
)
from relacc.kinematics import G2Kinematics, g2_acceleration, g2_kinematics
from relacc.note.equations import EQUATIONS
from relacc.rotations import (
    matrix_from_123,
    matrix_from_quaternion,
    omega_partials_123,
    omega_partials_123_dot,
    quaternion_exp,
    quaternion_from_123,
    quaternion_multiply,
    tilde,
)

__version__ = "0.1.0"

__all__ = [
    "Case",
    "CaseError",
    "EQUATIONS",
    "EngineError",
    "FixtureError",
    "G2Kinematics",
    "InputError",
    "IntegrationError",
    "RelaccError",
    "SingularityError",
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
    "__version__",
]
