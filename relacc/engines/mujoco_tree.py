"""MJCF and URDF files as relacc trees, read through MuJoCo's compiler: :func:`read_tree`.

The reading is ``relacc compare``'s reference (:func:`relacc.engines.robots.mujoco_.load_spec`,
``compile_spec``): includes, default classes, ``<compiler>`` settings (``angle``, ``eulerseq``,
``settotalmass``, ``inertiafromgeom``, ``fusestatic``, ...) are resolved by MuJoCo, and the tree takes the
compiled model's numbers: bodies in MuJoCo's order, their placement ``body_pos``/``body_quat``, joints'
``jnt_pos``/``jnt_axis``, ``qpos0`` as hinges' and slides' ``ref``, ``dof_armature``, the inertia
``body_ipos``, ``body_mass`` and ``body_inertia`` turned by ``body_iquat`` into body components, and the
gravity of ``<option>`` (zero when the model disables gravity). Named points: every site, and every
body the compiler fused into another (``fusestatic``, the default for URDF: a URDF's fixed links), at
its place in the body it was fused into.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from relacc.core.rotations import matrix_from_quaternion
from relacc.core.tree.model import Body, Joint, Point, Tree
from relacc.engines.mujoco_ import captured_warnings
from relacc.engines.robots.mujoco_ import TYPES, compile_spec, load_spec
from relacc.errors import ModelError


def tree_of(model, name: str = "", source: str = "", fused: tuple = ()) -> Tree:
    """A compiled ``MjModel`` as a :class:`relacc.Tree` (see the module docstring); ``fused``: extra points."""
    m = model
    body_name = lambda b: m.body(b).name or f"body {b}"  # noqa: E731
    bodies = []
    for b in range(1, m.nbody):
        joints = []
        for j in range(int(m.body_jntadr[b]), int(m.body_jntadr[b] + m.body_jntnum[b])):
            kind = TYPES[int(m.jnt_type[j])]
            d = int(m.jnt_dofadr[j])
            nv = {"free": 6, "ball": 3}.get(kind, 1)
            joints.append(Joint(m.joint(j).name or f"joint {j}", kind, pos=m.jnt_pos[j].copy(),
                                axis=m.jnt_axis[j].copy() if kind in ("hinge", "slide") else (0.0, 0.0, 1.0),
                                ref=float(m.qpos0[m.jnt_qposadr[j]]) if kind in ("hinge", "slide") else 0.0,
                                armature=m.dof_armature[d:d + nv].copy()))
        R = matrix_from_quaternion(m.body_iquat[b])
        inertia = R @ np.diag(m.body_inertia[b]) @ R.T
        bodies.append(Body(body_name(b), int(m.body_parentid[b]) - 1, pos=m.body_pos[b].copy(),
                           quat=m.body_quat[b].copy(), joints=tuple(joints), mass=float(m.body_mass[b]),
                           com=m.body_ipos[b].copy(), inertia=0.5 * (inertia + inertia.T)))
    points = [Point(m.site(s).name or f"site {s}", int(m.site_bodyid[s]) - 1, m.site_pos[s].copy())
              for s in range(m.nsite)]
    taken = {p.name for p in points}
    points += [p for p in fused if p.name not in taken]
    gravity = np.zeros(3) if m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY else m.opt.gravity.copy()
    return Tree(name, tuple(bodies), gravity=gravity, points=tuple(points), source=source)


def _fused_points(spec, model, path) -> tuple:
    """Bodies the compiler fused away (``fusestatic``), as points of the body that took them."""
    kept = {model.body(b).name for b in range(model.nbody)}
    whole = spec.copy()
    whole.compiler.fusestatic = False
    try:
        full, _ = compile_spec(whole, path)
    except Exception:  # noqa: BLE001 - the fused model compiled; without fusing there is nothing to add
        return ()
    if full.nbody == model.nbody:
        return ()
    data = mujoco.MjData(full)
    mujoco.mj_kinematics(full, data)
    points = []
    for b in range(1, full.nbody):
        name = full.body(b).name
        if not name or name in kept:
            continue
        anc = int(full.body_parentid[b])
        while anc and full.body(anc).name not in kept:
            anc = int(full.body_parentid[anc])
        R = data.xmat[anc].reshape(3, 3)
        rel = R.T @ (data.xpos[b] - data.xpos[anc])
        into = full.body(anc).name if anc else None
        at = -1 if into is None else [model.body(i).name for i in range(1, model.nbody)].index(into)
        points.append(Point(name, at, rel))
    return tuple(points)


def read_tree(path) -> Tree:
    """Read an MJCF (``.xml``) or URDF (``.urdf``) file into a :class:`relacc.Tree` through MuJoCo's compiler.

    Raises:
        ModelError: MuJoCo cannot read or compile the file (its message names the element).
    """
    path = Path(path)
    with captured_warnings():
        spec = load_spec(path)
        model, _ = compile_spec(spec.copy(), path)
        fused = _fused_points(spec, model, path)
    if model.nbody < 2:
        raise ModelError(f"{path}: MuJoCo reads no body besides the world in it: there is nothing to evaluate")
    return tree_of(model, spec.modelname or path.stem, str(path), fused)


def model_for(tree):
    """The compiled ``MjModel`` a tree was read from (its source file; a chain TOML's generated MJCF).

    Raises:
        EngineError: a tree built in Python, which MuJoCo has never read.
    """
    from relacc.errors import EngineError

    source = Path(tree.source) if tree.source != "python" else None
    if source is not None and source.suffix.lower() == ".toml":
        from relacc.fixtures import load

        source = load(source).path("two_body.xml")
    if source is None or not source.is_file():
        raise EngineError(f"tree {tree.name!r} was built in Python: MuJoCo has no model of it (read it from a file "
                          "to compare with MuJoCo)")
    with captured_warnings():
        model, _ = compile_spec(load_spec(source), source)
    return model


def evaluate(tree, q, u, udot) -> dict:
    """MuJoCo's own numbers for every body at states ``q (n, nq)``, ``u``, ``udot (n, nv)`` (MuJoCo's, case 2).

    ``position`` (``xipos``), ``velocity``, ``omega`` (``mj_jac`` at the mass centre times ``u``), ``V``, ``Omega``
    (``mj_jac``), ``acceleration``, ``alpha`` (MuJoCo's acceleration routine ``mj_rnePostConstraint`` at zero
    gravity: ``cacc`` moved to the mass centre, made classical by ``omega x v``); fixed-frame components,
    ``(n, nb, 3)`` and ``(n, nb, 3, nv)``.
    """
    m = model_for(tree)
    d = mujoco.MjData(m)
    n, nb = len(q), m.nbody - 1
    out = {k: np.zeros((n, nb, 3)) for k in ("position", "velocity", "omega", "acceleration", "alpha")}
    out.update({k: np.zeros((n, nb, 3, m.nv)) for k in ("V", "Omega")})
    m.opt.gravity[:] = 0.0
    for i in range(n):
        d.qpos[:], d.qvel[:], d.qacc[:] = q[i], u[i], udot[i]
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        mujoco.mj_comVel(m, d)
        mujoco.mj_rnePostConstraint(m, d)
        for b in range(1, m.nbody):
            J, Jr = out["V"][i, b - 1], out["Omega"][i, b - 1]
            mujoco.mj_jac(m, d, J, Jr, d.xipos[b], b)
            r = d.xipos[b] - d.subtree_com[m.body_rootid[b]]
            w, alpha = d.cvel[b, :3], d.cacc[b, :3]
            out["position"][i, b - 1] = d.xipos[b]
            out["velocity"][i, b - 1], out["omega"][i, b - 1] = J @ u[i], Jr @ u[i]
            out["alpha"][i, b - 1] = alpha
            out["acceleration"][i, b - 1] = (d.cacc[b, 3:] - np.cross(r, alpha)
                                             + np.cross(w, d.cvel[b, 3:] - np.cross(r, w)))
    return out


def jacobian_loop(tree, q, u):
    """The benchmarks' MuJoCo anchor: a closure looping over the states with ``mj_kinematics``, ``mj_comPos``,
    ``mj_comVel``, then ``mj_jac`` and ``mj_jacDot`` at every body's mass centre, stored into ``(n, nb, 3, nv)``
    arrays (translational and rotational), as a user collecting every body's would."""
    m = model_for(tree)
    d = mujoco.MjData(m)
    n, nb = len(q), m.nbody - 1
    J, Jr, Jd, Jrd = (np.empty((n, nb, 3, m.nv)) for _ in range(4))

    def run():
        for i in range(n):
            d.qpos[:], d.qvel[:] = q[i], u[i]
            mujoco.mj_kinematics(m, d)
            mujoco.mj_comPos(m, d)
            mujoco.mj_comVel(m, d)
            for b in range(1, m.nbody):
                mujoco.mj_jac(m, d, J[i, b - 1], Jr[i, b - 1], d.xipos[b], b)
                mujoco.mj_jacDot(m, d, Jd[i, b - 1], Jrd[i, b - 1], d.xipos[b], b)

    return run


def version() -> str:
    return mujoco.__version__
