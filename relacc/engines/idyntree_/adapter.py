"""iDynTree's adapter class and its loader (the package's docstring states the conventions)."""

from __future__ import annotations

from importlib.metadata import version as distribution_version
from pathlib import Path

import idyntree.bindings as idt
import numpy as np

from relacc.core.tree.coordinates import reference_q
from relacc.engines.base import BuiltJoint, Link, Points, Structure, combine, moving_mass
from relacc.engines.fixed_base import GRAVITY, FixedBaseAdapter
from relacc.engines.urdf import dynamics_text, is_urdf
from relacc.errors import EngineError, ModelError
from relacc.isolate import captured_output

__all__ = ["IDynTreeAdapter", "load", "version"]


def version() -> str:
    return distribution_version("idyntree")


def _matrix(transform) -> np.ndarray:
    """``(4, 4)`` a ``Transform`` as a homogeneous matrix (one call: iDynTree's temporaries do not outlive it)."""
    return np.array(transform.asHomogeneousTransform().toNumPy(), dtype=float)


class IDynTreeAdapter(FixedBaseAdapter):
    """A URDF in iDynTree's ``KinDynComputations``, its base fixed (the package's docstring)."""

    engine = "idyntree"
    global_coordinates = frozenset({"velocity", "V", "Vdot"})

    def __init__(self, path, reference):
        if not is_urdf(path):
            raise ModelError(f"{path}: relacc offers iDynTree URDF files only")
        text, note = dynamics_text(path)  # a xacro's expansion too; visual and collision elements left out
        loader = idt.ModelLoader()
        with captured_output(stdout=True) as printed:
            ok = loader.loadModelFromString(text, "urdf")
        if not ok or loader.model().getNrOfLinks() == 0:  # its parser can fail and still say it loaded (no link)
            said = "; ".join(line.removeprefix("[ERROR] ") for line in printed) or "its parser says no more"
            raise ModelError(f"{path}: iDynTree cannot load it: {said}")
        self.model = loader.model().copy()
        m = self.model
        joints = []
        for j in range(m.getNrOfJoints()):
            joint = m.getJoint(j)
            kind = "hinge" if joint.isRevoluteJoint() else "slide" if joint.isPrismaticJoint() else None
            if kind is None and not joint.isFixedJoint():
                raise ModelError(f"{path}: iDynTree's joint {m.getJointName(j)} is neither revolute, prismatic nor "
                                 "fixed: relacc does not match it")
            if kind is not None:
                joints.append({"name": m.getJointName(j), "kind": kind, "index": j, "dof": joint.getDOFsOffset(),
                               "child": m.getLinkName(joint.getSecondAttachedLink()),
                               "parent": m.getLinkName(joint.getFirstAttachedLink()),
                               "damping": joint.getDamping(0)})
        self.joint_info = sorted(joints, key=lambda j: j["dof"])
        n = m.getNrOfDOFs()
        matches = self._fixed_base("iDynTree", path, reference, "iDynTree's URDF parser drops a floating joint and "
                                   "lets the robot's base float by itself (measured on idyntree 15.1.0)",
                                   [(j["name"], j["kind"], j["dof"], j["dof"]) for j in self.joint_info])
        super().__init__(reference, matches, n, n, Path(path),
                         ([note] if note else []) + [f"iDynTree: {line}" for line in printed])
        with captured_output(stdout=True) as more:  # iDynTree's C++ says what goes wrong on stderr itself
            self.base, self.world_H_base = self._base(_root_link(text))
            self._frames()
            self.structure = self._structure()
        self.warnings += [f"iDynTree: {line}" for line in more]

    @property
    def version(self) -> str:
        return version()

    # --- the model ------------------------------------------------------------------------------------------

    def _base(self, root: str | None) -> tuple[str, np.ndarray]:
        """``(base link, (4, 4) its pose in the world)``: the URDF's root link held at the world. iDynTree's parser
        makes a massless link on a fixed joint an additional frame of its neighbour (a root ``world`` link with a
        fixed joint turning the robot: example-robot-data's TwoDofs), so the base is then the link that frame is on,
        placed so that the frame sits at the world's origin."""
        m = self.model
        if root is None or m.isLinkNameUsed(root):
            return (root if root is not None else m.getLinkName(m.getDefaultBaseLink())), np.eye(4)
        if not m.isFrameNameUsed(root):  # (getFrameIndex would print an error of its own on stderr)
            raise ModelError(f"{self.source}: iDynTree has neither a link nor a frame for the root link {root!r}")
        frame = m.getFrameIndex(root)
        link = m.getLinkName(m.getFrameLink(frame))
        return link, np.linalg.inv(_matrix(m.getFrameTransform(frame)))

    def _kd(self, model):
        kd = idt.KinDynComputations()
        if not kd.loadRobotModel(model):
            raise ModelError(f"{self.source}: iDynTree's KinDynComputations does not take the model")
        kd.setFrameVelocityRepresentation(idt.MIXED_REPRESENTATION)
        kd.setFloatingBase(self.base)
        return kd

    def _frames(self) -> None:
        """A frame at each moving link's mass centre (``relacc_com_<link>``, by iDynTree's inertias of the link and the
        links welded to it) and at each relacc body's mass centre (``relacc_body_<body>``), then the computations."""
        m = self.model
        kd = self._kd(m)
        self._state(kd, self.engine_q(reference_q(self.reference, 2))[0], np.zeros(self.nv_e), GRAVITY)
        for name, members in self.heads.items():
            inside = [b for b in members if m.isLinkNameUsed(b)]
            if not m.isLinkNameUsed(name):
                continue
            H = _matrix(kd.getWorldTransform(name))
            com = combine(self._parts(kd, inside))[1]
            local = H[:3, :3].T @ (com - H[:3, 3])
            m.addAdditionalFrameToLink(name, f"relacc_com_{name}", idt.Transform(idt.Rotation.Identity(),
                                                                                 idt.Position(*map(float, local))))
        for body in self.reference.bodies:
            if m.isLinkNameUsed(body.name):  # a link, or a link iDynTree made a frame of (massless on a fixed joint)
                link, H = body.name, np.eye(4)
            elif m.isFrameNameUsed(body.name):
                f = m.getFrameIndex(body.name)
                link, H = m.getLinkName(m.getFrameLink(f)), _matrix(m.getFrameTransform(f))
            else:
                continue
            at = H[:3, :3] @ np.asarray(body.com, dtype=float) + H[:3, 3]
            m.addAdditionalFrameToLink(link, f"relacc_body_{body.name}", idt.Transform(
                idt.Rotation.Identity(), idt.Position(*map(float, at))))
        self.kd = self._kd(m)

    def _parts(self, kd, links) -> list:
        """``[(mass, com (3,), inertia about it (3, 3))]`` of iDynTree's ``links`` at the state set, world
        components (kg, m, kg m^2)."""
        m, out = self.model, []
        for b in links:
            inertia = m.getLink(m.getLinkIndex(b)).getInertia()
            H = _matrix(kd.getWorldTransform(b))
            R = H[:3, :3]
            Ic = np.array(inertia.getRotationalInertiaWrtCenterOfMass().toNumPy(), dtype=float)
            c = np.array(inertia.getCenterOfMass().toNumPy(), dtype=float)
            out.append((float(inertia.getMass()), H[:3, 3] + R @ c, R @ Ic @ R.T))
        return out

    def _state(self, kd, qe, ve, gravity) -> None:
        H = self.world_H_base
        world_T_base = idt.Transform(idt.Rotation(*map(float, H[:3, :3].ravel())), idt.Position(*map(float, H[:3, 3])))
        kd.setRobotState(world_T_base, np.asarray(qe, dtype=float), idt.Twist.Zero(), np.asarray(ve, dtype=float),
                         np.asarray(gravity, dtype=float))

    def _structure(self) -> Structure:
        tree, m, kd = self.reference, self.model, self.kd
        self._state(kd, self.engine_q(reference_q(tree, 2))[0], np.zeros(self.nv_e), GRAVITY)
        by_dof = {j["dof"]: j for j in self.joint_info}
        joints = []
        for mt in self.matches:
            b, jt = tree.joints[mt.joints[0]]
            j = by_dof[mt.v[0]]
            H = _matrix(kd.getWorldTransform(j["child"]))
            col = self._jacobian(j["child"])[:, 6 + mt.v[0]]
            axis = anchor = None
            if mt.kind == "hinge":  # the axis, and its point nearest the world origin (v_O = v_o - w x o)
                w = col[3:]
                v_O = col[:3] - np.cross(w, H[:3, 3])
                axis, anchor = w / np.linalg.norm(w), np.cross(w, v_O) / (w @ w)
            else:
                axis = col[:3] / np.linalg.norm(col[:3])
            joints.append(BuiltJoint(jt.name, mt.kind, tree.bodies[b].name, axis, anchor, np.zeros(1),
                                     np.array([j["damping"]], dtype=float)))
        links = []
        for name, members in self.heads.items():
            inside = [b for b in members if m.isLinkNameUsed(b)]
            mass, com, inertia_w = combine(self._parts(kd, inside))
            links.append(Link(name, tuple(inside), mass, com, inertia_w))
        bodies = tuple(m.getLinkName(i) for i in range(m.getNrOfLinks()))
        return Structure(self.nq_e, self.nv_e, tuple(joints), tuple(links), GRAVITY.copy(), moving_mass(links),
                         bodies)

    def _jacobian(self, frame: str) -> np.ndarray:
        """``(6, 6 + nv)`` a frame's free-floating Jacobian (MIXED: ``[p_dot; omega]``, world components)."""
        J = idt.MatrixDynSize(6, 6 + self.nv_e)
        if not self.kd.getFrameFreeFloatingJacobian(frame, J):
            raise EngineError(f"{self.source}: iDynTree has no frame {frame!r}")
        return np.array(J.toNumPy(), dtype=float)


    # --- evaluations ----------------------------------------------------------------------------------------

    def _frame_of(self, spec) -> str:
        kind, name = spec
        frame = {"com": f"relacc_com_{name}", "body": f"relacc_body_{name}", "point": name}[kind]
        if not self.model.isFrameNameUsed(frame):
            raise EngineError(f"{self.source}: iDynTree has no frame for {kind} {name!r}")
        return frame

    def load_forces(self, qe, effects, t=0.0) -> np.ndarray:
        """Body loads through each body's mass-centre frame's Jacobian: ``J_v^T F + J_w^T T``."""
        tau = np.zeros((len(qe), self.nv_e))
        frames = {name: self._frame_of(("body", name)) for name in effects.bodies}
        for i in range(len(qe)):
            self._state(self.kd, qe[i], np.zeros(self.nv_e), GRAVITY)
            for name, load in effects.bodies.items():
                J = self._jacobian(frames[name])[:, 6:]
                tau[i] += float(load.factor(t[i] if np.ndim(t) else t)) * (J[:3].T @ load.force + J[3:].T @ load.torque)
        return tau

    def equations(self, qe, ve, effects=None, t=0.0):
        n, nv = len(qe), self.nv_e
        g = GRAVITY if effects is None or effects.gravity is None else np.asarray(effects.gravity, dtype=float)
        tau = self.generalized_forces(qe, ve, effects, t)
        M, f = np.empty((n, nv, nv)), np.empty((n, nv))
        Mi = idt.MatrixDynSize(6 + nv, 6 + nv)
        bias = idt.FreeFloatingGeneralizedTorques(self.model)
        for i in range(n):
            self._state(self.kd, qe[i], ve[i], g)
            self.kd.getFreeFloatingMassMatrix(Mi)
            M[i] = np.array(Mi.toNumPy(), dtype=float)[6:, 6:]
            self.kd.generalizedBiasForces(bias)
            f[i] = tau[i] - np.array(bias.jointTorques().toNumPy(), dtype=float)
        return M, f

    def points(self, qe, ve, ae, specs, *, jdot=False):
        """Positions, Jacobians, ``J_dot v`` (``getFrameBiasAcc``) and classical accelerations (``getFrameAcc`` at
        the rates ``ae``) of frames at the specs' points; ``jdot``: the Jacobian's rate is not offered by iDynTree
        (None)."""
        n, P, nv = len(qe), len(specs), self.nv_e
        frames = [self._frame_of(s) for s in specs]
        pos, J, Jdv = np.empty((n, P, 3)), np.empty((n, P, 3, nv)), np.empty((n, P, 3))
        acc = np.empty((n, P, 3))
        zero = np.zeros(6)
        for i in range(n):
            self._state(self.kd, qe[i], ve[i], GRAVITY)
            for k, frame in enumerate(frames):
                pos[i, k] = _matrix(self.kd.getWorldTransform(frame))[:3, 3]
                J[i, k] = self._jacobian(frame)[:3, 6:]
                Jdv[i, k] = np.array(self.kd.getFrameBiasAcc(frame).toNumPy(), dtype=float)[:3]
                if ae is not None:
                    acc[i, k] = np.array(self.kd.getFrameAcc(frame, zero, np.asarray(ae[i], dtype=float)).toNumPy(),
                                         dtype=float)[:3]
        return Points(pos, J, None, Jdv, None if ae is None else acc)

    def stepper(self, effects, dt, integrator, accuracy=None):
        raise EngineError("iDynTree has no integrator: relacc compares its dynamics, it does not step it")


def _root_link(text: str) -> str | None:
    """The URDF's root link (the one that is no joint's child), None when the text says none."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(text)
    children = {c.get("link") for j in root.iter("joint") for c in j.findall("child")}
    roots = [link.get("name") for link in root.findall("link") if link.get("name") not in children]
    return roots[0] if len(roots) == 1 else None


def load(path, reference=None, **options) -> IDynTreeAdapter:
    """The one loader signature: the URDF ``path`` read by iDynTree's ``ModelLoader``, matched to ``reference`` (None:
    relacc's own reading of the file).

    Raises:
        ModelError: not a URDF, or iDynTree cannot load it or has a joint relacc does not match.
    """
    if reference is None:
        from relacc.reading import read_tree

        reference = read_tree(path)
    return IDynTreeAdapter(path, reference)
