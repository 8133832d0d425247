"""The note's method on a tree, in plain numpy: each body's partial velocities from its parent's.

For every body, root first, the walk carries a *frame*: an origin ``o``, its orientation ``R``
(body components to fixed components, ``[R_B]^T`` in the note), the partial velocity matrix of the
origin ``V`` (``{v_o} = [V]{u}``), the partial angular velocities ``Omega`` (``{omega} = [Omega]{u}``),
their time derivatives ``Vdot``, ``Omegadot`` and the frame's angular velocity ``w``, all in fixed-frame
components, ``(n, 3, nv)`` and ``(n, 3)``. Three rules build everything, as in the note:

* a point ``P = Q + r`` fixed in a frame (eq1, eq5-eq7): ``[V_P] = [V_Q] - [r~][Omega]``,
  ``[Vdot_P] = [Vdot_Q] - [r_dot~][Omega] - [r~][Omegadot]`` with ``r_dot = w x r``;
* a slide of ``s`` along ``e`` adds the column ``e`` (and ``w x e`` to ``Vdot``), and its moving
  offset ``r = e s`` has ``r_dot = w x r + e s_dot`` (the note's ``{s2'}``, eq6);
* a rotating joint adds its partial angular velocities ``A`` (3 x its speeds) to ``Omega`` and
  their rate ``A_dot`` to ``Omegadot``; ``A`` is the case's choice of speeds (:func:`angular_map`).

The velocity and classical acceleration of any point are then ``[V]{u}`` and
``[V]{udot} + [Vdot]{u}`` (eq3-eq4, eq10-eq11, eq12).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from relacc.core.cases import Case
from relacc.core.rotations import matrix_from_123, matrix_from_quaternion, quaternion_exp, tilde
from relacc.core.so3 import w123, w123_dot


def mv(A, x):
    """Batched ``A x``: ``(n, m, k) x (n, k) -> (n, m)``."""
    return np.einsum("nij,nj->ni", A, x)


def cross_columns(r, M):
    """``[r~][M]``: ``r (n, 3)`` crossed into every column of ``M (n, 3, k)`` (numpy's ``cross`` formula, the
    same rounding, without its axis moves: the walk's most frequent operation)."""
    r0, r1, r2 = r[:, 0, None], r[:, 1, None], r[:, 2, None]
    M0, M1, M2 = M[:, 0], M[:, 1], M[:, 2]
    return np.stack([r1 * M2 - r2 * M1, r2 * M0 - r0 * M2, r0 * M1 - r1 * M0], axis=1)


def cross(a, b):
    """``a x b`` for ``(n, 3)`` rows (numpy's formula, the same rounding)."""
    a0, a1, a2, b0, b1, b2 = a[:, 0], a[:, 1], a[:, 2], b[:, 0], b[:, 1], b[:, 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=1)


@dataclass
class Frame:
    """A frame moving with the tree (see the module docstring); fields ``(n, 3)``, ``(n, 3, 3)``, ``(n, 3, nv)``."""

    o: np.ndarray
    R: np.ndarray
    V: np.ndarray
    Omega: np.ndarray
    Vdot: np.ndarray
    Omegadot: np.ndarray
    w: np.ndarray | None

    def point(self, r, r_dot=None):
        """``(V, Vdot)`` of the point ``o + r`` (``r (n, 3)`` fixed in the frame unless ``r_dot`` is given)."""
        if r_dot is None:
            r_dot = cross(self.w, r)
        return (self.V - cross_columns(r, self.Omega),
                self.Vdot - cross_columns(r_dot, self.Omega) - cross_columns(r, self.Omegadot))

    def moved(self, r, R=None) -> "Frame":
        """The frame carried to the origin ``o + r`` (``r`` fixed in it), with orientation ``R`` (default its own)."""
        V, Vdot = self.point(r)
        return Frame(self.o + r, self.R if R is None else R, V, self.Omega, Vdot, self.Omegadot, self.w)


@dataclass(frozen=True)
class JointFrames:
    """What a rotating joint sees, for the maps between cases: ``R_parent``, ``w_parent`` (its body's parent,
    identity and zero for the world), ``R_before``, ``w_before`` (the frame it turns from), ``R_after``,
    ``w_after`` (the frame it turns), ``theta`` (case 3: its angles, else None), ``A``, ``A_dot``."""

    R_parent: np.ndarray
    w_parent: np.ndarray
    R_before: np.ndarray
    w_before: np.ndarray
    R_after: np.ndarray
    w_after: np.ndarray
    A: np.ndarray
    A_dot: np.ndarray


def angular_map(case: int, kind: str, frames: dict, theta=None, theta_dot=None):
    """``(A, A_dot)``: the partial angular velocities of a ball's or free joint's three speeds, ``(n, 3, 3)``.

    The joint's angular velocity relative to the frame it turns from is ``A u_j`` (fixed components):

    * case 1: ``u_j`` in fixed components (free), in the parent body's components (ball):
      ``A = I`` or ``[R_parent]^T``;
    * case 2 (MuJoCo's ``qvel``): in the components of the frame it turns: ``A = [R_after]^T``;
    * case 3: 1-2-3 angle rates, ``A = [R_before]^T [W(theta)]`` (eq. of case 3's partials).

    ``A_dot`` follows from ``d/dt [R]^T = [w~][R]^T`` and ``[W_dot]``. ``frames`` holds the
    :class:`JointFrames` fields (without A); ``theta``, ``theta_dot``: case 3's angles and rates.
    """
    if case == Case.ANGLE_RATES:
        Rb, W = frames["R_before"], w123(theta)
        RW = Rb @ W
        return RW, tilde(frames["w_before"]) @ RW + Rb @ w123_dot(theta, theta_dot)
    if case == Case.BODY_FRAME:
        Ra = frames["R_after"]
        return Ra, tilde(frames["w_after"]) @ Ra
    if kind == "free":
        n = frames["R_after"].shape[0]
        eye = np.broadcast_to(np.eye(3, dtype=frames["R_after"].dtype), (n, 3, 3))
        return eye, np.zeros_like(eye)
    Rp = frames["R_parent"]
    return Rp, tilde(frames["w_parent"]) @ Rp


def rotation_of(case: int, kind: str, qj):
    """The joint's rotation matrix from its coordinates: a quaternion (cases 1-2) or 1-2-3 angles (case 3)."""
    return matrix_from_123(qj) if case == Case.ANGLE_RATES else matrix_from_quaternion(qj)


def walk(tree, case: int, q, u):
    """Every body's frame (after its joints) and every rotating joint's :class:`JointFrames`.

    Args:
        tree: :class:`relacc.Tree`. case: 1, 2 or 3. q: ``(n, nq)`` the case's coordinates (checked).
        u: ``(n, nv)`` its speeds.

    Returns:
        ``(frames, joints)``: a :class:`Frame` per body; ``{joint index: JointFrames}`` for ball and free joints.
    """
    n, nv = q.shape[0], tree.nv
    dtype = np.result_type(q, u, np.float64)
    qadr, dofadr = tree.qadr(case), tree.dofadr
    zeros = lambda: np.zeros((n, 3, nv), dtype=dtype)  # noqa: E731
    eye = np.broadcast_to(np.eye(3, dtype=dtype), (n, 3, 3))
    frames, joints = [], {}
    for b, body in enumerate(tree.bodies):
        parent = frames[body.parent] if body.parent >= 0 else None
        R_parent = eye if parent is None else parent.R
        w_parent = np.zeros((n, 3), dtype=dtype) if parent is None else parent.w
        ks = tree.body_joints[b]
        if body.joints and body.joints[0].type == "free":
            k = ks[0]
            a, d = qadr[k], dofadr[k]
            R = rotation_of(case, "free", q[:, a + 3:a + 3 + (3 if case == Case.ANGLE_RATES else 4)])
            f = Frame(q[:, a:a + 3].astype(dtype), R, zeros(), zeros(), zeros(), zeros(), None)
            f.V[:, :, d:d + 3] = eye
            rec = {"R_parent": eye, "w_parent": np.zeros((n, 3), dtype=dtype), "R_before": eye,
                   "w_before": np.zeros((n, 3), dtype=dtype), "R_after": R}
            if case == Case.BODY_FRAME:  # the frame it turns moves with its own speeds: w_after first
                rec["w_after"] = mv(R, u[:, d + 3:d + 6])
            A, A_dot = angular_map(case, "free", rec, *(
                (q[:, a + 3:a + 6], u[:, d + 3:d + 6]) if case == Case.ANGLE_RATES else ()))
            f.w = mv(A, u[:, d + 3:d + 6])
            rec["w_after"] = f.w
            f.Omega[:, :, d + 3:d + 6] = A
            f.Omegadot[:, :, d + 3:d + 6] = A_dot
            joints[k] = JointFrames(**rec, A=A, A_dot=A_dot)
            frames.append(f)
            continue
        Rb = matrix_from_quaternion(body.quat)
        if parent is None:
            f = Frame(np.broadcast_to(body.pos, (n, 3)).astype(dtype), np.broadcast_to(Rb, (n, 3, 3)).astype(dtype),
                      zeros(), zeros(), zeros(), zeros(), np.zeros((n, 3), dtype=dtype))
        else:
            f = parent.moved(mv(parent.R, np.broadcast_to(body.pos, (n, 3))), parent.R @ Rb)
        for k in ks:
            j = tree.joints[k][1]
            a, d = qadr[k], dofadr[k]
            if j.type == "slide":
                e = mv(f.R, np.broadcast_to(j.axis, (n, 3)))
                r = e * (q[:, a:a + 1] - j.ref)
                V, Vdot = f.point(r, cross(f.w, r) + e * u[:, d:d + 1])
                V[:, :, d] += e
                Vdot[:, :, d] += cross(f.w, e)
                f = Frame(f.o + r, f.R, V, f.Omega, Vdot, f.Omegadot, f.w)
                continue
            anchor = f.moved(mv(f.R, np.broadcast_to(j.pos, (n, 3))))
            Omega, Omegadot = f.Omega.copy(), f.Omegadot.copy()
            if j.type == "hinge":
                e = mv(f.R, np.broadcast_to(j.axis, (n, 3)))
                R = f.R @ matrix_from_quaternion(quaternion_exp(j.axis * (q[:, a:a + 1] - j.ref)))
                A, A_dot = e[:, :, None], cross(f.w, e)[:, :, None]
                w = f.w + e * u[:, d:d + 1]
            else:  # ball
                R = f.R @ rotation_of(case, "ball", q[:, a:a + (3 if case == Case.ANGLE_RATES else 4)])
                rec = {"R_parent": R_parent, "w_parent": w_parent, "R_before": f.R, "w_before": f.w, "R_after": R}
                if case == Case.BODY_FRAME:
                    rec["w_after"] = f.w + mv(R, u[:, d:d + 3])
                rates = (q[:, a:a + 3], u[:, d:d + 3]) if case == Case.ANGLE_RATES else ()
                A, A_dot = angular_map(case, "ball", rec, *rates)
                w = f.w + mv(A, u[:, d:d + 3])
                rec["w_after"] = w
                joints[k] = JointFrames(**rec, A=A, A_dot=A_dot)
            Omega[:, :, d:d + j.nv] += A
            Omegadot[:, :, d:d + j.nv] += A_dot
            turned = Frame(anchor.o, R, anchor.V, Omega, anchor.Vdot, Omegadot, w)
            f = turned.moved(-mv(R, np.broadcast_to(j.pos, (n, 3))))
        frames.append(f)
    return frames, joints
