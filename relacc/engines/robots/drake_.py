"""A robot model in Drake, read by Drake's MJCF parser, in the common coordinates.

Imports only ``pydrake``. Drake's conventions, converted here:

* a free joint becomes a ``QuaternionFloatingJoint`` named after its body: ``q = [qw, qx, qy, qz,
  x, y, z]``, ``v = [omega (world components), p_dot (world)]``; speed map ``omega_W = R omega_B``,
  whose ``T_dot v = R (omega_B x omega_B) = 0``;
* a ball joint becomes a ``BallRpyJoint``: ``q`` roll-pitch-yaw angles (converted from the
  quaternion by ``RollPitchYaw``), ``v`` the child's angular velocity in the parent's components,
  ``R_FM omega_M`` (again ``T_dot v = 0``);
* a body with several MJCF joints becomes a chain of massless bodies, one joint each (the last
  carries the body's name); hinge and slide joints keep their names and coordinates;
* armature: Drake keeps it only as the reflected inertia of an actuator it reads on that joint (``<motor>``
  or ``<position>``; ``rotor_inertia gear^2``), which is what this adapter reports;
* dynamics: ``CalcMassMatrix``, ``CalcBiasTerm`` (``C v``), ``CalcGravityGeneralizedForces``
  (``tau_g``, so the bias is ``C v - tau_g``), forward dynamics from the plant's generalized
  acceleration output (Drake's articulated-body algorithm) with zero actuation and joint damping;
  links' centres of mass by ``CalcJacobianTranslationalVelocity``,
  ``CalcBiasTranslationalAcceleration`` and ``CalcSpatialAccelerationsFromVdot``.

Drake's parser warnings (unsupported attributes and elements) are collected, not printed.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
from pydrake.common.eigen_geometry import Quaternion
from pydrake.math import RollPitchYaw
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex, JacobianWrtVariable

from relacc.core.rotations import matrix_from_quaternion
from relacc.engines.robots.base import Dynamics, Joint, Link, LinkKinematics, Robot, Structure, combine
from relacc.engines.robots.drake_readings import MJCF_READINGS, drop_armature, unactuated
from relacc.errors import ModelError

TYPES = {"quaternion_floating": "free", "ball_rpy": "ball", "revolute": "hinge", "prismatic": "slide"}


class _Collect(logging.Handler):
    def __init__(self):
        super().__init__(logging.WARNING)
        self.lines = []

    def emit(self, record):
        self.lines.append(" ".join(record.getMessage().split()))


NO_MODEL_NAME = "must have a name attribute or a model name must be specified"
"""Drake's MJCF parser refuses a ``<mujoco>`` without ``model=`` (MuJoCo itself names it "MuJoCo Model")."""


def _directive(path) -> str:
    """A Drake model directive adding ``path`` under its file's stem: how Drake's parser takes a model name."""
    path = Path(path).resolve()
    return ("directives:\n- add_model:\n"
            f"    name: {json.dumps(path.stem)}\n    file: {json.dumps(path.as_uri())}\n")


def _parse(path, named: bool):
    plant = MultibodyPlant(0.0)
    parser = Parser(plant)
    if named:
        parser.AddModelsFromString(_directive(path), "dmd.yaml")
    else:
        parser.AddModels(str(path))
    plant.Finalize()
    return plant


def _load(path):
    """Drake's plant of ``path`` and its parser's warnings (and, when relacc named the model, a line saying so)."""
    log, handler = logging.getLogger("drake"), _Collect()
    before = log.propagate
    log.addHandler(handler)
    log.propagate = False
    try:
        try:
            plant = _parse(path, named=False)
        except Exception as exc:
            if NO_MODEL_NAME not in str(exc):
                raise
            handler.lines.clear()
            plant = _parse(path, named=True)
            handler.lines.append(f"the file has no model name, which Drake's parser requires: relacc loaded it "
                                 f"through a model directive naming it {Path(path).stem!r} (the name only)")
    except Exception as exc:  # Drake raises RuntimeError with its parser's message (file and line)
        raise ModelError(f"{path}: Drake cannot read it: {' '.join(str(exc).split())}") from None
    finally:
        log.removeHandler(handler)
        log.propagate = before
    return plant, handler.lines


class DrakeRobot(Robot):
    """The model file in Drake, its joints matched by name (free joints by body) to the reference's."""

    engine = "drake"

    def __init__(self, path, reference):
        self.source = Path(path)
        self.plant, self.warnings = _load(path)
        p = self.plant
        self.context = p.CreateDefaultContext()
        joints = [p.get_joint(j) for j in p.GetJointIndices() if p.get_joint(j).num_velocities() > 0]
        by_name = {j.name(): j for j in joints if j.type_name() != "quaternion_floating"}
        floating = {j.child_body().name(): j for j in joints if j.type_name() == "quaternion_floating"}
        ref = reference.model
        self.map, self.heads = [], {}
        for k, name in enumerate(reference.joint_names):
            t = reference.structure.joints[k].type
            dj = floating.get(reference.structure.joints[k].body) if t == "free" else by_name.get(name)
            if dj is None or TYPES.get(dj.type_name()) != t:
                continue
            qa, va = int(ref.jnt_qposadr[k]), int(ref.jnt_dofadr[k])
            n = dj.num_velocities()
            self.map.append({"joint": k, "name": name, "body": reference.structure.joints[k].body, "type": t,
                             "drake": dj, "ref_q": range(qa, qa + (7 if t == "free" else 4 if t == "ball" else 1)),
                             "ref_v": range(va, va + n), "q": range(dj.position_start(), dj.position_start()
                                                                    + dj.num_positions()),
                             "v": range(dj.velocity_start(), dj.velocity_start() + n)})
            self.heads[reference.structure.joints[k].body] = dj.child_body()  # the last joint of a body wins
        self.dofs = np.array(sorted(v for e in self.map for v in e["ref_v"]), dtype=int)
        self.qdofs = np.array(sorted(i for e in self.map for i in e["ref_q"]), dtype=int)
        self.extra_dofs = p.num_velocities() - len(self.dofs)
        self.structure = self._structure(reference)

    def engine_q(self, q) -> np.ndarray:
        qe = self.plant.GetDefaultPositions().copy()
        for e in self.map:
            x = np.asarray(q, dtype=float)[list(e["ref_q"])]
            if e["type"] == "free":
                qe[list(e["q"])] = np.concatenate([x[3:], x[:3]])
            elif e["type"] == "ball":
                qe[list(e["q"])] = RollPitchYaw(Quaternion(x / np.linalg.norm(x))).vector()
            else:
                qe[e["q"][0]] = x[0]
        return qe

    def speed_map(self, q, v) -> tuple[np.ndarray, np.ndarray]:
        """``(T (nv_e, n), T_dot v = 0)``: Drake's speeds from the shared reference speeds."""
        column = {d: i for i, d in enumerate(self.dofs)}
        T = np.zeros((self.plant.num_velocities(), len(self.dofs)))
        for e in self.map:
            rows, cols = list(e["v"]), [column[d] for d in e["ref_v"]]
            x = np.asarray(q, dtype=float)[list(e["ref_q"])]
            if e["type"] == "free":
                T[np.ix_(rows[:3], cols[3:])] = matrix_from_quaternion(x[3:])
                T[np.ix_(rows[3:], cols[:3])] = np.eye(3)
            elif e["type"] == "ball":
                T[np.ix_(rows, cols)] = matrix_from_quaternion(x / np.linalg.norm(x))
            else:
                T[rows[0], cols[0]] = 1.0
        return T, np.zeros(self.plant.num_velocities())

    def _set(self, q, v=None):
        p, ctx = self.plant, self.context
        p.SetPositions(ctx, self.engine_q(q))
        T, Tdv = self.speed_map(q, np.zeros(0) if v is None else v)
        ve = np.zeros(p.num_velocities()) if v is None else T @ np.asarray(v, dtype=float)[self.dofs]
        p.SetVelocities(ctx, ve)
        return T, Tdv, ve

    def _group(self, head):
        p = self.plant
        return [b for b in p.GetBodiesWeldedTo(head) if b.index() != p.world_body().index()]

    def _link(self, name, head) -> Link:
        p, ctx = self.plant, self.context
        parts = []
        for b in self._group(head):
            M = b.CalcSpatialInertiaInBodyFrame(ctx)
            X = p.EvalBodyPoseInWorld(ctx, b)
            R = X.rotation().matrix()
            Icm = M.Shift(M.get_com()).CalcRotationalInertia().CopyToFullMatrix3()
            parts.append((M.get_mass(), X.multiply(M.get_com()), R @ Icm @ R.T))
        mass, com, inertia = combine(parts)
        return Link(name, tuple(b.name() for b in self._group(head)), mass, com, inertia)

    @property
    def mjcf_readings(self) -> tuple:
        """:data:`MJCF_READINGS`, the armature reading bound to the joints this plant has an actuator on."""
        driven = frozenset(self.plant.get_joint_actuator(a).joint().name()
                           for a in self.plant.GetJointActuatorIndices())
        return tuple((key, text, lambda spec: bool(unactuated(spec, driven)),
                      lambda spec: drop_armature(spec, driven)) if key == "armature" else
                     (key, text, applies, change) for key, text, applies, change in MJCF_READINGS)

    def _structure(self, reference) -> Structure:
        p, ctx = self.plant, self.context
        self._set(reference.reference())
        W = p.world_frame()
        reflected = np.zeros(p.num_velocities())
        for a in p.GetJointActuatorIndices():
            act = p.get_joint_actuator(a)
            if act.joint().num_velocities() == 1:
                reflected[act.joint().velocity_start()] += act.default_reflected_inertia()
        joints = []
        for e in self.map:
            t, dj = e["type"], e["drake"]
            B = dj.child_body()
            X = p.EvalBodyPoseInWorld(ctx, B)
            Jw = p.CalcJacobianSpatialVelocity(ctx, JacobianWrtVariable.kV, B.body_frame(), X.inverse().translation(),
                                               W, W)
            col = Jw[:, e["v"][0]]  # [w; v of the body point at the world origin]
            axis = anchor = None
            if t == "hinge":
                w = col[:3]
                axis, anchor = w / np.linalg.norm(w), np.cross(w, col[3:]) / (w @ w)
            elif t == "slide":
                axis = col[3:] / np.linalg.norm(col[3:])
            else:
                anchor = dj.frame_on_child().CalcPoseInWorld(ctx).translation().copy()
            joints.append(Joint(e["name"], t, e["body"], axis, anchor, reflected[list(e["v"])],
                                np.asarray(dj.default_damping_vector(), dtype=float)))
        links = tuple(self._link(name, head) for name, head in self.heads.items())
        every = [p.get_body(BodyIndex(i)) for i in range(1, p.num_bodies())]  # 0 is the world
        bodies, total = tuple(b.name() for b in every), sum(b.default_mass() for b in every)
        return Structure(p.num_positions(), p.num_velocities(), tuple(joints), links,
                         np.asarray(p.gravity_field().gravity_vector(), dtype=float), float(total), bodies)

    def dynamics(self, q, v) -> Dynamics:
        p, ctx = self.plant, self.context
        T, Tdv, ve = self._set(q, v)
        Me = p.CalcMassMatrix(ctx)
        tau_g = p.CalcGravityGeneralizedForces(ctx)
        be = p.CalcBiasTerm(ctx) - tau_g
        forward = None
        if self.extra_dofs == 0:
            if p.num_actuators():
                p.get_actuation_input_port().FixValue(ctx, np.zeros(p.num_actuated_dofs()))
            for j in p.GetJointIndices():
                joint = p.get_joint(j)
                if joint.num_velocities():
                    joint.SetDampingVector(ctx, np.zeros(joint.num_velocities()))
            ae = p.get_generalized_acceleration_output_port().Eval(ctx)
            forward = np.linalg.solve(T, ae - Tdv)
        return Dynamics(T.T @ Me @ T, T.T @ (be + Me @ Tdv), T.T @ (-tau_g), forward)

    def kinematics(self, q, v, a, links) -> LinkKinematics:
        p, ctx, W = self.plant, self.context, self.plant.world_frame()
        T, Tdv, ve = self._set(q, v)
        ae = T @ np.asarray(a, dtype=float)[self.dofs] + Tdv
        A = p.CalcSpatialAccelerationsFromVdot(ctx, ae)
        n = len(links)
        pos, J, Jdv, acc = np.zeros((n, 3)), np.zeros((n, 3, len(self.dofs))), np.zeros((n, 3)), np.zeros((n, 3))
        for i, name in enumerate(links):
            head = self.heads[name]
            pos[i] = self._link(name, head).com
            X = p.EvalBodyPoseInWorld(ctx, head)
            p_B = X.inverse().multiply(pos[i])
            Je = p.CalcJacobianTranslationalVelocity(ctx, JacobianWrtVariable.kV, head.body_frame(), p_B, W, W)
            J[i] = Je @ T
            Jdv[i] = p.CalcBiasTranslationalAcceleration(ctx, JacobianWrtVariable.kV, head.body_frame(), p_B, W,
                                                         W).ravel() + Je @ Tdv
            w = p.EvalBodySpatialVelocityInWorld(ctx, head).rotational()
            acc[i] = A[head.index()].Shift(pos[i] - X.translation(), w).translational()
        return LinkKinematics(pos, J, Jdv, acc)


ENGINE_READINGS = ()
"""No known difference in Drake's algorithms."""
