"""A robot model in MuJoCo: the reference of ``relacc compare`` (its coordinates are the common ones).

Imports only ``mujoco``. The model is read with ``mujoco.MjSpec.from_file`` and compiled; the spec
is kept, so that a comparison can recompile the model with one engine's reading of the file applied
(:meth:`MujocoRobot.recompiled`) and see whether MuJoCo then gives that engine's numbers.

Dynamics: ``M`` by ``mj_fullM`` (armature included, as MuJoCo's ``qM``); the bias by ``mj_rne``
without accelerations (Coriolis, centrifugal, gravity); gravity alone by ``mj_rne`` at zero speeds;
forward dynamics by ``mj_solveM`` on ``-bias``: MuJoCo's smooth dynamics without passive forces,
actuators or constraints, which are not rigid-body dynamics and differ between engines by design.
MuJoCo's warnings while compiling are collected (:attr:`MujocoRobot.warnings`), not printed.
"""

from __future__ import annotations

import warnings as warnings_module
from pathlib import Path

import mujoco
import numpy as np

from relacc.engines.mujoco_ import full_inertia
from relacc.engines.robots.base import Dynamics, Joint, Link, LinkKinematics, Robot, Structure, combine
from relacc.errors import ModelError

TYPES = {int(mujoco.mjtJoint.mjJNT_FREE): "free", int(mujoco.mjtJoint.mjJNT_BALL): "ball",
         int(mujoco.mjtJoint.mjJNT_SLIDE): "slide", int(mujoco.mjtJoint.mjJNT_HINGE): "hinge"}


def load_spec(path) -> "mujoco.MjSpec":
    """The file's ``MjSpec`` (MuJoCo's parse: includes and default classes resolved).

    Raises:
        ModelError: a missing file or MuJoCo's parser message (it names the element and line).
    """
    path = Path(path)
    if not path.is_file():
        raise ModelError(f"{path}: no such file")
    try:
        return mujoco.MjSpec.from_file(str(path))
    except Exception as exc:  # mujoco raises ValueError with the parser's message
        raise ModelError(f"{path}: MuJoCo cannot read it: {' '.join(str(exc).split())}") from None


def compile_spec(spec, path) -> tuple["mujoco.MjModel", list[str]]:
    """``(model, warnings)``: the compiled spec and MuJoCo's warnings while compiling (e.g. missing meshes raise)."""
    try:
        with warnings_module.catch_warnings(record=True) as caught:  # MuJoCo's Python bindings warn through here
            warnings_module.simplefilter("always")
            model = spec.compile()
    except Exception as exc:
        raise ModelError(f"{path}: MuJoCo cannot compile it: {' '.join(str(exc).split())}") from None
    return model, [" ".join(str(w.message).split()) for w in caught]


def rigid_groups(model) -> dict[int, list[int]]:
    """``{moving body: [it and the bodies welded to it]}``; bodies welded to the world are left out."""
    head = {0: 0}
    groups: dict[int, list[int]] = {}
    for b in range(1, model.nbody):
        head[b] = b if model.body_jntnum[b] > 0 else head[int(model.body_parentid[b])]
        if head[b]:
            groups.setdefault(head[b], []).append(b)
    return groups


class MujocoRobot(Robot):
    """A model file in MuJoCo (the reference): every speed is shared with itself."""

    engine = "mujoco"

    def __init__(self, path, spec=None):
        self.path = Path(path)
        self.spec = load_spec(path) if spec is None else spec
        # a copy is compiled: compiling edits a spec in place where it fuses static bodies (compiler fusestatic,
        # the default for URDF), and the readings are applied to the spec as the file has it
        self.model, self.warnings = compile_spec(self.spec.copy(), self.path)
        self.data = mujoco.MjData(self.model)
        m = self.model
        self.dofs, self.qdofs = np.arange(m.nv), np.arange(m.nq)
        self.extra_dofs = 0
        self.groups = rigid_groups(m)
        self.joint_names = [m.joint(j).name or f"joint {j}" for j in range(m.njnt)]
        self.structure = self._structure()

    def recompiled(self, change) -> "MujocoRobot":
        """This model compiled again after ``change(spec)`` on a copy of its spec (the file is not touched)."""
        spec = self.spec.copy()
        change(spec)
        return MujocoRobot(self.path, spec)

    def body_name(self, b) -> str:
        return self.model.body(b).name or f"body {b}"

    def _at(self, q, v=None):
        d = self.data
        d.qpos[:] = q
        d.qvel[:] = 0.0 if v is None else v
        mujoco.mj_kinematics(self.model, d)
        mujoco.mj_comPos(self.model, d)
        mujoco.mj_comVel(self.model, d)
        return d

    def _link(self, b, d) -> Link:
        m = self.model
        parts = [(float(m.body_mass[c]), d.xipos[c].copy(),
                  d.ximat[c].reshape(3, 3) @ np.diag(m.body_inertia[c]) @ d.ximat[c].reshape(3, 3).T)
                 for c in self.groups[b]]
        mass, com, inertia = combine(parts)
        return Link(self.body_name(b), tuple(self.body_name(c) for c in self.groups[b]), mass, com, inertia)

    def _structure(self) -> Structure:
        m = self.model
        d = self._at(m.qpos0)
        joints = []
        for j in range(m.njnt):
            kind, a = TYPES[int(m.jnt_type[j])], int(m.jnt_dofadr[j])
            n = {"free": 6, "ball": 3}.get(kind, 1)
            axis = d.xaxis[j].copy() if kind in ("hinge", "slide") else None
            anchor = d.xanchor[j].copy()
            if kind == "hinge":  # the point of the axis nearest the world origin
                anchor = anchor - (anchor @ axis) * axis
            joints.append(Joint(self.joint_names[j], kind, self.body_name(m.jnt_bodyid[j]), axis,
                                None if kind == "slide" else anchor,
                                m.dof_armature[a:a + n].copy(), m.dof_damping[a:a + n].copy()))
        links = tuple(self._link(b, d) for b in self.groups)
        gravity = np.zeros(3) if m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY else m.opt.gravity.copy()
        return Structure(m.nq, m.nv, tuple(joints), links, gravity, float(m.body_mass[1:].sum()),
                         tuple(self.body_name(b) for b in range(1, m.nbody)))

    def reference(self) -> np.ndarray:
        """``(nq,)`` the reference configuration: MuJoCo's ``qpos0`` (joint ``ref`` values, unit quaternions)."""
        return self.model.qpos0.copy()

    def dynamics(self, q, v) -> Dynamics:
        m, d = self.model, self._at(q, v)
        M = np.zeros((m.nv, m.nv))
        mujoco.mj_crb(m, d)
        full_inertia(m, d, M)
        bias, gravity = np.zeros(m.nv), np.zeros(m.nv)
        mujoco.mj_rne(m, d, 0, bias)
        self._at(q)
        mujoco.mj_rne(m, d, 0, gravity)
        self._at(q, v)
        mujoco.mj_factorM(m, d)
        forward = np.zeros(m.nv)
        mujoco.mj_solveM(m, d, forward.reshape(1, -1), -bias.reshape(1, -1))
        return Dynamics(M, bias, gravity, forward)

    def kinematics(self, q, v, a, links) -> LinkKinematics:
        """Each link's centre of mass: ``mj_jac``, ``mj_jacDot`` at that point of its moving body.

        The classical acceleration is ``J a + J_dot v`` from those.
        """
        m, d = self.model, self._at(q, v)
        names = {self.body_name(b): b for b in self.groups}
        n = len(links)
        pos, J, Jdv, acc = np.zeros((n, 3)), np.zeros((n, 3, m.nv)), np.zeros((n, 3)), np.zeros((n, 3))
        for i, name in enumerate(links):
            b = names[name]
            mass = sum(m.body_mass[c] for c in self.groups[b])
            pos[i] = sum(m.body_mass[c] * d.xipos[c] for c in self.groups[b]) / mass
            jdot = np.zeros((3, m.nv))
            mujoco.mj_jac(m, d, J[i], None, pos[i], b)
            mujoco.mj_jacDot(m, d, jdot, None, pos[i], b)
            Jdv[i] = jdot @ v
            acc[i] = J[i] @ a + Jdv[i]
        return LinkKinematics(pos, J, Jdv, acc)

    def rne_kinematics(self, q, v, a, links) -> LinkKinematics:
        """As :meth:`kinematics`, but ``J_dot v`` and the classical acceleration from MuJoCo's acceleration routine
        (``mj_rnePostConstraint``'s ``cacc``, at zero gravity, made classical at the centre of mass) instead of
        ``mj_jacDot``: MuJoCo's other reading of the same quantity."""
        m, d = self.model, self._at(q, v)
        base = self.kinematics(q, v, a, links)
        names = {self.body_name(b): b for b in self.groups}
        gravity = m.opt.gravity.copy()
        out = []
        try:
            m.opt.gravity[:] = 0.0
            for rates in (np.zeros(m.nv), a):
                d.qacc[:] = rates
                mujoco.mj_rnePostConstraint(m, d)
                acc = np.zeros((len(links), 3))
                for i, name in enumerate(links):
                    b = names[name]
                    total = 0.0
                    for c in self.groups[b]:
                        r = d.xipos[c] - d.subtree_com[m.body_rootid[c]]
                        w, alpha = d.cvel[c, :3], d.cacc[c, :3]
                        lin = d.cacc[c, 3:] - np.cross(r, alpha) + np.cross(w, d.cvel[c, 3:] - np.cross(r, w))
                        acc[i] += m.body_mass[c] * lin
                        total += m.body_mass[c]
                    acc[i] /= total
                out.append(acc)
        finally:
            m.opt.gravity[:] = gravity
        return LinkKinematics(base.position, base.J, out[0], out[1])

