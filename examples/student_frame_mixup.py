"""The correct Case 1 student code, but with a frame mix-up: B2's angular velocity in B1, omega_hat_B2,
is given in B1 components and used as if it were in fixed components (the [R_B1]^T is missing).

relacc grade examples/student_frame_mixup.py:velocity --quantity velocity --case 1
"""

from student_correct import _terms, tilde


def velocity(chain, q, u, udot):
    R1T, q2, s2, r2, w1, _ = _terms(chain, q, u)
    return u[0:3] - (tilde(q2) + tilde(s2) + tilde(r2)) @ w1 + R1T @ u[6:9] - tilde(r2) @ u[9:12]
