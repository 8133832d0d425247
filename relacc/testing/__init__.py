"""relacc in other people's tests: seeded states, engine truth and relacc's error model.

Layer rule: imports the core, kernels, dynamics, reading, the engines, the fixtures and
the validation harness, lazily; nothing heavy on import, so the pytest plugin
(:mod:`relacc.testing.plugin`, registered as ``relacc``) costs no one
anything until a fixture is used.

* :func:`states`, :func:`truth`: states of a case (ordinary or hard) and an
  engine's (or relacc's) values for them, as :class:`Expected` quantities;
* :func:`assert_agrees`: relacc's error model, with a message naming the
  worst state, its seed, the component and the columns that disagree;
* :func:`check_formula`: grade a user's formula (``relacc grade``).
"""

from relacc.testing.agree import SPEED_NAMES, assert_agrees
from relacc.testing.expected import Expected, Truth
from relacc.testing.grade import check_formula
from relacc.testing.truth import states, truth

__all__ = ["SPEED_NAMES", "Expected", "Truth", "assert_agrees", "check_formula", "states", "truth"]
