"""A robot model in Pinocchio, read by its MJCF parser or from a URDF, in the common coordinates.

Imports only ``pinocchio``. Pinocchio's conventions, converted here:

* configuration: quaternions ``(x, y, z, w)``; a free joint's placement is relative to its joint
  frame (``q = jointPlacement^-1 X``, with ``X`` the body's pose in world); bodies with several MJCF
  joints become one ``JointModelComposite`` named ``Composite_<first joint>``; an unbounded revolute
  joint has ``q = (cos, sin)``;
* speeds: a free joint's ``v = [R^T p_dot, omega]`` (both in body components: the speed map
  ``T = diag(R^T, I)``, ``T_dot v = [-omega x R^T p_dot, 0]``); ball, hinge and slide as MuJoCo's;
* dynamics: ``crba`` (upper triangle, armature included), ``rnea`` at zero accelerations,
  ``computeGeneralizedGravity``, ``aba`` at zero torques; classical accelerations of the links'
  centres of mass by ``getFrameClassicalAcceleration`` (LOCAL_WORLD_ALIGNED) at frames added there.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from relacc.core.rotations import matrix_from_quaternion
from relacc.engines.robots.base import Dynamics, Joint, Link, LinkKinematics, Robot, Structure
from relacc.errors import ModelError

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def kind(joint) -> str | None:
    """The common type of a (sub-)joint model, or None for one relacc does not map."""
    name = joint.shortname()
    if name == "JointModelFreeFlyer":
        return "free"
    if name == "JointModelSpherical":
        return "ball"
    if name.startswith(("JointModelR", "JointModelRevolute")):
        return "hinge"
    if name.startswith(("JointModelP", "JointModelPrismatic")):
        return "slide"
    return None


def _load(path, urdf, root_free):
    try:
        if urdf is not None:
            return pin.buildModelFromUrdf(str(urdf), pin.JointModelFreeFlyer()) if root_free else \
                pin.buildModelFromUrdf(str(urdf))
        return pin.buildModelFromMJCF(str(path))
    except Exception as exc:  # Pinocchio raises ValueError/RuntimeError with its parser's message
        raise ModelError(f"{urdf or path}: Pinocchio cannot read it: {' '.join(str(exc).split())}") from None


class PinocchioRobot(Robot):
    """The model file (or ``urdf``) in Pinocchio, its joints matched by name to the reference's."""

    engine = "pinocchio"

    def __init__(self, path, reference, urdf=None, split=False):
        ref = reference.structure
        root_free = bool(ref.joints) and ref.joints[0].type == "free"
        self.model = _load(path, urdf, root_free)
        self.args = (path, reference, urdf)
        if split:  # the engine-side reading below: composites as chains of simple joints
            from relacc.engines.pinocchio_ import split_composites

            self.model = split_composites(self.model)
        self.source = Path(urdf) if urdf is not None else Path(path)
        m = self.model
        self.map = self._match(reference, urdf is not None)
        self.dofs = np.array(sorted(v for entry in self.map for v in entry["ref_v"]), dtype=int)
        self.qdofs = np.array(sorted(i for entry in self.map for i in entry["ref_q"]), dtype=int)
        self.extra_dofs = m.nv - len(self.dofs)
        self.link_frames = {}
        last = {e["body"]: e for e in self.map}  # a body's last joint carries it
        named = {self._joint_of(e["v"][-1]): body for body, e in last.items()}  # links by the reference's names
        for j in range(1, m.njoints):
            bodies = [f.name for f in m.frames if f.type == pin.FrameType.BODY and f.parentJoint == j]
            if j not in named and not bodies:
                continue  # a massless joint between the sub-joints of a split composite
            name = named.get(j, bodies[0] if bodies else m.names[j])
            placement = pin.SE3(np.eye(3), m.inertias[j].lever.copy())
            self.link_frames[name] = (j, tuple(bodies), m.addFrame(pin.Frame(f"relacc_com_{name}", j, placement,
                                                                              pin.FrameType.OP_FRAME)))
        self.data = m.createData()
        self.warnings: list[str] = []
        self.structure = self._structure(reference.reference())

    def _match(self, reference, from_urdf):
        """Each reference joint Pinocchio has: its index slices in both coordinates and its type."""
        m, ref = self.model, reference.model
        subjoints = {}  # name -> (joint model, q start, v start)
        for j in range(1, m.njoints):
            jm = m.joints[j]
            if jm.shortname() == "JointModelComposite":
                iq, iv = jm.idx_q, jm.idx_v
                for k, sub in enumerate(jm.extract().joints if hasattr(jm, "extract") else jm.joints):
                    subjoints[(m.names[j], k)] = (sub, iq, iv)
                    iq, iv = iq + sub.nq, iv + sub.nv
            else:
                name, _, k = m.names[j].partition("[")  # split composites: "Composite_<first>[k]"
                subjoints[(name, int(k[:-1]) if k else 0)] = (jm, jm.idx_q, jm.idx_v)
        entries = []
        by_body: dict[int, list[int]] = {}
        for j in range(ref.njnt):
            by_body.setdefault(int(ref.jnt_bodyid[j]), []).append(j)
        for j, name in enumerate(reference.joint_names):
            siblings = by_body[int(ref.jnt_bodyid[j])]
            key = (name, 0)
            if key not in subjoints and len(siblings) > 1:
                key = (f"Composite_{reference.joint_names[siblings[0]]}", siblings.index(j))
            if key not in subjoints and from_urdf and j == 0 and reference.structure.joints[0].type == "free":
                key = (m.names[1], 0)
            if key not in subjoints:
                continue
            jm, iq, iv = subjoints[key]
            t = reference.structure.joints[j].type
            if kind(jm) != t:
                continue  # reported by the audit as a type difference
            qa, va = int(ref.jnt_qposadr[j]), int(ref.jnt_dofadr[j])
            nq, nv = {"free": (7, 6), "ball": (4, 3)}.get(t, (1, 1))
            entries.append({"joint": j, "name": name, "body": reference.structure.joints[j].body, "type": t,
                            "ref_q": range(qa, qa + nq), "ref_v": range(va, va + nv),
                            "q": range(iq, iq + jm.nq), "v": range(iv, iv + nv),
                            "placement": self._placement(iv) if t == "free" else None})
        return entries

    def _placement(self, v_index):
        return self.model.jointPlacements[self._joint_of(v_index)]

    def composites(self) -> list[str]:
        """Names of the model's ``JointModelComposite`` joints (bodies with several MJCF joints)."""
        return [self.model.names[j] for j in range(1, self.model.njoints)
                if self.model.joints[j].shortname() == "JointModelComposite"]

    def engine_q(self, q) -> np.ndarray:
        """Pinocchio's configuration of the reference's ``q`` (joints Pinocchio lacks are ignored)."""
        qe = pin.neutral(self.model)
        for e in self.map:
            x = np.asarray(q, dtype=float)[list(e["ref_q"])]
            if e["type"] == "free":
                pose = pin.SE3(matrix_from_quaternion(x[3:]), x[:3])
                qe[list(e["q"])] = pin.SE3ToXYZQUAT(e["placement"].inverse() * pose)
            elif e["type"] == "ball":
                qe[list(e["q"])] = [x[1], x[2], x[3], x[0]]
            elif len(e["q"]) == 2:  # unbounded revolute
                qe[list(e["q"])] = [np.cos(x[0]), np.sin(x[0])]
            else:
                qe[e["q"][0]] = x[0]
        return qe

    def speed_map(self, q, v) -> tuple[np.ndarray, np.ndarray]:
        """``(T (nv_e, n), T_dot v (nv_e,))``: Pinocchio's speeds from the shared reference speeds ``v[dofs]``."""
        column = {d: i for i, d in enumerate(self.dofs)}
        T, Tdv = np.zeros((self.model.nv, len(self.dofs))), np.zeros(self.model.nv)
        for e in self.map:
            rows, cols = list(e["v"]), [column[d] for d in e["ref_v"]]
            if e["type"] == "free":
                R = matrix_from_quaternion(np.asarray(q, dtype=float)[list(e["ref_q"])][3:])
                T[np.ix_(rows[:3], cols[:3])] = R.T
                T[np.ix_(rows[3:], cols[3:])] = np.eye(3)
                w, pdot = np.asarray(v, dtype=float)[list(e["ref_v"])][3:], np.asarray(v, dtype=float)[
                    list(e["ref_v"])][:3]
                Tdv[rows[:3]] = -np.cross(w, R.T @ pdot)
            else:
                T[np.ix_(rows, cols)] = np.eye(len(rows))
        return T, Tdv

    def _structure(self, q_ref) -> Structure:
        m, d = self.model, self.data
        qe = self.engine_q(q_ref)
        pin.forwardKinematics(m, d, qe)
        pin.computeJointJacobians(m, d, qe)
        joints = []
        for e in self.map:
            t, col = e["type"], d.J[:, e["v"][0]]
            axis = anchor = None
            if t == "hinge":  # the axis, and its point nearest the world origin (v_O = p x w)
                w = col[3:]
                axis, anchor = w / np.linalg.norm(w), np.cross(w, col[:3]) / (w @ w)
            elif t == "slide":
                axis = col[:3] / np.linalg.norm(col[:3])
            else:
                anchor = d.oMi[self._joint_of(e["v"][0])].translation.copy()
            joints.append(Joint(e["name"], t, e["body"], axis, anchor, m.armature[list(e["v"])].copy(),
                                m.damping[list(e["v"])].copy()))
        links = []
        for name, (j, bodies, _) in self.link_frames.items():
            I = m.inertias[j]
            R = d.oMi[j].rotation
            links.append(Link(name, bodies, float(I.mass), d.oMi[j].act(I.lever), R @ I.inertia @ R.T))
        body_names = tuple(f.name for f in m.frames if f.type == pin.FrameType.BODY)
        return Structure(m.nq, m.nv, tuple(joints), tuple(links), m.gravity.linear.copy(),
                         float(pin.computeTotalMass(m)),
                         body_names)

    def _joint_of(self, v_index) -> int:
        m = self.model
        for j in range(1, m.njoints):
            if m.idx_vs[j] <= v_index < m.idx_vs[j] + m.nvs[j]:
                return j
        raise ModelError(f"{self.source}: no Pinocchio joint holds speed {v_index}")

    def dynamics(self, q, v) -> Dynamics:
        m, d = self.model, self.data
        qe = self.engine_q(q)
        T, Tdv = self.speed_map(q, v)
        ve = T @ np.asarray(v, dtype=float)[self.dofs]
        upper = pin.crba(m, d, qe)
        Me = np.triu(upper) + np.triu(upper, 1).T
        be = pin.rnea(m, d, qe, ve, np.zeros(m.nv))
        ge = pin.computeGeneralizedGravity(m, d, qe)
        M, bias = T.T @ Me @ T, T.T @ (be + Me @ Tdv)
        forward = None
        if self.extra_dofs == 0:
            forward = np.linalg.solve(T, pin.aba(m, d, qe, ve, np.zeros(m.nv)) - Tdv)
        return Dynamics(M, bias, T.T @ ge, forward)

    def kinematics(self, q, v, a, links) -> LinkKinematics:
        m, d = self.model, self.data
        qe = self.engine_q(q)
        T, Tdv = self.speed_map(q, v)
        ve = T @ np.asarray(v, dtype=float)[self.dofs]
        ae = T @ np.asarray(a, dtype=float)[self.dofs] + Tdv
        pin.computeJointJacobiansTimeVariation(m, d, qe, ve)
        pin.updateFramePlacements(m, d)
        n = len(links)
        pos, J, Jdv, acc = np.zeros((n, 3)), np.zeros((n, 3, len(self.dofs))), np.zeros((n, 3)), np.zeros((n, 3))
        for i, name in enumerate(links):
            f = self.link_frames[name][2]
            Je = pin.getFrameJacobian(m, d, f, LWA)[:3]
            pos[i] = d.oMf[f].translation
            J[i] = Je @ T
            Jdv[i] = pin.getFrameJacobianTimeVariation(m, d, f, LWA)[:3] @ ve + Je @ Tdv
        pin.forwardKinematics(m, d, qe, ve, ae)
        for i, name in enumerate(links):
            acc[i] = pin.getFrameClassicalAcceleration(m, d, self.link_frames[name][2], LWA).linear
        return LinkKinematics(pos, J, Jdv, acc)



def _drop_later_world_children(spec):
    for body in list(spec.worldbody.bodies)[1:]:
        spec.delete(body)


def _visual_geoms(spec):
    """Geoms with ``contype = conaffinity = 0`` in bodies whose inertia comes from their geoms."""
    return [g for b in spec.bodies if not b.explicitinertial for g in b.geoms if g.contype == 0 and g.conaffinity == 0]


def _leave_out_of_inertia(spec):
    for g in spec.geoms:
        g.group = min(int(g.group), 4)
    for g in _visual_geoms(spec):
        g.group = 5
    spec.compiler.inertiagrouprange = [0, 4]
    spec.compiler.boundmass = spec.compiler.boundinertia = 1e-14  # MuJoCo refuses massless moving bodies


def _default_gravity(spec):
    spec.option.gravity = [0.0, 0.0, -9.81]


MJCF_READINGS = (
    ("first_body", "Pinocchio's MJCF parser reads only the first <body> under <worldbody>; the others are dropped",
     lambda spec: len(list(spec.worldbody.bodies)) > 1, _drop_later_world_children),
    ("settotalmass", "Pinocchio ignores <compiler settotalmass>, which makes MuJoCo scale every mass",
     lambda spec: spec.compiler.settotalmass > 0, lambda spec: setattr(spec.compiler, "settotalmass", -1.0)),
    ("visual_geoms", "Pinocchio's MJCF parser takes geoms with contype=0 and conaffinity=0 as visual and leaves "
     "them out of the inertia; MuJoCo counts every geom in inertiagrouprange",
     lambda spec: bool(_visual_geoms(spec)), _leave_out_of_inertia),
    ("gravity", "Pinocchio's MJCF parser ignores <option gravity> and keeps (0, 0, -9.81)",
     lambda spec: list(spec.option.gravity) != [0.0, 0.0, -9.81], _default_gravity),
)
"""How Pinocchio's MJCF parser reads a file differently from MuJoCo, each as ``(key, cause, applies(spec),
change(spec))``: ``change`` makes MuJoCo read the file Pinocchio's way, so that a comparison can check that the
difference is explained (MuJoCo recompiled with the change gives Pinocchio's numbers)."""

ENGINE_READINGS = (
    ("composite_jdot", "Pinocchio's Jacobian time variation (J_dot v) of a JointModelComposite, which its MJCF parser "
     "makes of a body with several joints, is wrong (stack-of-tasks/pinocchio#2519): with the composites split "
     "into simple joints Pinocchio agrees",
     lambda robot: bool(robot.composites()), lambda robot: PinocchioRobot(*robot.args, split=True)),
)
"""Differences in Pinocchio's algorithms rather than its reading of the file: ``(key, cause, applies(robot),
rebuild(robot))``, ``rebuild`` giving a robot without the difference."""
