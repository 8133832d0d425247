"""The note's building blocks against independent references (scipy, numpy, complex step)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from relacc.core import rotations as rot
from relacc.core.derivatives import complex_step
from relacc.core.tolerances import assert_normalized_error

from .conftest import SEED

N = 500


@pytest.fixture
def gen():
    return np.random.default_rng(SEED + 7)


def test_tilde_is_cross_product(gen):
    """[v~] w equals numpy's cross product v x w."""
    v, w = gen.normal(size=(N, 3)), gen.normal(size=(N, 3))
    got = np.einsum("nij,nj->ni", rot.tilde(v), w)
    scale = np.linalg.norm(v, axis=-1) * np.linalg.norm(w, axis=-1)
    assert_normalized_error(got, np.cross(v, w), scale, what="tilde", seed=SEED + 7, factor=4)
    assert_normalized_error(rot.untilde(rot.tilde(v)), v, np.linalg.norm(v, axis=-1), what="untilde", factor=0)


def test_quaternion_matrix_matches_scipy(gen):
    """matrix_from_quaternion (w first) equals scipy's active rotation matrix."""
    quat = gen.normal(size=(N, 4))
    quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
    ref = Rotation.from_quat(rot.quaternion_to_xyzw(quat)).as_matrix()
    assert_normalized_error(rot.matrix_from_quaternion(quat), ref, np.ones(N),
                            what="quat->matrix", seed=SEED + 7, factor=8)


def test_antipodal_quaternions_give_the_same_matrix(gen):
    """q and -q represent the same rotation (the w < 0 sign)."""
    quat = gen.normal(size=(N, 4))
    quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
    assert np.array_equal(rot.matrix_from_quaternion(quat), rot.matrix_from_quaternion(-quat))


def test_quaternion_from_matrix_matches_scipy_and_inverts_the_matrix(gen):
    """quaternion_from_matrix (w first, w >= 0) equals scipy's ``from_matrix`` with the same sign choice on random
    rotations and on the half turns and near-half turns about each axis (where the trace is -1 and Shepperd's choice
    matters), and its matrix is the input. Tolerances: a quaternion's unit components formed by one division and a
    normalization (8 eps); the matrix from it, as in the test above (8 eps)."""
    quat = gen.normal(size=(N, 4))
    quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
    turns = [axis * angle for axis in np.eye(3) for angle in (np.pi, np.pi - 1e-9, 1e-9, np.pi / 2)]
    R = np.concatenate([rot.matrix_from_quaternion(quat), Rotation.from_rotvec(turns).as_matrix(), np.eye(3)[None]])
    ref = rot.quaternion_from_xyzw(Rotation.from_matrix(R).as_quat())
    ref = np.where(ref[:, :1] < 0, -ref, ref)
    got = rot.quaternion_from_matrix(R)
    assert np.all(got[:, 0] >= 0)
    exact = np.abs(ref[:, 0]) > 1e-6  # a half turn's w is 0 to rounding: its sign, and so q's, is either
    assert_normalized_error(got[exact], ref[exact], np.ones(exact.sum()), what="matrix->quat", seed=SEED + 7, factor=8)
    assert_normalized_error(rot.matrix_from_quaternion(got), R, np.ones(len(R)), what="quat->matrix->quat",
                            seed=SEED + 7, factor=8)


def test_123_matrix_matches_scipy_intrinsic_xyz(gen):
    """Rx(t1) Ry(t2) Rz(t3) equals scipy's intrinsic 'XYZ' Euler rotation."""
    theta = gen.uniform(-np.pi, np.pi, (N, 3))
    ref = Rotation.from_euler("XYZ", theta).as_matrix()
    assert_normalized_error(rot.matrix_from_123(theta), ref, np.ones(N), what="123->matrix", seed=SEED + 7, factor=8)


def test_quaternion_from_123_matches_matrix(gen):
    """The quaternion of 1-2-3 angles has the 1-2-3 matrix."""
    theta = gen.uniform(-np.pi, np.pi, (N, 3))
    got = rot.matrix_from_quaternion(rot.quaternion_from_123(theta))
    assert_normalized_error(got, rot.matrix_from_123(theta), np.ones(N), what="123->quat->matrix", factor=8)


def test_quaternion_product_composes_matrices(gen):
    """matrix(p (x) q) = matrix(p) matrix(q)."""
    p, q = gen.normal(size=(2, N, 4))
    p /= np.linalg.norm(p, axis=-1, keepdims=True)
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    got = rot.matrix_from_quaternion(rot.quaternion_multiply(p, q))
    ref = rot.matrix_from_quaternion(p) @ rot.matrix_from_quaternion(q)
    assert_normalized_error(got, ref, np.ones(N), what="product", factor=16)


@pytest.mark.parametrize("magnitude", [0.0, 1e-12, 1e-5, 1e-3, 1.0, 3.0, 100.0])
def test_quaternion_exp_matches_scipy_rotvec(gen, magnitude):
    """quaternion_exp(phi) is scipy's rotation vector phi, across the series switch at |phi|^2 = 1e-8."""
    axis = gen.normal(size=(N, 3))
    phi = magnitude * axis / np.linalg.norm(axis, axis=-1, keepdims=True)
    got = rot.matrix_from_quaternion(rot.quaternion_exp(phi))
    ref = Rotation.from_rotvec(phi).as_matrix()
    assert_normalized_error(got, ref, np.ones(N), what=f"exp |phi|={magnitude}", factor=8)
    norm_dev = np.abs(np.sum(rot.quaternion_exp(phi) ** 2, axis=-1) - 1)
    assert np.all(norm_dev <= 4 * np.finfo(float).eps)


def test_omega_partials_123_give_angular_velocity(gen):
    """W(theta) theta_dot equals the angular velocity from Rdot R^T (complex step)."""
    theta = gen.uniform(-np.pi, np.pi, (N, 3))
    theta_dot = gen.normal(size=(N, 3))
    R = rot.matrix_from_123(theta)
    R_dot = complex_step(lambda t: rot.matrix_from_123(theta + t * theta_dot))
    omega_ref = rot.untilde(R_dot @ np.swapaxes(R, -1, -2))  # reference-frame components
    got = np.einsum("nij,nj->ni", rot.omega_partials_123(theta), theta_dot)
    assert_normalized_error(got, omega_ref, np.linalg.norm(theta_dot, axis=-1), what="W theta_dot", factor=16)


def test_omega_partials_123_dot_is_time_derivative(gen):
    """W_dot(theta, theta_dot) equals the complex-step derivative of W along theta_dot."""
    theta = gen.uniform(-np.pi, np.pi, (N, 3))
    theta_dot = gen.normal(size=(N, 3))
    ref = complex_step(lambda t: rot.omega_partials_123(theta + t * theta_dot))
    got = rot.omega_partials_123_dot(theta, theta_dot)
    assert_normalized_error(got, ref, np.linalg.norm(theta_dot, axis=-1), what="W_dot", factor=8)
