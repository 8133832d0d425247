"""Random kinematic trees as MJCF text, for tests against MuJoCo (numpy.random.default_rng(seed))."""

from __future__ import annotations

import numpy as np

STACKS = (("ball",), ("hinge",), ("slide",), ("hinge", "hinge"), ("slide", "hinge"),
          ("slide", "slide", "slide", "ball"), ("hinge", "ball"), ("ball", "slide"), ())
"""Joint stacks a non-root body may get (the last: welded to its parent)."""


def _unit(rng, n=3):
    v = rng.standard_normal(n)
    return v / np.linalg.norm(v)


def _f(v):
    return " ".join(repr(float(x)) for x in np.atleast_1d(v))


def random_mjcf(seed: int, n_bodies: int, *, free_root: bool = True, scale: float = 1.0, chain: bool = False,
                light: float | None = None) -> str:
    """An MJCF of ``n_bodies`` bodies with random placements, anchors, axes and inertial frames.

    Body 0 is the root (free when ``free_root``, else a ball at the world); each later body hangs on a
    random earlier body (the previous one with ``chain``) with a random stack of :data:`STACKS`. Masses
    are 0.1 to 2 kg (``light`` kg and inertia ``light`` times as small for every body but the root),
    principal moments satisfy the triangle inequality. Lengths are scaled by ``scale`` (m).
    """
    rng = np.random.default_rng(seed)
    parents = [-1] + [b - 1 if chain else int(rng.integers(0, b)) for b in range(1, n_bodies)]
    children = {b: [c for c in range(n_bodies) if parents[c] == b] for b in range(-1, n_bodies)}

    def inertial(root):
        a, b = rng.uniform(0.05, 1.0, 2)
        c = rng.uniform(abs(a - b) + 1e-3, a + b - 1e-3)
        mass, factor = rng.uniform(0.1, 2.0), 0.1
        if light is not None and not root:
            mass, factor = light, 0.1 * light
        return (f'<inertial pos="{_f(scale * rng.uniform(-0.3, 0.3, 3))}" quat="{_f(_unit(rng, 4))}" '
                f'mass="{mass!r}" diaginertia="{_f(np.array([a, b, c]) * factor)}"/>')

    def body(b, depth):
        pad = "  " * depth
        if b == 0:
            joints = ['<freejoint name="root"/>'] if free_root else ['<joint name="root" type="ball"/>']
            pos = scale * rng.uniform(-0.5, 0.5, 3)
        else:
            stack = STACKS[int(rng.integers(0, len(STACKS)))]
            joints = []
            for i, kind in enumerate(stack):
                extra = "" if kind == "ball" else f' axis="{_f(_unit(rng))}"'
                if kind == "hinge":
                    extra += f' ref="{rng.uniform(-0.5, 0.5)!r}"'
                joints.append(f'<joint name="j{b}_{i}" type="{kind}" pos="{_f(scale * rng.uniform(-0.2, 0.2, 3))}"'
                              f'{extra}/>')
            pos = scale * rng.uniform(-0.6, 0.6, 3)
        head = f'{pad}<body name="b{b}" pos="{_f(pos)}" quat="{_f(_unit(rng, 4))}">'
        inner = [pad + "  " + line for line in joints + [inertial(b == 0)]]
        inner += [body(c, depth + 1) for c in children[b]]
        return "\n".join([head] + inner + [f"{pad}</body>"])

    return (f'<mujoco model="random{seed}">\n  <compiler angle="radian" autolimits="true"/>\n'
            f'  <option gravity="0.3 -0.2 -9.81"/>\n  <worldbody>\n{body(0, 2)}\n  </worldbody>\n</mujoco>\n')


def mujoco_reference(model, q, u, udot):
    """MuJoCo's own numbers at states ``q (n, nq)``, ``u``, ``udot (n, nv)`` (case 2): per body (MuJoCo's order,
    the world left out) ``position`` (``xipos``), ``velocity``, ``omega`` (``mj_jac`` times ``u``), ``acceleration``,
    ``alpha`` (MuJoCo's acceleration routine, ``mj_rnePostConstraint``'s ``cacc`` at the mass centre, made classical),
    ``J``, ``Jr`` (``mj_jac``), ``Jdot``, ``Jrdot`` (``mj_jacDot``), and ``M`` (``mj_fullM``), ``bias``
    (``qfrc_bias``: Coriolis, centrifugal and gravity).

    Gravity is zeroed for the accelerations (``cacc`` includes ``-g``) and kept for ``bias``.
    """
    import mujoco

    from relacc.engines.mujoco_.adapter import full_inertia

    m, d = model, mujoco.MjData(model)
    n, nb = q.shape[0], m.nbody - 1
    out = {k: np.zeros((n, nb, 3)) for k in ("position", "velocity", "omega", "acceleration", "alpha")}
    out.update({k: np.zeros((n, nb, 3, m.nv)) for k in ("J", "Jr", "Jdot", "Jrdot")})
    out["M"], out["bias"] = np.zeros((n, m.nv, m.nv)), np.zeros((n, m.nv))
    gravity = m.opt.gravity.copy()
    for i in range(n):
        d.qpos[:], d.qvel[:], d.qacc[:] = q[i], u[i], udot[i]
        m.opt.gravity[:] = gravity
        mujoco.mj_fwdPosition(m, d)
        mujoco.mj_fwdVelocity(m, d)
        full_inertia(m, d, out["M"][i])  # mj_fullM in this MuJoCo version's call form
        out["bias"][i] = d.qfrc_bias
        m.opt.gravity[:] = 0.0
        mujoco.mj_rnePostConstraint(m, d)
        for b in range(1, m.nbody):
            J, Jr, Jd, Jrd = (out[k][i, b - 1] for k in ("J", "Jr", "Jdot", "Jrdot"))
            mujoco.mj_jac(m, d, J, Jr, d.xipos[b], b)
            mujoco.mj_jacDot(m, d, Jd, Jrd, d.xipos[b], b)
            r = d.xipos[b] - d.subtree_com[m.body_rootid[b]]  # cacc, cvel: spatial, at the root's subtree COM
            w, alpha = d.cvel[b, :3], d.cacc[b, :3]
            out["position"][i, b - 1] = d.xipos[b]
            out["velocity"][i, b - 1] = J @ u[i]
            out["omega"][i, b - 1] = Jr @ u[i]
            out["alpha"][i, b - 1] = alpha
            v = d.cvel[b, 3:] - np.cross(r, w)  # the mass centre's velocity
            out["acceleration"][i, b - 1] = d.cacc[b, 3:] - np.cross(r, alpha) + np.cross(w, v)
    m.opt.gravity[:] = gravity
    return out


def jacdot_exact(model) -> np.ndarray:
    """``(nb,)`` whether MuJoCo's ``mj_jacDot`` is the true time derivative for each body (MuJoCo's order, no world).

    ``mj_jacDot`` takes a ball's (or free joint's) columns from the velocity of the whole body, so a slide
    after a ball on the same body adds ``v_slide x omega_ball`` to ``J_dot v`` of that body and its
    descendants (relacc's finding, ``tests/test_tree.py::test_mujoco_jacdot_after_a_ball_and_a_slide``).
    """
    import mujoco

    m = model
    bad = np.zeros(m.nbody, bool)
    for b in range(1, m.nbody):
        kinds = [int(m.jnt_type[j]) for j in range(m.body_jntadr[b], m.body_jntadr[b] + m.body_jntnum[b])]
        ball = mujoco.mjtJoint.mjJNT_BALL
        after_ball = ball in kinds and mujoco.mjtJoint.mjJNT_SLIDE in kinds[kinds.index(ball) + 1:]
        bad[b] = after_ball or bad[m.body_parentid[b]]
    return ~bad[1:]


def passive_off() -> int:
    """MuJoCo's disable flags for every passive force: ``mjDSBL_SPRING | mjDSBL_DAMPER`` from 3.3.6,
    ``mjDSBL_PASSIVE`` before (measured release by release)."""
    import mujoco

    D = mujoco.mjtDisableBit
    return int(D.mjDSBL_SPRING | D.mjDSBL_DAMPER) if hasattr(D, "mjDSBL_SPRING") else int(D.mjDSBL_PASSIVE)


def _mujoco_version() -> tuple:
    import mujoco

    return tuple(int("".join(c for c in p if c.isdigit()) or 0) for p in mujoco.__version__.split(".")[:3])


def rk4_as_textbook():
    """For the tests that hold MuJoCo's RK4 trajectories to relacc's and Pinocchio's at 1e-9: MuJoCo 3.x's RK4 is not
    the same scheme (measured, 3.14.0 to 3.17.0: 7.7e-9 from 4.0.0 after 1000 steps of the note's chain tumbling,
    where relacc and Pinocchio agree with 4.0.0 to rounding); from 4.0.0 it is. Strict: such a test must fail on 3.x,
    so a 3.x that agreed would be news."""
    import pytest

    return pytest.mark.xfail(_mujoco_version() < (4, 0, 0), strict=True,
                             reason="MuJoCo 3.x's RK4 differs from the textbook scheme by ~1e-8 over 1000 steps")
