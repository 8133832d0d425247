"""The correct Case 1 student code, but with an error in one block of V: the prismatic columns use
[R_B1] (fixed -> B1) where the note has [R_B1]^T (B1 -> fixed).

relacc grade examples/student_block_error.py:V --quantity V --case 1
"""

import numpy as np
from student_correct import _terms, tilde


def V(chain, q, u, udot):
    R1T, q2, s2, r2, _, _ = _terms(chain, q, u)
    return np.hstack([np.eye(3), -(tilde(q2) + tilde(s2) + tilde(r2)), R1T.T, -tilde(r2) @ R1T])
