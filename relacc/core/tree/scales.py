"""The error model on a tree: each body's term magnitudes along its path to the root, and its tolerance.

Part of relacc's one error model (:mod:`relacc.core.tolerances`, :mod:`relacc.core.scales`). A
body's quantity is a sum of terms contributed by the joints on its path to the world; its scale is
the magnitude of those terms, accumulated root first, with

* ``L``: the levers summed along the path (body placements, anchors out and back, slide offsets,
  and, for a mass centre, its offset), m; ``P`` the same plus a free root's ``|p|``;
* ``W``: the joints' angular speeds summed (``|u_j|`` per rotating joint), rad/s; ``A`` their rates;
* ``S``: the translational speeds summed (a free root's ``|p_dot|``, slides' rates), ``S2`` the slides'
  alone; ``Sa`` their rates;

a run of slides on one body with mutually orthogonal axes counts as one vector (its length, as the chain's ``s2'``;
slides that are not orthogonal add their magnitudes). The two-body chain's :func:`relacc.core.scales.term_scales` is
this for its tree's B2 (:meth:`relacc.Tree.from_chain`):

* position ``P``; V ``1 + L``; velocity ``S + L W``; Vdot ``W (1 + L) + S2``;
* acceleration ``Sa + L A + W (W L + 2 S2)``; omega ``W``; alpha ``A + W^2``; Omega 1; Omegadot ``W``.

The tolerance of a body's normalized error is ``c eps d`` (:func:`tree_tolerance`): ``c`` the
chain's rounding factor (it covers one joint's transforms and their sums), ``d`` the number of
joints between the body and the world (:attr:`relacc.Tree.depth`): each joint composes one more
rotation and adds one more lever, so rounding grows linearly along the path.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from relacc.core.tolerances import EPS, ROUNDING_FACTOR
from relacc.core.tree.model import AXIS_TOLERANCE


@dataclass(frozen=True)
class TreeScales:
    """Per body term magnitudes, each ``(..., nb)`` in the quantity's units (see the module docstring)."""

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    V: np.ndarray
    Vdot: np.ndarray
    Omega: np.ndarray
    Omegadot: np.ndarray

    def of(self, quantity: str) -> np.ndarray:
        """The scale of a quantity by name (``"position"``, ..., ``"Omegadot"``)."""
        return getattr(self, quantity)


def tree_tolerance(tree) -> np.ndarray:
    """``(nb,)`` tolerance on each body's normalized error: ``ROUNDING_FACTOR * eps * depth``."""
    return ROUNDING_FACTOR * EPS * np.asarray(tree.depth, dtype=float)


def tree_scales(tree, case, q, u, udot=None, *, at=None) -> TreeScales:
    """Per body term magnitudes of a case's state (see the module docstring).

    Args:
        tree: :class:`relacc.Tree`. case: 1, 2 or 3. q ``(..., nq)``, u ``(..., nv)``, udot ``(..., nv)`` or None
            (acceleration and alpha scales 0).
        at: per body, the offset ``(3,)`` (body frame, m) of the point the scale is for; default the mass centre.
    """
    c = int(case)
    q, u = np.asarray(q), np.asarray(u)
    n = lambda a: np.linalg.norm(np.real(a), axis=-1)  # noqa: E731
    batch = np.broadcast_shapes(q.shape[:-1], u.shape[:-1])
    zero = np.zeros(batch)
    ud = None if udot is None else np.asarray(udot)
    qadr, dofadr = tree.qadr(c), tree.dofadr
    acc = {k: [] for k in ("P", "L", "W", "A", "S", "S2", "Sa")}
    out = {k: [] for k in ("position", "velocity", "acceleration", "omega", "alpha", "V", "Vdot", "Omega",
                           "Omegadot")}
    for b, body in enumerate(tree.bodies):
        p = body.parent
        P, L, W, A, S, S2, Sa = ((acc[k][p] if p >= 0 else zero) for k in ("P", "L", "W", "A", "S", "S2", "Sa"))
        P, L = P + n(body.pos), L + n(body.pos)
        for group in _joint_groups(tree, b):
            j, k = tree.joints[group[0]][1], group[0]
            qa, d = qadr[k], dofadr[k]
            if j.type == "free":  # the body's pose is its own: nothing of the parent's path remains
                P, L, S2 = n(q[..., qa:qa + 3]) + zero, zero, zero
                S, W = n(u[..., d:d + 3]) + zero, n(u[..., d + 3:d + 6]) + zero
                Sa, A = (zero, zero) if ud is None else (n(ud[..., d:d + 3]) + zero, n(ud[..., d + 3:d + 6]) + zero)
            elif j.type == "slide":  # one slide, or orthogonal slides in a row: one displacement vector
                s = n(np.stack([q[..., qadr[i]] - tree.joints[i][1].ref for i in group], axis=-1))
                rate = n(np.stack([u[..., dofadr[i]] for i in group], axis=-1))
                P, L = P + s, L + s
                S, S2 = S + rate, S2 + rate
                if ud is not None:
                    Sa = Sa + n(np.stack([ud[..., dofadr[i]] for i in group], axis=-1))
            else:
                lever = 2 * n(j.pos)
                P, L = P + lever, L + lever
                block = slice(d, d + j.nv)
                W = W + n(u[..., block])
                if ud is not None:
                    A = A + n(ud[..., block])
        for key, value in zip(("P", "L", "W", "A", "S", "S2", "Sa"), (P, L, W, A, S, S2, Sa)):
            acc[key].append(value)
        off = n(body.com if at is None else np.asarray(at[b]))
        Pc, Lc = P + off, L + off
        out["position"].append(Pc)
        out["V"].append(1 + Lc)
        out["velocity"].append(S + Lc * W)
        out["Vdot"].append(W * (1 + Lc) + S2)
        out["acceleration"].append(Sa + Lc * A + W * (W * Lc + 2 * S2) if ud is not None else zero)
        out["omega"].append(W)
        out["alpha"].append(A + W * W if ud is not None else zero)
        out["Omega"].append(np.ones(batch))
        out["Omegadot"].append(W)
    return TreeScales(**{k: np.stack(np.broadcast_arrays(*v), axis=-1) for k, v in out.items()})


def _joint_groups(tree, b) -> list[list[int]]:
    """A body's joints in order as groups of joint indices: a run of slides with mutually orthogonal axes is one group
    (their displacements are the orthogonal components of one vector, as the chain's ``s2'``: its length is the
    magnitude of their terms, each component rounded on its own); every other joint is a group of its own. Slides
    that are not orthogonal stay apart (their terms can cancel, so their magnitudes add)."""
    groups: list[list[int]] = []
    for k in tree.body_joints[b]:
        j = tree.joints[k][1]
        last = groups[-1] if groups else None
        if (j.type == "slide" and last is not None and tree.joints[last[0]][1].type == "slide"
                and all(abs(float(j.axis @ tree.joints[i][1].axis)) <= AXIS_TOLERANCE for i in last)):
            last.append(k)
        else:
            groups.append([k])
    return groups


def extent(tree) -> float:
    """The tree's size ``L`` (m): the largest distance between two mass centres at the reference configuration, at
    least 1 mm."""
    from relacc.core.tree.coordinates import reference_q
    from relacc.core.tree.kinematics import tree_kinematics

    p = np.asarray(tree_kinematics(tree, 2, reference_q(tree, 2), np.zeros(tree.nv), partials=False).position)
    return max(1e-3, float(np.max(np.linalg.norm(p[:, None] - p[None], axis=-1))) if len(p) else 1e-3)


def velocity_terms(tree, q2, u2, size: float) -> np.ndarray:
    """``(n,)`` the magnitude of the velocity-product terms that make up the generalized forces before they cancel
    (N m or N per speed) at case-2 states: ``sum_b m_b |omega_b| (|v_b| + |omega_b| L) L + ||I_b|| |omega_b|^2`` (a
    body's Coriolis and centrifugal force through a lever up to the tree's ``size`` ``L``, and its gyroscopic
    torque). A hinge spinning about a principal axis has none in ``f``, yet every engine forms ``omega x I omega``
    and rounds it; a symmetric state cancels them between bodies."""
    from relacc.core.tree.kinematics import tree_kinematics

    k = tree_kinematics(tree, 2, np.atleast_2d(q2), np.atleast_2d(u2), partials=False)
    w = np.linalg.norm(np.asarray(k.omega), axis=-1)
    v = np.linalg.norm(np.asarray(k.velocity), axis=-1)
    m = np.array([b.mass for b in tree.bodies])
    inertia = np.array([np.linalg.norm(b.inertia, 2) for b in tree.bodies])
    return np.sum(m * w * (v + w * size) * size + inertia * w * w, axis=-1)
