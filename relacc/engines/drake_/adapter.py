"""Drake's adapter class and its loader (the package's docstring states the conventions)."""

from __future__ import annotations

from importlib.metadata import version as distribution_version
from pathlib import Path

import numpy as np
from pydrake.autodiffutils import ExtractGradient, InitializeAutoDiff
from pydrake.common.eigen_geometry import Quaternion
from pydrake.math import RollPitchYaw
from pydrake.multibody.tree import BodyIndex, JacobianWrtVariable

from relacc.core.rotations import matrix_from_quaternion, tilde
from relacc.core.tree.coordinates import reference_q
from relacc.engines.base import Adapter, BuiltJoint, Link, Loop, Points, Structure, combine, moving_mass
from relacc.engines.capabilities import PointLoop
from relacc.engines.drake_ import run
from relacc.engines.drake_.plant import build_plant, match_parsed, parse, quiet
from relacc.errors import EngineError

__all__ = ["DrakeAdapter", "load", "version"]

KV = JacobianWrtVariable.kV


def version() -> str:
    import pydrake

    return getattr(pydrake, "__version__", None) or distribution_version("drake")


class DrakeAdapter(PointLoop, Adapter):
    """A model in Drake: a file read by Drake's parser, or (``build``) the plant of the reference tree itself."""

    engine = "drake"
    global_coordinates = frozenset({"velocity", "V", "Vdot"})
    absolute_velocities = frozenset({"Vdot"})  # measured: tests/test_hardcases.py

    def __init__(self, path, reference, build: bool = False):
        self.built = build
        if build:
            self.plant, matches, self.heads = build_plant(reference)
            warnings = []
        else:
            self.plant, warnings = parse(path)
            matches, self.heads = match_parsed(self.plant, reference)
        self.path = Path(path) if path is not None else None
        p = self.plant
        super().__init__(reference, matches, p.num_positions(), p.num_velocities(), self.path, warnings)
        self.context = p.CreateDefaultContext()
        self._load_plan: tuple | None = None  # (effects, [(frame, point, wrench, load)]): see load_forces
        self.gravity0 = np.asarray(p.gravity_field().gravity_vector(), dtype=float).copy()
        self._ad: tuple | None = None
        self.structure = self._structure()

    @property
    def version(self) -> str:
        return version()

    def rebuilt(self):
        """A fresh plant of the same model (a simulation's diagram owns its plant)."""
        return build_plant(self.reference)[0] if self.built else parse(self.path)[0]

    # --- conversions ----------------------------------------------------------------------------------------

    def default_q(self) -> np.ndarray:
        return self.plant.GetDefaultPositions().copy()

    def q_block(self, mt, x):
        if mt.kind in ("free", "floating"):
            return np.concatenate([x[:, 3:7], x[:, :3]], axis=1)
        if mt.kind == "ball":
            return np.array([RollPitchYaw(Quaternion(r / np.linalg.norm(r))).vector() for r in x])
        return x

    def q_back(self, mt, xe):
        if mt.kind in ("free", "floating"):
            return np.concatenate([xe[:, 4:7], xe[:, :4]], axis=1)
        if mt.kind == "ball":
            return np.array([RollPitchYaw(r).ToQuaternion().wxyz() for r in xe])
        return xe

    varying_speed_maps = ("free", "floating", "ball")
    """A free or ball joint's angular speeds are Drake's in its parent's frame (``R w``); its translations' of a free
    joint in the world's."""

    def v_block(self, mt, x, w):
        n = len(x)
        if mt.kind in ("free", "floating"):
            R = matrix_from_quaternion(x[:, 3:7])
            T, Td = np.zeros((n, 6, 6)), np.zeros((n, 6, 6))
            T[:, :3, 3:], T[:, 3:, :3] = R, np.eye(3)
            Td[:, :3, 3:] = R @ tilde(w[:, 3:6])
            return T, Td
        if mt.kind == "ball":
            R = matrix_from_quaternion(x / np.linalg.norm(x, axis=1, keepdims=True))
            return R, R @ tilde(w)
        return super().v_block(mt, x, w)

    def v_block_inverse(self, mt, x):
        """:meth:`v_block`'s ``T^-1`` in closed form: ``R^T`` for a ball; a free joint's ``[[0, I], [R^T, 0]]``."""
        if mt.kind in ("free", "floating"):
            R = matrix_from_quaternion(x[:, 3:7])
            T_inv = np.zeros((len(x), 6, 6))
            T_inv[:, :3, 3:], T_inv[:, 3:, :3] = np.eye(3), np.swapaxes(R, 1, 2)
            return T_inv
        if mt.kind == "ball":
            return np.swapaxes(matrix_from_quaternion(x / np.linalg.norm(x, axis=1, keepdims=True)), 1, 2)
        return super().v_block_inverse(mt, x)

    # --- the reading ----------------------------------------------------------------------------------------

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

    def _set(self, qe, ve=None):
        p, ctx = self.plant, self.context
        p.SetPositions(ctx, qe)
        p.SetVelocities(ctx, np.zeros(p.num_velocities()) if ve is None else ve)

    def _structure(self) -> Structure:
        p, ctx, tree = self.plant, self.context, self.reference
        self._set(self.engine_q(reference_q(tree, 2))[0])
        W = p.world_frame()
        reflected = np.zeros(p.num_velocities())
        for a in p.GetJointActuatorIndices():
            act = p.get_joint_actuator(a)
            if act.joint().num_velocities() == 1:
                reflected[act.joint().velocity_start()] += act.default_reflected_inertia()
        joints = []
        for mt in self.matches:
            b, jt = tree.joints[mt.joints[-1]]
            dj = next(p.get_joint(j) for j in p.GetJointIndices() if p.get_joint(j).velocity_start() == mt.v[0]
                      and p.get_joint(j).num_velocities() == len(mt.v))
            B = dj.child_body()
            X = p.EvalBodyPoseInWorld(ctx, B)
            Jw = p.CalcJacobianSpatialVelocity(ctx, KV, B.body_frame(), X.inverse().translation(), W, W)
            col = Jw[:, mt.v[0]]  # [w; v of the body point at the world origin]
            axis = anchor = None
            if mt.kind == "hinge":
                w = col[:3]
                axis, anchor = w / np.linalg.norm(w), np.cross(w, col[3:]) / (w @ w)
            elif mt.kind == "slide":
                axis = col[3:] / np.linalg.norm(col[3:])
            else:
                anchor = dj.frame_on_child().CalcPoseInWorld(ctx).translation().copy()
            joints.append(BuiltJoint(jt.name, "free" if mt.kind == "floating" else mt.kind, tree.bodies[b].name, axis,
                                anchor, reflected[list(mt.v)], np.asarray(dj.default_damping_vector(), dtype=float)))
        links = tuple(self._link(name, head) for name, head in self.heads.items())
        every = [p.get_body(BodyIndex(i)) for i in range(1, p.num_bodies())]  # 0 is the world
        bodies = tuple(b.name() for b in every)
        return Structure(p.num_positions(), p.num_velocities(), tuple(joints), links, self.gravity0.copy(),
                         moving_mass(links), bodies)

    # --- evaluations ----------------------------------------------------------------------------------------

    def _gravity(self, effects):
        g = self.gravity0 if effects is None or effects.gravity is None else effects.gravity
        self.plant.mutable_gravity_field().set_gravity_vector(np.asarray(g, dtype=float))

    def _where(self, spec):
        """``(body, p_B)``: the body a point spec is fixed on and its place in the body's frame."""
        kind, name = spec
        p = self.plant
        if kind == "com":
            head = self.heads[name]
            link = self._link(name, head)
            X = p.EvalBodyPoseInWorld(self.context, head)
            return head, X.inverse().multiply(link.com)
        if kind == "body":  # by name, else (an unnamed body: Drake names it otherwise) by the joint that moves it
            if p.HasBodyNamed(name):
                body = p.GetBodyByName(name)
            elif name in self.heads:
                body = self.heads[name]
            else:
                raise EngineError(f"{self.source or 'the plant'}: relacc finds no Drake body for {name!r} (its parser "
                                  "names it otherwise and no matched joint moves it)")
            return body, np.asarray(self.reference.bodies[self.reference.body(name)].com, dtype=float)
        if not p.HasFrameNamed(name):
            raise EngineError(f"{self.source or 'the plant'}: Drake has no frame named {name!r}")
        frame = p.GetFrameByName(name)
        return frame.body(), frame.GetFixedPoseInBodyFrame().translation()

    def load_forces(self, qe, effects, t=0.0) -> np.ndarray:
        """Body loads through ``CalcJacobianSpatialVelocity`` at the bodies' mass centres (world components): ``J^T``
        of the wrench ``(T, F)``. Steppers call this at every stage: each body's frame and point are found once per
        ``effects``."""
        p, ctx, W = self.plant, self.context, self.plant.world_frame()
        tau = np.zeros((len(qe), self.nv_e))
        if self._load_plan is None or self._load_plan[0] is not effects:
            where = {name: self._where(("body", name)) for name in effects.bodies}
            self._load_plan = (effects, [(where[name][0].body_frame(), where[name][1], np.r_[load.torque, load.force],
                                          load) for name, load in effects.bodies.items()])
        for i in range(len(qe)):
            p.SetPositions(ctx, qe[i])
            ti = t[i] if np.ndim(t) else t
            for frame, p_B, wrench, load in self._load_plan[1]:
                J = p.CalcJacobianSpatialVelocity(ctx, KV, frame, p_B, W, W)
                tau[i] += float(load.factor(ti)) * wrench @ J
        return tau

    def equations(self, qe, ve, effects=None, t=0.0):
        p, ctx = self.plant, self.context
        n = len(qe)
        tau = self.generalized_forces(qe, ve, effects, t)
        M, f = np.empty((n, self.nv_e, self.nv_e)), np.empty((n, self.nv_e))
        self._gravity(effects)
        try:
            for i in range(n):
                self._set(qe[i], ve[i])
                M[i] = p.CalcMassMatrix(ctx)
                f[i] = tau[i] + p.CalcGravityGeneralizedForces(ctx) - p.CalcBiasTerm(ctx)
        finally:
            self._gravity(None)
        return M, f

    def forward(self, qe, ve, effects=None, t=0.0):
        """Drake's forward dynamics; a state where Drake finds an articulated mass matrix not positive definite (a
        joint that moves no inertia) is NaN: its forward dynamics is undefined, as the comparison reads it."""
        p, ctx = self.plant, self.context
        tau = self.generalized_forces(qe, ve, effects, t)
        quiet(p, ctx)
        out = np.empty((len(qe), self.nv_e))
        self._gravity(effects)
        try:
            for i in range(len(qe)):
                self._set(qe[i], ve[i])
                p.get_applied_generalized_force_input_port().FixValue(ctx, tau[i])
                try:
                    out[i] = p.get_generalized_acceleration_output_port().Eval(ctx)
                except RuntimeError as exc:
                    if "not positive-definite" not in str(exc):
                        raise
                    out[i] = np.nan
        finally:
            self._gravity(None)
            p.get_applied_generalized_force_input_port().FixValue(ctx, np.zeros(self.nv_e))
        return out

    def _autodiff(self):
        if self._ad is None:
            plant = self.plant.ToAutoDiffXd()
            self._ad = (plant, plant.CreateDefaultContext())
        return self._ad

    def points(self, qe, ve, ae, specs, *, jdot=False):
        p, ctx, W = self.plant, self.context, self.plant.world_frame()
        self._set(self.engine_q(reference_q(self.reference, 2))[0])
        where = [self._where(s) for s in specs]
        n, P, nv = len(qe), len(specs), self.nv_e
        pos, J, Jdv = np.empty((n, P, 3)), np.empty((n, P, 3, nv)), np.empty((n, P, 3))
        Jd = np.empty((n, P, 3, nv))  # returned only with jdot
        acc = np.empty((n, P, 3))  # returned only with ae
        for i in range(n):
            self._set(qe[i], ve[i])
            A = None if ae is None else p.CalcSpatialAccelerationsFromVdot(ctx, ae[i])
            for k, (body, p_B) in enumerate(where):
                X = p.EvalBodyPoseInWorld(ctx, body)
                pos[i, k] = X.multiply(p_B)
                J[i, k] = p.CalcJacobianTranslationalVelocity(ctx, KV, body.body_frame(), p_B, W, W)
                Jdv[i, k] = p.CalcBiasTranslationalAcceleration(ctx, KV, body.body_frame(), p_B, W, W).ravel()
                if A is not None:
                    w = p.EvalBodySpatialVelocityInWorld(ctx, body).rotational()
                    acc[i, k] = A[body.index()].Shift(X.rotation().multiply(p_B), w).translational()
            if jdot:
                ad_plant, ad_ctx = self._autodiff()
                qdot = p.MapVelocityToQDot(ctx, ve[i])
                ad_plant.SetPositions(ad_ctx, InitializeAutoDiff(qe[i], qdot.reshape(-1, 1))[:, 0])
                for k, (body, p_B) in enumerate(where):
                    frame = ad_plant.get_body(body.index()).body_frame()
                    Jad = ad_plant.CalcJacobianTranslationalVelocity(ad_ctx, KV, frame, p_B, ad_plant.world_frame(),
                                                                     ad_plant.world_frame())
                    Jd[i, k] = _derivative(Jad)
        return Points(pos, J, Jd if jdot else None, Jdv, None if ae is None else acc)

    def stepper(self, effects, dt, integrator, accuracy=None):
        return run.stepper(self, effects, dt, integrator, accuracy)

    def point_loop(self, qe, ve, ae, spec, full: bool = False):
        """The throughput anchor: a closure looping Drake over the states for one point's classical acceleration
        (``SetPositions``, ``SetVelocities``, ``CalcSpatialAccelerationsFromVdot``, the body's pose and spatial
        velocity, the shift to the point); results in its ``acc`` attribute ``(n, 3)``. ``full`` is not offered."""
        p, ctx = self.plant, self.context
        body, p_B = self._where(spec)
        n = len(qe)
        acc = np.empty((n, 3))

        def loop():
            for i in range(n):
                p.SetPositions(ctx, qe[i])
                p.SetVelocities(ctx, ve[i])
                A = p.CalcSpatialAccelerationsFromVdot(ctx, ae[i])[body.index()]
                X = p.EvalBodyPoseInWorld(ctx, body)
                w = p.EvalBodySpatialVelocityInWorld(ctx, body).rotational()
                acc[i] = A.Shift(X.rotation().multiply(p_B), w).translational()

        return Loop(loop, acc=acc)

    def applied(self, effects) -> dict:
        from relacc.engines.base import describe

        return {"gravity field and generalized forces (LeafSystem)": describe(effects)}

    def energy(self, qe, ve, effects):
        """``(kinetic, gravity, spring)`` energies ``(n,)`` J by Drake itself (its quaternions are integrated as
        coordinates, so their norm drifts by rounding: relacc's formulas accept unit quaternions only); the
        springs' from the reference's coordinates."""
        from relacc.dynamics.tree_energy import spring_energy

        p, ctx = self.plant, self.context
        T, V = np.empty(len(qe)), np.empty(len(qe))
        self._gravity(effects)
        try:
            for i in range(len(qe)):
                self._set(qe[i], ve[i])
                T[i], V[i] = p.CalcKineticEnergy(ctx), p.CalcPotentialEnergy(ctx)
        finally:
            self._gravity(None)
        q, _ = self.from_engine(qe, ve)
        return T, V, spring_energy(self.reference, q, effects)

    def momenta(self, qe, ve):
        """Drake's linear (kg m/s) and angular (kg m^2/s, about the world origin) momenta ``(n, 3)``."""
        p, ctx = self.plant, self.context
        lin, ang = np.empty((len(qe), 3)), np.empty((len(qe), 3))
        for i in range(len(qe)):
            self._set(qe[i], ve[i])
            L = p.CalcSpatialMomentumInWorldAboutPoint(ctx, np.zeros(3))
            lin[i], ang[i] = L.translational(), L.rotational()
        return lin, ang


def _derivative(matrix) -> np.ndarray:
    """The first derivative component of a matrix of ``AutoDiffXd`` (0 where it has none)."""
    flat = np.asarray(matrix).ravel()
    grad = np.asarray(ExtractGradient(flat))
    out = grad[:, 0] if grad.shape[1] else np.zeros(flat.size)
    return out.reshape(np.shape(matrix))


def load(path, reference=None, *, build=False, **options) -> DrakeAdapter:
    """The one loader signature: ``path`` read by Drake's parser (or, ``build``, the plant of ``reference``),
    matched to ``reference``.

    Raises:
        ModelError: Drake cannot read the file. EngineError: a tree Drake's plant builder does not take.
    """
    if reference is None:  # relacc's own reading, never another engine's
        from relacc.reading import read_tree

        reference = read_tree(path)
    return DrakeAdapter(path, reference, build=build)
