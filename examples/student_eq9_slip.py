"""The correct Case 1 student code, but with eq. (9) as printed: -[r2~][omega_B1~]^T instead of
-[r2~][omega_B1~][R_B1]^T in the rate of the last partial velocity matrix (one of the note's slips).

relacc grade examples/student_eq9_slip.py:acceleration --quantity acceleration --case 1
"""

import numpy as np
from student_correct import V, _terms, tilde


def Vdot(chain, q, u, udot):
    R1T, q2, s2, r2, w1, w2 = _terms(chain, q, u)
    q2d, s2d, r2d = np.cross(w1, q2), np.cross(w1, s2) + R1T @ u[6:9], np.cross(w2, r2)
    return np.hstack([np.zeros((3, 3)), -(tilde(q2d) + tilde(s2d) + tilde(r2d)), tilde(w1) @ R1T,
                      -tilde(r2d) @ R1T - tilde(r2) @ tilde(w1).T])     # eq. (9) as printed


def acceleration(chain, q, u, udot):
    return V(chain, q, u, udot) @ udot + Vdot(chain, q, u, udot) @ u
