"""Pinocchio's adapter class and its loader (the package's docstring states the conventions)."""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np
import pinocchio as pin

from relacc.core.rotations import (
    matrix_from_quaternion,
    quaternion_from_xyzw,
    quaternion_multiply,
    quaternion_to_xyzw,
    tilde,
)
from relacc.engines.base import Adapter, BuiltJoint, Link, Loop, Points, Structure, fixed_step_only, moving_mass
from relacc.engines.capabilities import BatchedForward, KinematicsLoops, ManifoldRates, PointLoop, ThreadedStepper
from relacc.engines.pinocchio_.model import match, parse, split_composites
from relacc.engines.urdf import dynamics_text, is_urdf
from relacc.errors import EngineError, ModelError
from relacc.limits import require_memory

__all__ = ["LWA", "PinocchioAdapter", "load", "split_composites", "version"]

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

THREADS = 2
"""Threads of Pinocchio's batched algorithms here (``abaInParallel``)."""

POOL_MIN = 64
"""Batches smaller than this run ``aba`` state by state on the adapter's one ``Data``: a ``ModelPool`` holds a
``Data`` per thread, which is what costs (:data:`DATA_BYTES_PER_NV2`)."""

DATA_BYTES_PER_NV2 = 8.5e3
"""A Pinocchio ``Data`` costs up to this many bytes per squared speed: measured with Pinocchio 4.1.0 on serial chains
of hinges, 3.6e3, 6.8e3 and 8.4e3 bytes times nv^2 at nv = 50, 100 and 250 (8.7 MB, 66 MB, 513 MB)."""


def data_bytes(nv: int) -> float:
    """An upper estimate of one Pinocchio ``Data``'s memory for ``nv`` speeds (:data:`DATA_BYTES_PER_NV2`)."""
    return DATA_BYTES_PER_NV2 * float(nv) ** 2


def version() -> str:
    return pin.__version__


def six(J) -> np.ndarray:
    """A Pinocchio Jacobian as ``(6, nv)``: its bindings give a model with one speed a ``(6,)`` vector."""
    J = np.asarray(J)
    return J.reshape(6, -1) if J.ndim == 1 else J


class PinocchioAdapter(PointLoop, KinematicsLoops, BatchedForward, ThreadedStepper, ManifoldRates, Adapter):
    """A model file in Pinocchio (its MJCF parser, or ``urdf`` by its URDF parser), matched to ``reference``."""

    engine = "pinocchio"
    THREADED_INTEGRATORS = ("rk4",)  # RKMK4 on Pinocchio's manifold, pin.abaInParallel at every stage
    global_coordinates = frozenset({"velocity", "V", "Vdot"})
    absolute_velocities = frozenset({"acceleration", "Vdot"})  # measured: tests/test_hardcases.py

    def __init__(self, path, reference, urdf=None, split=False, armature_as_case2=False):
        if urdf is None and is_urdf(path):  # a URDF goes to Pinocchio's URDF parser
            urdf = path
        self.from_urdf = urdf is not None
        root_free = bool(reference.joints) and reference.joints[0][1].type == "free"
        loaded, printed = parse(path, urdf, root_free)
        self.args, self.composite_model = (path, reference, urdf), loaded
        self.split, self.armature_as_case2 = split, armature_as_case2
        self.model = split_composites(loaded) if split else loaded
        self.gravity0 = self.model.gravity.linear.copy()
        m = self.model
        note = dynamics_text(urdf)[1] if urdf is not None else None  # what it was not given of the URDF
        super().__init__(reference, match(m, reference, urdf is not None), m.nq, m.nv,
                         Path(urdf) if urdf is not None else Path(path), ([note] if note else []) + printed)
        self.link_frames, self.body_frames = {}, {}
        self._add_frames()
        require_memory(data_bytes(m.nv), f"Pinocchio's data of {Path(path).name} ({m.nv} speeds)",
                       "leave Pinocchio out (--engines)")
        self.data = m.createData()
        self.structure = self._structure()

    @property
    def version(self) -> str:
        return version()

    def composites(self) -> list[str]:
        """Names of the model's ``JointModelComposite`` joints (bodies with several MJCF joints)."""
        return [self.model.names[j] for j in range(1, self.model.njoints)
                if self.model.joints[j].shortname() == "JointModelComposite"]

    def _joint_of(self, v_index) -> int:
        m = self.model
        for j in range(1, m.njoints):
            if m.idx_vs[j] <= v_index < m.idx_vs[j] + m.nvs[j]:
                return j
        raise ModelError(f"{self.source}: no Pinocchio joint holds speed {v_index}")

    def _add_frames(self):
        """A frame at each link's mass centre (named as the reference's moving body) and at each reference body's
        mass centre (for loads), on the joint that carries it."""
        m, tree = self.model, self.reference
        last = {}
        for mt in self.matches:
            last[tree.joints[mt.joints[-1]][0]] = mt  # a body's last joint carries it
        named = {self._joint_of(mt.v[-1]): tree.bodies[b].name for b, mt in last.items()}
        for j in range(1, m.njoints):
            bodies = [f.name for f in m.frames if f.type == pin.FrameType.BODY and f.parentJoint == j]
            if j not in named and not bodies:
                continue  # a massless joint between the sub-joints of a split composite
            name = named.get(j, bodies[0] if bodies else m.names[j])
            placement = pin.SE3(np.eye(3), m.inertias[j].lever.copy())
            self.link_frames[name] = (j, tuple(bodies), m.addFrame(pin.Frame(f"relacc_com_{name}", j, placement,
                                                                              pin.FrameType.OP_FRAME)))
        for b, body in enumerate(tree.bodies):
            found = self._body_frame(b, last)
            if found is not None:
                f = m.frames[found]
                at = f.placement * pin.SE3(np.eye(3), np.asarray(body.com, dtype=float))
                self.body_frames[body.name] = m.addFrame(pin.Frame(f"relacc_body_{body.name}", f.parentJoint, at,
                                                                   pin.FrameType.OP_FRAME))

    def _body_frame(self, b: int, last: dict) -> int | None:
        """Pinocchio's BODY frame of the reference's body ``b``: by name, else (an unnamed body, which Pinocchio names
        ``<parent>Bis``) the one BODY frame on the joint that carries the body's last matched joint; None if neither
        says."""
        m, name = self.model, self.reference.bodies[b].name
        if m.existFrame(name, pin.FrameType.BODY):
            return m.getFrameId(name, pin.FrameType.BODY)
        if b not in last:
            return None
        j = self._joint_of(last[b].v[-1])
        on = [i for i, f in enumerate(m.frames) if f.type == pin.FrameType.BODY and f.parentJoint == j]
        return on[0] if len(on) == 1 else None

    def _structure(self) -> Structure:
        m, d = self.model, self.model.createData()
        qe = self.engine_q(self.reference_q())[0]
        pin.forwardKinematics(m, d, qe)
        pin.computeJointJacobians(m, d, qe)
        tree, joints = self.reference, []
        for mt in self.matches:
            k = mt.joints[0]
            b, jt = tree.joints[k]
            col = six(d.J)[:, mt.v[0]]
            axis = anchor = None
            if mt.kind == "hinge":  # the axis, and its point nearest the world origin (v_O = p x w)
                w = col[3:]
                axis, anchor = w / np.linalg.norm(w), np.cross(w, col[:3]) / (w @ w)
            elif mt.kind == "slide":
                axis = col[:3] / np.linalg.norm(col[:3])
            else:
                anchor = d.oMi[self._joint_of(mt.v[0])].translation.copy()
            joints.append(BuiltJoint(jt.name, mt.kind, tree.bodies[b].name, axis, anchor, m.armature[list(mt.v)].copy(),
                                m.damping[list(mt.v)].copy()))
        links = []
        for name, (j, bodies, _) in self.link_frames.items():
            inertia = m.inertias[j]
            R = d.oMi[j].rotation
            links.append(Link(name, bodies, float(inertia.mass), d.oMi[j].act(inertia.lever),
                              R @ inertia.inertia @ R.T))
        body_names = tuple(f.name for f in m.frames if f.type == pin.FrameType.BODY)
        return Structure(m.nq, m.nv, tuple(joints), tuple(links), self.gravity0.copy(),
                         moving_mass(links), body_names)

    def reference_q(self) -> np.ndarray:
        from relacc.core.tree.coordinates import reference_q

        return reference_q(self.reference, 2)

    # --- conversions ----------------------------------------------------------------------------------------

    def default_q(self) -> np.ndarray:
        return pin.neutral(self.model)

    def _placement(self, mt):
        return self.model.jointPlacements[self._joint_of(mt.v[0])]

    def _placement_wxyz(self, mt):
        """The free joint's placement in its parent: ``(R (3, 3), t (3,), quaternion (w, x, y, z))``."""
        P = self._placement(mt)
        return P.rotation, P.translation, quaternion_from_xyzw(pin.SE3ToXYZQUAT(P)[3:])

    def q_block(self, mt, x):
        if mt.kind == "free":  # pose = P^-1 X, by quaternion products (a rotation's sign is kept, never flipped)
            R, t, qP = self._placement_wxyz(mt)
            quat = quaternion_multiply(qP * np.array([1.0, -1.0, -1.0, -1.0]), x[:, 3:7])
            return np.concatenate([(x[:, :3] - t) @ R, quaternion_to_xyzw(quat)], axis=1)
        if mt.kind == "ball":
            return quaternion_to_xyzw(x)
        if len(mt.q) == 2:  # unbounded revolute
            return np.concatenate([np.cos(x), np.sin(x)], axis=1)
        return x

    def q_back(self, mt, xe):
        if mt.kind == "free":  # X = P pose
            R, t, qP = self._placement_wxyz(mt)
            quat = quaternion_multiply(np.broadcast_to(qP, (len(xe), 4)), quaternion_from_xyzw(xe[:, 3:7]))
            return np.concatenate([xe[:, :3] @ R.T + t, quat], axis=1)
        if mt.kind == "ball":
            return quaternion_from_xyzw(xe)
        if len(mt.q) == 2:
            return np.arctan2(xe[:, 1:2], xe[:, 0:1])
        return xe

    varying_speed_maps = ("free",)
    """A free joint's linear speeds are Pinocchio's in the body's frame (``R^T v``)."""

    def v_block(self, mt, x, w):
        if mt.kind != "free":
            return super().v_block(mt, x, w)
        n = len(x)
        RT = np.swapaxes(matrix_from_quaternion(x[:, 3:7]), 1, 2)
        T, Td = np.zeros((n, 6, 6)), np.zeros((n, 6, 6))
        T[:, :3, :3], T[:, 3:, 3:] = RT, np.eye(3)
        Td[:, :3, :3] = -tilde(w[:, 3:6]) @ RT
        return T, Td

    # --- evaluations ----------------------------------------------------------------------------------------

    @contextlib.contextmanager
    def _gravity(self, effects):
        """``model.gravity`` set to the effects' (or the model's own) for the block, and back."""
        m = self.model
        g = self.gravity0 if effects is None or effects.gravity is None else effects.gravity
        m.gravity.linear[:] = g
        try:
            yield m
        finally:
            m.gravity.linear[:] = self.gravity0

    def load_forces(self, qe, effects, t=0.0) -> np.ndarray:
        """Body loads through the LOCAL_WORLD_ALIGNED frame Jacobians at the bodies' mass centres: ``J^T F``,
        ``J_w^T T``."""
        m, d = self.model, self.data
        tau = np.zeros((len(qe), m.nv))
        for i in range(len(qe)):
            pin.computeJointJacobians(m, d, qe[i])
            pin.updateFramePlacements(m, d)
            for name, load in effects.bodies.items():
                J = six(pin.getFrameJacobian(m, d, self.body_frames[name], LWA))
                tau[i] += float(load.factor(t[i] if np.ndim(t) else t)) * (J[:3].T @ load.force + J[3:].T @ load.torque)
        return tau

    def free_armature(self) -> dict:
        """``{v index of a free joint's first speed: (3,) its translations' armature, kg}`` where nonzero: Pinocchio
        adds it in its own speeds (the body-frame velocity of the body's origin), MuJoCo and relacc in case 2's (the
        world-frame one)."""
        m = self.model
        out = {}
        for j in range(1, m.njoints):
            if m.joints[j].shortname() == "JointModelFreeFlyer":
                a = m.armature[m.joints[j].idx_v:m.joints[j].idx_v + 3]
                if np.any(a != 0):
                    out[m.joints[j].idx_v] = a.copy()
        return out

    def generalized_forces(self, qe, ve, effects, t=0.0) -> np.ndarray:
        """As :meth:`Adapter.generalized_forces`; with ``armature_as_case2`` (a known behaviour's change, not the
        engine as it is) also ``A T_dot u = -a (omega x v)`` on a free joint's translations (``a`` their armature,
        ``omega`` and ``v`` its body-frame angular and linear speeds, ``T_dot`` of :meth:`v_block`): mapped to case 2,
        Pinocchio's equations carry ``-T^T A T_dot u`` from its armature, added in its own speeds; this undoes it, so
        that the armature acts as MuJoCo's and relacc's, added in case 2's."""
        tau = super().generalized_forces(qe, ve, effects, t)
        if self.armature_as_case2:
            ve = np.atleast_2d(ve)
            for k, a in self.free_armature().items():
                tau[:, k:k + 3] -= a * np.cross(ve[:, k + 3:k + 6], ve[:, k:k + 3])
        return tau

    def equations(self, qe, ve, effects=None, t=0.0):
        n, nv = len(qe), self.model.nv
        tau = self.generalized_forces(qe, ve, effects, t)
        M, f = np.empty((n, nv, nv)), np.empty((n, nv))
        with self._gravity(effects) as m:
            d = self.data
            for i in range(n):
                upper = pin.crba(m, d, qe[i])
                M[i] = np.triu(upper) + np.triu(upper, 1).T  # crba fills the upper triangle
                f[i] = tau[i] - pin.rnea(m, d, qe[i], ve[i], np.zeros(nv))
        return M, f

    def forward(self, qe, ve, effects=None, t=0.0):
        """``aba`` over the batch by ``abaInParallel`` (Pinocchio's batched API), under exactly ``effects``."""
        tau = self.generalized_forces(qe, ve, effects, t)
        with self._gravity(effects) as m:
            if len(qe) < POOL_MIN:  # one Data, state by state: (n, nv)
                out = np.array([pin.aba(m, self.data, x, w, f) for x, w, f in zip(qe, ve, tau)])
                return out.reshape(len(qe), m.nv)
            out = np.zeros((m.nv, len(qe)), order="F")
            pin.abaInParallel(THREADS, self._pool(m, THREADS), np.asfortranarray(qe.T), np.asfortranarray(ve.T),
                              np.asfortranarray(tau.T), out)
        return out.T.copy()

    def _pool(self, model, threads: int):
        """A ``pin.ModelPool`` of ``model`` as it is now (its gravity included), one per gravity and thread count."""
        if getattr(self, "_pools", None) is None:
            self._pools = {}
        key = (threads, tuple(model.gravity.linear))
        if key not in self._pools:
            require_memory(threads * data_bytes(model.nv), f"Pinocchio's pool of {threads} data ({model.nv} speeds)",
                           "use fewer threads")
            self._pools[key] = pin.ModelPool(model, threads)
        return self._pools[key]

    def _frame(self, spec) -> int:
        kind, name = spec
        if kind == "com":
            return self.link_frames[name][2]
        if kind == "body":
            if name not in self.body_frames:
                raise EngineError(f"{self.source}: relacc finds no Pinocchio body for {name!r} (its parser names it "
                                  "otherwise and no matched joint carries it)")
            return self.body_frames[name]
        frames = [i for i, f in enumerate(self.model.frames) if f.name == name]
        if not frames:
            raise EngineError(f"{self.source}: Pinocchio has no frame named {name!r}")
        return frames[0]

    def points(self, qe, ve, ae, specs, *, jdot=False):
        m, d = self.model, self.data
        frames = [self._frame(s) for s in specs]
        n, P, nv = len(qe), len(specs), m.nv
        pos, J, Jd = np.empty((n, P, 3)), np.empty((n, P, 3, nv)), np.empty((n, P, 3, nv))
        acc = np.empty((n, P, 3))  # returned only with ae
        for i in range(n):
            # one pass: forward kinematics with v, joint Jacobians and their time variation
            pin.computeJointJacobiansTimeVariation(m, d, qe[i], ve[i])
            pin.updateFramePlacements(m, d)
            for k, f in enumerate(frames):
                pos[i, k] = d.oMf[f].translation
                J[i, k] = six(pin.getFrameJacobian(m, d, f, LWA))[:3]
                Jd[i, k] = six(pin.getFrameJacobianTimeVariation(m, d, f, LWA))[:3]
            if ae is not None:  # second pass: accelerations, read as classical
                pin.forwardKinematics(m, d, qe[i], ve[i], ae[i])
                for k, f in enumerate(frames):
                    acc[i, k] = pin.getFrameClassicalAcceleration(m, d, f, LWA).linear
        return Points(pos, J, Jd if jdot else None, np.einsum("npij,nj->npi", Jd, ve), None if ae is None else acc)

    def space(self):
        """Pinocchio's configuration manifold for :mod:`relacc.dynamics.integrate`, batched over rows."""
        return PinocchioSpace(self.model)

    def stepper(self, effects, dt, integrator, accuracy=None, threads: int = 1):
        """RKMK4 (or semi-implicit Euler) on Pinocchio's manifold with ``aba`` accelerations under ``effects``, on
        one state ``(nq_e,)`` or a batch ``(n, nq_e)`` (``abaInParallel`` on ``threads``); time runs on from 0."""
        from relacc.dynamics.integrate import STEPPERS, space_stepper

        if integrator not in STEPPERS:
            raise EngineError(f"Pinocchio integrators here: {', '.join(STEPPERS)}; got {integrator!r}")
        fixed_step_only("Pinocchio (with relacc's integrators)", accuracy)
        return space_stepper(self.space(), self.derivs(effects, threads), dt, integrator)

    def derivs(self, effects, threads: int = 1):
        """``derivs(x, w, t) -> (w, vdot)``: the tangent velocity (Pinocchio's ``v``) and the accelerations under
        ``effects`` at time ``t``, for :mod:`relacc.dynamics.integrate` on :meth:`space`; one state or a batch."""
        return lambda x, w, t: (w, self._accelerations(x, w, effects, t, threads))

    def _accelerations(self, x, w, effects, t, threads):
        one = x.ndim == 1
        X, W = np.atleast_2d(x), np.atleast_2d(w)
        tau = self.generalized_forces(X, W, effects, t)
        with self._gravity(effects) as m:
            if one:
                return pin.aba(m, self.data, x, w, tau[0])
            out = np.zeros((m.nv, len(X)), order="F")
            pin.abaInParallel(threads, self._pool(m, threads), np.asfortranarray(X.T), np.asfortranarray(W.T),
                              np.asfortranarray(tau.T), out)
        return out.T.copy()

    def batched_forward(self, threads: int, qe, ve, gravity=None):
        """The benchmarks' anchor: a closure timing ``pin.abaInParallel`` on a ``pin.ModelPool`` (its fastest use:
        inputs ``(nq_e, n)``, ``(nv_e, n)`` and output prepared in its column-major layout), at ``gravity`` (m/s^2;
        default the model's own); its ``out`` attribute holds the accelerations ``(nv_e, n)``."""
        from relacc.dynamics.tree_effects import TreeEffects

        with self._gravity(None if gravity is None else TreeEffects(gravity)) as m:
            pool = pin.ModelPool(m, threads)
        qe, ve = np.asfortranarray(qe), np.asfortranarray(ve)
        tau, out = np.zeros_like(ve, order="F"), np.zeros_like(ve, order="F")

        def loop():
            pin.abaInParallel(threads, pool, qe, ve, tau, out)

        return Loop(loop, out=out)

    def jacobian_loop(self, qe, ve, specs):
        """The benchmarks' anchor: a closure looping over the states: ``computeJointJacobiansTimeVariation`` then,
        per point, ``getFrameJacobian`` and ``getFrameJacobianTimeVariation`` (LOCAL_WORLD_ALIGNED) stored into
        ``(n, P, 6, nv_e)`` arrays, as a user collecting every body's would."""
        m, d = self.model, self.data
        frames = [self._frame(s) for s in specs]
        n = len(qe)
        J, Jd = np.empty((n, len(frames), 6, m.nv)), np.empty((n, len(frames), 6, m.nv))

        def loop():
            for i in range(n):
                pin.computeJointJacobiansTimeVariation(m, d, qe[i], ve[i])
                pin.updateFramePlacements(m, d)
                for k, f in enumerate(frames):
                    J[i, k] = six(pin.getFrameJacobian(m, d, f, LWA))
                    Jd[i, k] = six(pin.getFrameJacobianTimeVariation(m, d, f, LWA))

        return loop

    def motion_loop(self, qe, ve, ae, specs):
        """The benchmarks' anchor for kinematics without Jacobians: a closure looping over the states with
        ``forwardKinematics`` (q, v, a) and ``updateFramePlacements``, then per point its position, velocity, classical
        acceleration, angular velocity and acceleration (``getFrameVelocity``, ``getFrameClassicalAcceleration``,
        ``getFrameAcceleration``, LOCAL_WORLD_ALIGNED) stored into ``(n, P, 3)`` arrays, as a user would; the results in
        the closure's ``pos``, ``vel``, ``acc`` attributes."""
        m, d = self.model, self.data
        frames = [self._frame(s) for s in specs]
        n, P = len(qe), len(frames)
        pos, vel, acc, om, al = (np.empty((n, P, 3)) for _ in range(5))

        def loop():
            for i in range(n):
                pin.forwardKinematics(m, d, qe[i], ve[i], ae[i])
                pin.updateFramePlacements(m, d)
                for k, f in enumerate(frames):
                    v = pin.getFrameVelocity(m, d, f, LWA)
                    pos[i, k], vel[i, k], om[i, k] = d.oMf[f].translation, v.linear, v.angular
                    acc[i, k] = pin.getFrameClassicalAcceleration(m, d, f, LWA).linear
                    al[i, k] = pin.getFrameAcceleration(m, d, f, LWA).angular

        return Loop(loop, pos=pos, vel=vel, acc=acc)

    def point_loop(self, qe, ve, ae, spec, full: bool = False):
        """The throughput anchor: a closure looping over the states as a user would for one point's classical
        acceleration (``forwardKinematics``, ``getFrameClassicalAcceleration``) and, with ``full``, its position,
        Jacobian and time variation; results in its ``acc`` attribute ``(n, 3)``."""
        m, d, f = self.model, self.data, self._frame(spec)
        n = len(qe)
        acc, J, Jd = np.empty((n, 3)), np.empty((n, 6, m.nv)), np.empty((n, 6, m.nv))

        def loop():
            for i in range(n):
                if full:
                    pin.computeJointJacobiansTimeVariation(m, d, qe[i], ve[i])
                    pin.updateFramePlacements(m, d)
                    J[i] = six(pin.getFrameJacobian(m, d, f, LWA))
                    Jd[i] = six(pin.getFrameJacobianTimeVariation(m, d, f, LWA))
                pin.forwardKinematics(m, d, qe[i], ve[i], ae[i])
                acc[i] = pin.getFrameClassicalAcceleration(m, d, f, LWA).linear

        return Loop(loop, acc=acc)


class PinocchioSpace:
    """Pinocchio's configuration manifold for :mod:`relacc.dynamics.integrate`, on one state or a batch of rows.

    ``integrate`` is ``pin.integrate`` (SE(3) exponential for the free-flyer, SO(3) for the spherical joint);
    ``dexpinv(x0, delta, w)`` inverts ``pin.dIntegrate`` with respect to the increment, which maps local increments
    at ``x0`` to velocities at the moved configuration.
    """

    def __init__(self, model):
        self.model = model

    def integrate(self, x, delta):
        if x.ndim == 1:
            return pin.integrate(self.model, x, delta)
        return np.array([pin.integrate(self.model, a, b) for a, b in zip(x, delta)])

    def dexpinv(self, x0, delta, w):
        if x0.ndim > 1:
            return np.array([self.dexpinv(a, b, c) for a, b, c in zip(x0, delta, w)])
        if not np.any(delta):
            return w
        return np.linalg.solve(pin.dIntegrate(self.model, x0, delta, pin.ArgumentPosition.ARG1), w)


def load(path, reference=None, *, urdf=None, split=False, **options) -> PinocchioAdapter:
    """The one loader signature: ``path`` (MJCF; or ``urdf`` by the URDF parser) in Pinocchio, matched to
    ``reference``; ``split``: composites split into simple joints (:func:`split_composites`).

    Raises:
        ModelError: Pinocchio cannot read the file.
    """
    if reference is None:  # relacc's own reading, never another engine's
        from relacc.reading import read_tree

        reference = read_tree(path)
    return PinocchioAdapter(path, reference, urdf=urdf, split=split)
