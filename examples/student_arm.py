"""A student's formulas for the forearm of examples/three_link_arm.xml, by the note's method, numpy only.

Case 2 (MuJoCo's coordinates): q = [shoulder_yaw, shoulder_pitch, elbow, wrist] (rad), u their rates (rad/s),
udot their second derivatives. Every result is about the forearm's mass centre, in fixed-frame components. Grade:

    relacc grade examples/student_arm.py:velocity --model examples/three_link_arm.xml --body forearm \
        --quantity velocity --case 2
    relacc grade examples/student_arm.py:acceleration_slip --model examples/three_link_arm.xml --body forearm \
        --quantity acceleration --case 2          # the classic slip: the elbow axis treated as fixed in space
"""

import numpy as np

SHOULDER = np.array([0.0, 0.0, 0.5])  # the upper arm's frame in the world, m
UPPER = np.array([0.4, 0.0, 0.0])     # the elbow from the shoulder, upper arm's frame, m
COM = np.array([0.15, 0.0, 0.0])      # the forearm's mass centre from the elbow, forearm's frame, m
EZ, EY = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _frames(q, u):
    R0 = rz(q[0])                       # after the yaw
    R1 = R0 @ ry(q[1])                  # the upper arm: body -> fixed components
    R2 = R1 @ ry(q[2])                  # the forearm
    e0, e1, e2 = EZ, R0 @ EY, R1 @ EY   # the hinge axes, fixed components
    w1 = u[0] * e0 + u[1] * e1          # the upper arm's angular velocity
    w2 = w1 + u[2] * e2                 # the forearm's
    return R1, R2, e0, e1, e2, w1, w2


def position(tree, q, u, udot):
    R1, R2, *_ = _frames(q, u)
    return SHOULDER + R1 @ UPPER + R2 @ COM


def velocity(tree, q, u, udot):
    """v = w1 x (R1 a) + w2 x (R2 c): each lever turns with its link."""
    R1, R2, e0, e1, e2, w1, w2 = _frames(q, u)
    return np.cross(w1, R1 @ UPPER) + np.cross(w2, R2 @ COM)


def acceleration(tree, q, u, udot):
    """a = al1 x r1 + w1 x (w1 x r1) + al2 x r2 + w2 x (w2 x r2), with the axes' own rates in al1, al2."""
    R1, R2, e0, e1, e2, w1, w2 = _frames(q, u)
    r1, r2 = R1 @ UPPER, R2 @ COM
    al1 = udot[0] * e0 + udot[1] * e1 + u[1] * np.cross(u[0] * e0, e1)   # e1 turns with the yaw
    al2 = al1 + udot[2] * e2 + u[2] * np.cross(w1, e2)                     # e2 turns with the upper arm
    return np.cross(al1, r1) + np.cross(w1, np.cross(w1, r1)) + np.cross(al2, r2) + np.cross(w2, np.cross(w2, r2))


def acceleration_slip(tree, q, u, udot):
    """The same, with the elbow's axis treated as fixed in space: u[2] (w1 x e2) left out of al2."""
    R1, R2, e0, e1, e2, w1, w2 = _frames(q, u)
    r1, r2 = R1 @ UPPER, R2 @ COM
    al1 = udot[0] * e0 + udot[1] * e1 + u[1] * np.cross(u[0] * e0, e1)
    al2 = al1 + udot[2] * e2
    return np.cross(al1, r1) + np.cross(w1, np.cross(w1, r1)) + np.cross(al2, r2) + np.cross(w2, np.cross(w2, r2))
