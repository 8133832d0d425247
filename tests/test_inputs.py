"""Bad input raises a RelaccError subclass that says what was wrong and what is accepted."""

import numpy as np
import pytest

import relacc
from relacc.errors import CaseError, InputError, VariantError

Q14 = np.r_[0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0.0]
U = np.zeros(12)


@pytest.mark.parametrize(
    "case,q,u,error,match",
    [
        (4, Q14, U, CaseError, "accepted cases are 1, 2 and 3"),
        ("1", Q14, U, CaseError, "accepted cases"),
        (True, Q14, U, CaseError, "accepted cases"),
        (1, Q14[:12], U, InputError, r"shape \(\.\.\., 14\)"),
        (3, Q14, U, InputError, r"shape \(\.\.\., 12\)"),
        (1, Q14, U[:11], InputError, r"shape \(\.\.\., 12\).*got shape \(11,\)"),
        (1, np.r_[Q14[:3], 0.5, 0, 0, 0, Q14[7:]], U, InputError, "does not normalize"),
        (1, np.where(np.arange(14) == 0, np.nan, Q14), U, InputError, "non-finite"),
        (1, Q14, np.where(np.arange(12) == 5, np.inf, U), InputError, "non-finite"),
        (1, ["a"] * 14, U, InputError, "expected numbers"),
        (1, [[0.0] * 14, [0.0]], U, InputError, "cannot be read as an array"),
    ],
)
def test_bad_state_inputs(chain, case, q, u, error, match):
    """Wrong case, lengths, NaN/inf, strings and non-unit quaternions are rejected by name."""
    with pytest.raises(error, match=match):
        relacc.g2_kinematics(chain, case, q, u)


def test_quaternion_within_tolerance_is_accepted_and_not_normalized(chain):
    """A quaternion off unit by 1e-13 (inside the documented 1e-12) is used as given."""
    q = Q14.copy()
    q[3] = np.sqrt(1 + 1e-13)
    k = relacc.g2_kinematics(chain, 1, q, U)
    assert np.all(np.isfinite(k.position))


def test_unknown_variant_and_ids(chain):
    """variant accepts 'corrected', 'printed' or equation ids, and names them."""
    with pytest.raises(VariantError, match="'corrected', 'printed'"):
        relacc.g2_kinematics(chain, 1, Q14, U, variant="fixed")
    with pytest.raises(VariantError, match="eq13"):
        relacc.g2_kinematics(chain, 1, Q14, U, variant={"eq13"})


def test_batch_shapes_that_do_not_broadcast(chain):
    """q of batch 3 with u of batch 2 is an InputError naming both shapes."""
    with pytest.raises(InputError, match="do not broadcast"):
        relacc.g2_kinematics(chain, 1, np.tile(Q14, (3, 1)), np.zeros((2, 12)))


@pytest.mark.parametrize(
    "kwargs,match",
    [
        ({"q2": [0, 0], "r2": [0, 0, 0]}, "q2: expected 3 numbers"),
        ({"q2": [0, 0, np.nan], "r2": [0, 0, 0]}, "q2: every entry must be finite"),
        ({"q2": [0, 0, 0], "r2": [0, 0, 0], "m1": 0}, "m1: expected a finite positive mass"),
        ({"q2": [0, 0, 0], "r2": [0, 0, 0], "I2": [[1, 2, 0], [0, 1, 0], [0, 0, 1]]}, "symmetric"),
        ({"q2": [0, 0, 0], "r2": [0, 0, 0], "I1": np.diag([1, 1, 3])}, "not physically realizable"),
        ({"q2": "abc", "r2": [0, 0, 0]}, "q2"),
    ],
)
def test_bad_chain_geometry_and_inertia(kwargs, match):
    """TwoBodyChain rejects non-finite or mis-shaped geometry and unphysical inertia."""
    with pytest.raises(InputError, match=match):
        relacc.TwoBodyChain(**kwargs)


def test_chain_must_be_a_two_body_chain():
    """Passing something else as the chain is an InputError."""
    with pytest.raises(InputError, match="TwoBodyChain"):
        relacc.g2_kinematics({"q2": [0, 0, 0]}, 1, Q14, U)


def test_every_error_is_a_relacc_error():
    """All error classes derive from RelaccError."""
    for cls in (InputError, CaseError, VariantError, relacc.FixtureError, relacc.EngineError):
        assert issubclass(cls, relacc.RelaccError)
