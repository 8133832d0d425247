"""Energy and momenta of a tree at case-2 states (MuJoCo's ``qpos``, ``qvel``): what a simulation's drift is
measured by.

* kinetic ``T = sum_b 1/2 m_b |v_b|^2 + 1/2 omega_b . I_b omega_b + 1/2 sum_i a_i u_i^2`` (mass centres'
  velocities, angular velocities, armature ``a`` on case-2 speeds: the kinetic energy of ``M``);
* gravity ``V = -sum_b m_b g . r_b`` (zero at the origin);
* springs ``1/2 k (q - rest)^2`` on hinges and slides, ``1/2 k |Log(rest^-1 q)|^2`` on balls
  (the potential of MuJoCo's spring forces, :func:`relacc.dynamics.tree.joint_forces`);
* momenta: linear ``sum_b m_b v_b`` (kg m/s) and angular about the world origin
  ``sum_b r_b x m_b v_b + I_b omega_b`` (kg m^2/s), fixed components.

The springs' energy takes quaternions as they are (an engine that integrates them as coordinates lets their norm
drift by rounding).
"""

from __future__ import annotations

import numpy as np

from relacc.core.so3 import SO3


def spring_energy(tree, q, effects) -> np.ndarray:
    """``(n,)`` J: the joint springs' potential energy of ``effects`` at case-2 coordinates ``q (n, nq)``."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    out = np.zeros(len(q))
    if effects is None:
        return out
    _, joints, _ = effects.resolve(tree)
    qadr = tree.qadr(2)
    for k, eff, rest in joints:
        if not eff.stiffness:
            continue
        kind, a = tree.joints[k][1].type, qadr[k]
        if kind == "ball":
            phi = (SO3(np.broadcast_to(rest, (len(q), 4))).inverse() @ SO3(q[:, a:a + 4])).log()
            out += 0.5 * eff.stiffness * np.sum(phi * phi, axis=1)
        else:
            out += 0.5 * eff.stiffness * (q[:, a] - rest) ** 2
    return out


def tree_energy(tree, q, v, effects=None):
    """``(kinetic, gravity, spring)`` energies ``(n,)`` J at case-2 states ``q (n, nq)``, ``v (n, nv)`` (gravity:
    the effects', else the tree's)."""
    from relacc.core.tree import tree_kinematics

    q, v = np.atleast_2d(np.asarray(q, dtype=float)), np.atleast_2d(np.asarray(v, dtype=float))
    k = tree_kinematics(tree, 2, q, v, backend="reference")
    m = np.array([b.mass for b in tree.bodies])
    I = np.stack([np.asarray(b.inertia, dtype=float) for b in tree.bodies])
    Iw = k.rotation @ I[None] @ np.swapaxes(k.rotation, -1, -2)
    kinetic = 0.5 * (np.einsum("b,nbi,nbi->n", m, k.velocity, k.velocity)
                     + np.einsum("nbi,nbij,nbj->n", k.omega, Iw, k.omega))
    arm = np.concatenate([np.asarray(j.armature, dtype=float) for _, j in tree.joints]) if tree.joints else np.zeros(0)
    kinetic = kinetic + 0.5 * np.einsum("i,ni,ni->n", arm, v, v)
    g = tree.gravity if effects is None or effects.gravity is None else effects.gravity
    gravity = -np.einsum("b,i,nbi->n", m, np.asarray(g, dtype=float), k.position)
    return kinetic, gravity, spring_energy(tree, q, effects)


def tree_momenta(tree, q, v):
    """Linear (kg m/s) and angular (kg m^2/s, about the world origin) momenta ``(n, 3)`` at case-2 states."""
    from relacc.core.tree import tree_kinematics

    q, v = np.atleast_2d(np.asarray(q, dtype=float)), np.atleast_2d(np.asarray(v, dtype=float))
    k = tree_kinematics(tree, 2, q, v, backend="reference")
    m = np.array([b.mass for b in tree.bodies])
    I = np.stack([np.asarray(b.inertia, dtype=float) for b in tree.bodies])
    Iw = k.rotation @ I[None] @ np.swapaxes(k.rotation, -1, -2)
    lin = np.einsum("b,nbi->nbi", m, k.velocity)
    return lin.sum(axis=1), (np.cross(k.position, lin) + np.einsum("nbij,nbj->nbi", Iw, k.omega)).sum(axis=1)
