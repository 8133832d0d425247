"""A student's implementation of the note's Case 1 formulas, one state at a time, with numpy only.

Conventions (relacc's, see its README): q = [s1, quat_B1 (w, x, y, z), s2', quat_B2/B1], u = [s1_dot,
omega_B1 (fixed components), s2'_dot (B1 components), omega_hat_B2 (B1 components)]. Every result is
about G2, in fixed-frame components. Grade it:  relacc grade examples/student_correct.py:acceleration
--quantity acceleration --case 1
"""

import numpy as np


def tilde(v):
    """[v~], with [v~] w = v x w."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def rotation(quat):
    """The matrix of a unit quaternion (w, x, y, z): body -> reference components."""
    w, x, y, z = quat
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _terms(chain, q, u):
    R1T = rotation(q[3:7])                 # [R_B1]^T: B1 -> fixed
    R2T = R1T @ rotation(q[10:14])         # [R_B2]^T = [R_B1]^T [^{B2}R_{B1}]
    q2, s2, r2 = R1T @ chain.q2, R1T @ q[7:10], R2T @ chain.r2
    w1 = u[3:6]
    w2 = w1 + R1T @ u[9:12]                # B2's angular velocity in R
    return R1T, q2, s2, r2, w1, w2


def position(chain, q, u, udot):
    """G2 from R's origin: s1 + q2 + s2 + r2 (m)."""
    R1T, q2, s2, r2, _, _ = _terms(chain, q, u)
    return q[0:3] + q2 + s2 + r2


def V(chain, q, u, udot):
    """Eq. (3): [I, -(q2~ + s2~ + r2~), [R_B1]^T, -r2~ [R_B1]^T], 3 x 12."""
    R1T, q2, s2, r2, _, _ = _terms(chain, q, u)
    return np.hstack([np.eye(3), -(tilde(q2) + tilde(s2) + tilde(r2)), R1T, -tilde(r2) @ R1T])


def Vdot(chain, q, u, udot):
    """Eqs. (5)-(9), with eq. (9)'s first form: the rates of the partial velocity matrices, 3 x 12."""
    R1T, q2, s2, r2, w1, w2 = _terms(chain, q, u)
    q2d = np.cross(w1, q2)                              # eq. (5)
    s2d = np.cross(w1, s2) + R1T @ u[6:9]               # eq. (6)
    r2d = np.cross(w2, r2)                              # eq. (7)
    R1Td = tilde(w1) @ R1T                              # eq. (8)
    return np.hstack([np.zeros((3, 3)), -(tilde(q2d) + tilde(s2d) + tilde(r2d)), R1Td,
                      -tilde(r2d) @ R1T - tilde(r2) @ R1Td])


def velocity(chain, q, u, udot):
    """Eq. (1): v = V u (m/s)."""
    return V(chain, q, u, udot) @ u


def acceleration(chain, q, u, udot):
    """Eq. (4): a = V udot + Vdot u, classical (m/s^2)."""
    return V(chain, q, u, udot) @ udot + Vdot(chain, q, u, udot) @ u
