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

from relacc.core.rotations import quaternion_from_123
from relacc.core.so3 import SO3
from relacc.errors import InputError


def spring_energy(tree, q, effects, case: int = 2) -> np.ndarray:
    """``(n,)`` J: the joint springs' potential energy of ``effects`` at a case's coordinates ``q (n, nq)`` (case 2
    by default; real or complex)."""
    q = np.atleast_2d(np.asarray(q))
    out = np.zeros(len(q), dtype=np.result_type(q, float))
    if effects is None:
        return out
    _, joints, _ = effects.resolve(tree)
    qadr = tree.qadr(case)
    for k, eff, rest in joints:
        if not eff.stiffness:
            continue
        kind, a = tree.joints[k][1].type, qadr[k]
        if kind == "ball":
            if np.iscomplexobj(q):
                raise InputError(f"a ball's spring energy (joint {tree.joints[k][1].name!r}) takes real coordinates: "
                                 "its rotation's logarithm is not complex-analytic as computed")
            x = quaternion_from_123(q[:, a:a + 3]) if int(case) == 3 else q[:, a:a + 4]
            phi = (SO3(np.broadcast_to(rest, (len(q), 4))).inverse() @ SO3(x)).log()
            out = out + 0.5 * eff.stiffness * np.sum(phi * phi, axis=1)
        else:
            out = out + 0.5 * eff.stiffness * (q[:, a] - rest) ** 2
    return out


def _motion(tree, q, v, case):
    """Each body's kinematics (the compiled walk; the reference walk for complex inputs), masses and inertias in fixed
    components."""
    from relacc.core.tree import tree_kinematics

    q, v = np.atleast_2d(np.asarray(q)), np.atleast_2d(np.asarray(v))
    complex_step = np.iscomplexobj(q) or np.iscomplexobj(v)  # the compiled walk takes real inputs only
    k = tree_kinematics(tree, case, q, v, partials=False, backend="reference" if complex_step else "auto")
    m = np.array([b.mass for b in tree.bodies])
    I = np.stack([np.asarray(b.inertia, dtype=float) for b in tree.bodies])
    return q, v, k, m, k.rotation @ I[None] @ np.swapaxes(k.rotation, -1, -2)


def tree_energy(tree, q, v, effects=None, case: int = 2):
    """``(kinetic, gravity, spring)`` energies ``(n,)`` J at a case's states ``q (n, nq)``, ``v (n, nv)`` (case 2,
    MuJoCo's ``qpos``, ``qvel``, by default; real or complex; gravity: the effects', else the tree's).

    Raises:
        InputError: in case 1 or 3, armature on a ball or free joint's rotation (it acts on case-2 speeds).
    """
    q, v, k, m, Iw = _motion(tree, q, v, case)
    kinetic = 0.5 * (np.einsum("b,nbi,nbi->n", m, k.velocity, k.velocity)
                     + np.einsum("nbi,nbij,nbj->n", k.omega, Iw, k.omega))
    arm = np.concatenate([np.asarray(j.armature, dtype=float) for _, j in tree.joints]) if tree.joints else np.zeros(0)
    if int(case) != 2:
        for (_, j), d in zip(tree.joints, tree.dofadr):
            if j.type in ("ball", "free") and np.any(arm[d + (3 if j.type == "free" else 0):d + j.nv]):
                raise InputError(f"energy in case {int(case)}: joint {j.name!r} has armature on its rotation, which "
                                 "acts on case-2 speeds; give case-2 states")
    kinetic = kinetic + 0.5 * np.einsum("i,ni,ni->n", arm, v, v)
    g = tree.gravity if effects is None or effects.gravity is None else effects.gravity
    gravity = -np.einsum("b,i,nbi->n", m, np.asarray(g, dtype=float), k.position)
    return kinetic, gravity, spring_energy(tree, q, effects, case)


def tree_momenta(tree, q, v, case: int = 2):
    """Linear (kg m/s) and angular (kg m^2/s, about the world origin) momenta ``(n, 3)``, fixed components, at a case's
    states (case 2 by default; real or complex)."""
    q, v, k, m, Iw = _motion(tree, q, v, case)
    lin = np.einsum("b,nbi->nbi", m, k.velocity)
    return lin.sum(axis=1), (np.cross(k.position, lin) + np.einsum("nbij,nbj->nbi", Iw, k.omega)).sum(axis=1)
