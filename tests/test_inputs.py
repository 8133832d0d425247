"""Bad input raises a RelaccError subclass that says what was wrong and what is accepted."""

import time
from pathlib import Path

import numpy as np
import pytest

import relacc
from relacc.core.states import random_states
from relacc.core.stream import iter_g2_kinematics
from relacc.errors import CaseError, InputError, VariantError
from tests.cli import one_line, run_relacc

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


ROOT = Path(__file__).resolve().parents[1]


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


@pytest.mark.parametrize("call,match", [
    (lambda: relacc.matrix_from_quaternion([np.nan, 0, 0, 0]), "non-finite"),
    (lambda: relacc.matrix_from_quaternion([2.0, 0, 0, 0]), "does not normalize"),
    (lambda: relacc.matrix_from_quaternion([True, 0, 0, 0]), "boolean"),
    (lambda: relacc.matrix_from_quaternion([np.sqrt(2), 1j, 0, 0]), "does not normalize"),
    (lambda: relacc.quaternion_multiply([1, 0, 0, 0], [0, 0, 0, 0]), "does not normalize"),
    (lambda: relacc.tilde([1, 2]), r"shape \(\.\.\., 3\)"),
    (lambda: relacc.matrix_from_123(["a", "b", "c"]), "expected numbers"),
    (lambda: relacc.quaternion_exp([np.inf, 0, 0]), "non-finite"),
    (lambda: relacc.omega_partials_123_dot(np.zeros((2, 3)), np.zeros((3, 3))), "do not broadcast"),
    (lambda: relacc.quaternion_from_123([0, 0, None]), "expected numbers"),
])
def test_exported_building_blocks_check_their_inputs(call, match):
    """Whatever relacc exports validates as g2_kinematics does: NaN, non-unit, booleans and strings refused."""
    with pytest.raises(InputError, match=match):
        call()


def test_exported_building_blocks_take_lists_and_agree_with_the_bare_ones():
    """Lists are accepted, and the checked functions return exactly what the bare ones do."""
    from relacc.core import rotations

    q = [0.5, 0.5, 0.5, 0.5]
    assert np.array_equal(relacc.matrix_from_quaternion(q), rotations.matrix_from_quaternion(np.array(q)))
    assert np.array_equal(relacc.tilde([1, 2, 3]), rotations.tilde(np.array([1.0, 2.0, 3.0])))
    R = relacc.matrix_from_quaternion(q)
    assert np.allclose(R @ R.T, np.eye(3), rtol=0, atol=4 * np.finfo(float).eps)


def test_a_complex_quaternion_is_judged_by_its_true_size(chain):
    """(sqrt 2, i, 0, 0) has q.q = 1 but |q|^2 = 3: refused; a complex step's small imaginary part passes."""
    q = Q14.astype(complex)
    q[3:7] = [np.sqrt(2), 1j, 0, 0]
    with pytest.raises(InputError, match="squared norm 3"):
        relacc.g2_kinematics(chain, 1, q, U)
    q[3:7] = [1, 1e-20j, 0, 0]
    assert relacc.g2_kinematics(chain, 1, q, U).position.dtype == complex


@pytest.mark.parametrize("kwargs,error,match", [
    ({"variant": "nope"}, VariantError, "unknown variant"),
    ({"backend": "gpu"}, InputError, "unknown backend"),
])
def test_empty_batches_still_check_everything(chain, kwargs, error, match):
    """A batch of zero states still has its variant, backend and chain checked."""
    with pytest.raises(error, match=match):
        relacc.g2_kinematics(chain, 1, np.zeros((0, 14)), np.zeros((0, 12)), **kwargs)
    with pytest.raises(InputError, match="TwoBodyChain"):
        relacc.g2_kinematics("chain", 1, np.zeros((0, 14)), np.zeros((0, 12)))
    assert relacc.g2_kinematics(chain, 1, np.zeros((0, 14)), np.zeros((0, 12))).V.shape == (0, 3, 12)


def test_accelerations_raise_at_gimbal_lock(fixture):
    """Kane's accelerations in case 3 at gimbal lock raise SingularityError, as the inverse speed map does."""
    q = np.zeros(12)
    q[4] = np.pi / 2
    with pytest.raises(relacc.SingularityError, match="gimbal lock"):
        relacc.dynamics.accelerations(fixture.chain, 3, q, np.zeros(12))
    q[4] = np.pi / 2 - 0.1  # far enough: an answer
    assert np.all(np.isfinite(relacc.dynamics.accelerations(fixture.chain, 3, q, np.ones(12))))


@pytest.mark.parametrize("column,value,match", [
    (5, 0.5, r"quat_B1 at batch index \(637,\) has squared norm"),
    (0, np.nan, r"non-finite"),
    (-1, np.inf, r"non-finite"),  # in u
])
def test_accelerations_check_every_state_in_the_kernel(fixture, column, value, match):
    """The compiled path flags a bad state inside a large batch and the checks name it, as g2_kinematics does."""
    from relacc.core.states import random_states

    s = random_states(1, 1000, [7, 1])
    q, u = s.q.copy(), s.u.copy()
    (u if column < 0 else q)[637, column] = value
    with pytest.raises(InputError, match=match):
        relacc.dynamics.accelerations(fixture.chain, 1, q, u)
    with pytest.raises(InputError, match=match):
        relacc.dynamics.accelerations(fixture.chain, 1, q, u, backend="reference")


def test_accelerations_flag_near_gimbal_lock_but_the_checks_decide(fixture):
    """Condition 2/delta: 6.7e7 (flagged by the kernel, under MAX_CONDITION = 1e8) passes; 2e8 raises."""
    q = np.zeros((3, 12))
    q[1, 4] = np.pi / 2 - 3e-8
    assert np.all(np.isfinite(relacc.dynamics.accelerations(fixture.chain, 3, q, np.zeros(12))))
    q[2, 10] = -np.pi / 2 + 1e-8
    with pytest.raises(relacc.SingularityError, match=r"theta_B2\[1\].*batch index \(2,\)"):
        relacc.dynamics.accelerations(fixture.chain, 3, q, np.zeros(12))


def test_requests_that_cannot_fit_are_refused_up_front(chain):
    """A batch whose outputs exceed the memory available is refused with the estimate, before any work."""
    from relacc.limits import available_memory

    n = int(2 * (available_memory() or 2**40) // 8 // 120) + 1
    q = np.broadcast_to(Q14, (n, 14))  # a view: no memory of its own
    with pytest.raises(InputError, match=r"evaluating \d+ states at once needs about .* GiB.*iter_g2_kinematics"):
        relacc.g2_kinematics(chain, 1, q, U)


def test_stream_takes_lists(chain):
    s = random_states(1, 5, 0)
    chunks = list(iter_g2_kinematics(chain, 1, s.q.tolist(), s.u.tolist(), s.udot.tolist(), chunk_size=2))
    assert [c.stop for c, _ in chunks] == [2, 4, 5]
    np.testing.assert_array_equal(chunks[-1][1].acceleration,
                                  relacc.g2_kinematics(chain, 1, s.q[4:], s.u[4:], s.udot[4:]).acceleration)


def test_generalized_forces_take_lists_and_check_shapes(chain):
    from relacc.dynamics import Effects, generalized_forces

    s = random_states(2, 3, 1)
    gravity = Effects(gravity=[0, 0, -9.81])
    Q = generalized_forces(chain, 2, s.q.tolist(), s.u.tolist(), gravity)
    np.testing.assert_array_equal(Q, generalized_forces(chain, 2, s.q, s.u, gravity))
    assert Q.shape == (3, 12)
    with pytest.raises(InputError, match=r"expected shape \(\.\.\., 14\)"):
        generalized_forces(chain, 2, s.q[:, :11], s.u, gravity)


def test_truth_assert_agrees_and_random_states_say_what_is_wrong():
    from relacc.testing import assert_agrees, truth

    with pytest.raises(InputError, match="expected the states"):
        truth([np.zeros(14)])
    with pytest.raises(InputError, match="numbers"):
        assert_agrees(["a", "b", "c"], np.zeros(3))
    with pytest.raises(InputError, match="n: expected an integer"):
        random_states(1, 2.0, 0)


@pytest.mark.slow
def test_huge_requests_are_refused_before_any_work(tmp_path, relacc_states):
    for argv in (["compare", str(ROOT / "models" / "two_body.xml"), "--states", "1000000000"],
                 ["grade", "examples/student_correct.py:velocity", "--quantity", "velocity", "--case", "1",
                  "--states", "1000000000"]):
        start = time.monotonic()
        line = one_line(run_relacc(*argv, cwd=ROOT if argv[0] == "grade" else tmp_path, timeout=60))
        assert "memory" in line and time.monotonic() - start < 30, (argv, line)
    with pytest.raises(InputError, match="memory"):
        relacc_states(n=10**12)
