"""Drake adapter: imports only ``pydrake``.

The plant (``MultibodyPlant``, continuous time) is built from the chain's
TOML values, the same source as the other engines' MJCF and URDF files:

* B1 joins the world through a ``QuaternionFloatingJoint``; B2 joins the
  frame ``Q2`` fixed on B1 at ``q2'`` (B1's axes) through a second
  ``QuaternionFloatingJoint``, whose translation is the prismatic offset
  ``s2'`` and whose rotation is ``quat_B2/B1``: the three slides and the ball
  of the chain, with no rotation-angle singularity anywhere. G2 is the frame
  ``G2`` fixed on B2 at ``r2'``.
* Drake's own MJCF parser reads ``two_body.xml`` with the same masses,
  mass centers and inertias, but turns the ball into a ``BallRpyJoint``
  (roll-pitch-yaw positions, singular at pitch +-pi/2) and ignores sites, so
  G2 would be lost; ``tests/test_drake.py`` checks it against this plant.
  The euler route loads ``two_body_euler.urdf`` through Drake's URDF parser,
  which reads it whole (checked by the same test).

Conventions of Drake, converted here and nowhere else:

* A ``QuaternionFloatingJoint``'s positions are ``[qw, qx, qy, qz, x, y, z]``:
  the quaternion first (scalar first, the child's orientation in the parent
  frame), then the child origin's position in the parent frame. So
  ``q = [quat_B1, s1, quat_B2/B1, s2']``.
* Its velocities are ``[w_FM, v_FM]``: the child's angular velocity in the
  parent frame F and its origin's velocity in F, both in **F's components**.
  For B1, F is the world: ``[omega_B1 (fixed), s1_dot (fixed)]``; for B2, F is
  ``Q2`` on B1: ``[omega_hat_B2 (B1), s2'_dot (B1)]``. Drake's velocities
  are therefore Case 1's speeds, reordered; from the body speeds
  ``nu`` of :mod:`relacc.core.speeds`, ``v_e = [P] nu`` with
  ``P = [[0, R1^T, 0, 0], [I, 0, 0, 0], [0, 0, 0, R21], [0, 0, I, 0]]``
  (``R1^T`` the matrix of ``quat_B1``, ``R21`` that of ``quat_B2/B1``) and
  ``P_dot`` holding ``R1^T [omega'_B1~]`` and ``R21 [omega_hat'_B2~]``.
* Euler route: the URDF's prismatic and revolute joints give ``q``, ``v`` =
  Case 3's own coordinates and rates (no map).

APIs: ``CalcPointsPositions``; ``CalcJacobianTranslationalVelocity`` (with
respect to ``v``, G2 in the world, world components). Drake has no
Jacobian-rate matrix, only the bias ``J_dot v``
(``CalcBiasTranslationalAcceleration``); ``J_dot`` is Drake's own automatic
differentiation of ``J`` along ``q_dot = N(q) v`` (``ToAutoDiffXd``). The
classical acceleration comes from Drake's acceleration kinematics,
``CalcSpatialAccelerationsFromVdot``, shifted from B2's origin to G2
(``SpatialAcceleration.Shift``), independently of ``J_dot``. Dynamics:
``CalcMassMatrix``, ``CalcBiasTerm`` (``C(q, v) v``),
``CalcGravityGeneralizedForces``; the effects' generalized forces are put on
the joint coordinates (spring, dampers) and through Jacobians (force at G2,
torques). Simulation: Drake's ``Simulator`` with its own integrators
(:data:`relacc.core.conventions.DRAKE_SCHEMES`), fixed-step or error-controlled, and a ``LeafSystem`` that
applies exactly the scene's effects and nothing else (gravity through the
plant's gravity field, set to the scene's or to zero).

Accuracy far from the origin (measured, ``docs/hard-cases.md``): Drake
forms point velocities and Jacobians in the world frame from world
positions, so they lose about ``eps |s1|`` per metre of lever like the other
engines (``global_coordinates``); its acceleration kinematics, propagated
body by body, and its positions keep full accuracy.
"""

from __future__ import annotations

import numpy as np
from pydrake.autodiffutils import ExtractGradient, InitializeAutoDiff
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import (
    FixedOffsetFrame,
    JacobianWrtVariable,
    QuaternionFloatingJoint,
    RotationalInertia,
    SpatialInertia,
)
from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator
from pydrake.systems.framework import BasicVector, DiagramBuilder, LeafSystem

from relacc.core.conventions import DRAKE_SCHEMES
from relacc.core.rotations import matrix_from_quaternion, tilde
from relacc.dynamics.steps import Stepper
from relacc.engines.base import Engine, PointKinematics, identity_input, note_from_quaternions, quaternion_route_input
from relacc.errors import EngineError, FixtureError, IntegrationError
from relacc.fixtures import Fixture

KV = JacobianWrtVariable.kV

SAME_SCHEME = {"euler": "semi_explicit_euler"}
"""A scene integrator Drake has under another name: semi-implicit Euler (``v`` first, then ``q`` with the new ``v``)."""

def _inertia(m, com, I) -> SpatialInertia:
    """A body's spatial inertia about its origin from mass (kg), mass center (m) and central inertia (kg m^2)."""
    return SpatialInertia.MakeFromCentralInertia(
        float(m), np.asarray(com, dtype=float),
        RotationalInertia(I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]))


def build_plant(chain) -> MultibodyPlant:
    """The chain as a finalized continuous-time ``MultibodyPlant`` (module docstring), gravity off."""
    plant = MultibodyPlant(0.0)
    b1 = plant.AddRigidBody("B1", _inertia(chain.m1, chain.r1, chain.I1))
    b2 = plant.AddRigidBody("B2", _inertia(chain.m2, chain.r2, chain.I2))
    plant.AddJoint(QuaternionFloatingJoint("B1_free", plant.world_frame(), b1.body_frame()))
    q2 = plant.AddFrame(FixedOffsetFrame("Q2", b1.body_frame(), RigidTransform(np.asarray(chain.q2, dtype=float))))
    plant.AddJoint(QuaternionFloatingJoint("B2_slides_ball", q2, b2.body_frame()))
    plant.AddFrame(FixedOffsetFrame("G2", b2.body_frame(), RigidTransform(np.asarray(chain.r2, dtype=float))))
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
    plant.Finalize()
    return plant


def engine_q(q14):
    """``[s1, quat_B1, s2', quat_B2/B1]`` ``(n, 14)`` -> Drake's ``[quat_B1, s1, quat_B2/B1, s2']``."""
    return np.concatenate([q14[:, 3:7], q14[:, 0:3], q14[:, 10:14], q14[:, 7:10]], 1)


def q14_of(q_e):
    """Drake's positions ``(n, 14)`` -> ``[s1, quat_B1, s2', quat_B2/B1]``."""
    return np.concatenate([q_e[:, 4:7], q_e[:, 0:4], q_e[:, 11:14], q_e[:, 7:11]], 1)


class _Route:
    """A plant with its context, its G2 frame, and (on first use) its AutoDiff twin for ``J_dot``."""

    def __init__(self, plant: MultibodyPlant):
        self.plant = plant
        self.context = plant.CreateDefaultContext()
        self.g2 = plant.GetFrameByName("G2")
        self.body = self.g2.body()  # B2 (built plant) or the URDF's G2 link, welded to B2
        self.offset = self.g2.GetFixedPoseInBodyFrame().translation()  # G2 from that body's origin, its components
        self._ad = None

    def autodiff(self):
        if self._ad is None:
            plant = self.plant.ToAutoDiffXd()
            self._ad = (plant, plant.CreateDefaultContext(), plant.GetFrameByName("G2"))
        return self._ad


def _load_urdf(path) -> MultibodyPlant:
    plant = MultibodyPlant(0.0)
    try:
        Parser(plant).AddModels(str(path))
    except Exception as exc:  # Drake's parser raises RuntimeError with its message
        raise FixtureError(f"{path}: Drake cannot load it: {exc}") from None
    plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0])
    plant.Finalize()
    if not plant.HasFrameNamed("G2"):
        raise FixtureError(f"{path}: Drake finds no frame named G2")
    return plant


class _Effects(LeafSystem):
    """Applies the generalized forces of exactly the given effects (gravity excepted: the plant's field)."""

    def __init__(self, engine: "DrakeEngine", effects):
        super().__init__()
        self.engine, self.effects = engine, effects
        self.nq, self.nv = 14, 12
        self.state = self.DeclareVectorInputPort("state", BasicVector(self.nq + self.nv))
        self.DeclareVectorOutputPort("tau", BasicVector(self.nv), self._calc)

    def _calc(self, context, output):
        x = self.state.Eval(context)
        output.SetFromVector(self.engine.generalized_forces(x[:self.nq], x[self.nq:], self.effects))


class DrakeEngine(Engine):
    """Drake's ``MultibodyPlant``: the chain built from its TOML (quaternion route) and its URDF (euler route)."""

    name = "drake"
    global_coordinates = frozenset({"velocity", "V", "Vdot"})

    def __init__(self, fixture: Fixture):
        self.chain = fixture.chain
        with fixture.engine_files() as paths:
            euler = _load_urdf(paths["two_body_euler.urdf"])
        self.routes = {"quaternion": _Route(build_plant(fixture.chain)), "euler": _Route(euler)}

    @property
    def version(self) -> str:
        import pydrake

        return getattr(pydrake, "__version__", None) or _distribution_version()

    def engine_input(self, route, case, q, u, udot):
        if route == "euler":
            return identity_input(q, u, udot)
        n = q.shape[0]

        def P(q14, nu):
            out = np.zeros((n, 12, 12))
            out[:, 0:3, 3:6] = matrix_from_quaternion(q14[:, 3:7])  # omega_B1 = [R_B1]^T omega'_B1
            out[:, 3:6, 0:3] = np.eye(3)
            out[:, 6:9, 9:12] = matrix_from_quaternion(q14[:, 10:14])  # omega_hat_B2 = [^{B2}R_{B1}] omega_hat'_B2
            out[:, 9:12, 6:9] = np.eye(3)
            return out

        def P_dot(q14, nu):
            out = np.zeros((n, 12, 12))
            out[:, 0:3, 3:6] = matrix_from_quaternion(q14[:, 3:7]) @ tilde(nu[:, 3:6])
            out[:, 6:9, 9:12] = matrix_from_quaternion(q14[:, 10:14]) @ tilde(nu[:, 9:12])
            return out

        return quaternion_route_input(case, q, u, udot, P, P_dot, engine_q)

    def note_coordinates(self, route, case, q_e):
        return q_e if route == "euler" else note_from_quaternions(case, q14_of(q_e))

    def body_state(self, q, v):
        q, v = np.atleast_2d(q), np.atleast_2d(v)
        q14 = q14_of(q)
        R1_T, R21 = matrix_from_quaternion(q14[:, 3:7]), matrix_from_quaternion(q14[:, 10:14])
        nu = np.concatenate([v[:, 3:6], np.einsum("nji,nj->ni", R1_T, v[:, 0:3]), v[:, 9:12],
                             np.einsum("nji,nj->ni", R21, v[:, 6:9])], 1)
        return q14, nu

    def points(self, route, q, v, a):
        r = self.routes[route]
        plant, ctx, g2, world = r.plant, r.context, r.g2, r.plant.world_frame()
        n, nv = q.shape[0], plant.num_velocities()
        pos, J, Jd = np.empty((n, 3)), np.empty((n, 3, nv)), np.empty((n, 3, nv))
        acc = None if a is None else np.empty((n, 3))
        ad_plant, ad_ctx, ad_g2 = r.autodiff()
        zero = np.zeros(3)
        for i in range(n):
            plant.SetPositions(ctx, q[i])
            plant.SetVelocities(ctx, v[i])
            pos[i] = plant.CalcPointsPositions(ctx, g2, zero, world)[:, 0]
            J[i] = plant.CalcJacobianTranslationalVelocity(ctx, KV, g2, zero, world, world)
            qdot = plant.MapVelocityToQDot(ctx, v[i])
            ad_plant.SetPositions(ad_ctx, InitializeAutoDiff(q[i], qdot.reshape(-1, 1))[:, 0])
            Jad = ad_plant.CalcJacobianTranslationalVelocity(ad_ctx, KV, ad_g2, zero, ad_plant.world_frame(),
                                                             ad_plant.world_frame())
            Jd[i] = _derivative(Jad)
            if a is not None:
                A_B = plant.CalcSpatialAccelerationsFromVdot(ctx, a[i])[r.body.index()]
                X = plant.EvalBodyPoseInWorld(ctx, r.body)
                w = plant.EvalBodySpatialVelocityInWorld(ctx, r.body).rotational()
                p_BG2 = X.rotation().multiply(r.offset)  # the offset rotated into world: not a difference of positions
                acc[i] = A_B.Shift(p_BG2, w).translational()
        return PointKinematics(position=pos, J=J, J_dot=Jd, acceleration=acc)

    def generalized_forces(self, q, v, effects):
        """The effects' generalized forces ``(nv,)`` in Drake's coordinates, one state (gravity excepted).

        Spring and damper on ``s2'`` (positions 11-13, velocities 9-11, B1 axes);
        ball damping ``-c omega_hat_B2`` on velocities 6-8 (B1 components);
        force at G2 and torques on B1, B2 through the world-frame Jacobians.
        """
        r = self.routes["quaternion"]
        plant, ctx = r.plant, r.context
        tau = np.zeros(12)
        tau[9:12], tau[6:9] = effects.joint_forces(q[11:14], v[9:12], v[6:9])
        if {"force_G2", "torque_B1", "torque_B2"} & set(effects.active()):
            plant.SetPositions(ctx, q)
            world = plant.world_frame()
            if effects.force_G2 is not None:
                tau += plant.CalcJacobianTranslationalVelocity(ctx, KV, r.g2, np.zeros(3), world,
                                                               world).T @ effects.force_G2
            for body, torque in (("B1", effects.torque_B1), ("B2", effects.torque_B2)):
                if torque is not None:
                    frame = plant.GetBodyByName(body).body_frame()
                    tau += plant.CalcJacobianAngularVelocity(ctx, KV, frame, world, world).T @ torque
        return tau

    def _set_gravity(self, plant, effects):
        plant.mutable_gravity_field().set_gravity_vector([0.0, 0.0, 0.0] if effects.gravity is None
                                                         else effects.gravity)

    def dynamics(self, q, v, effects):
        r = self.routes["quaternion"]
        plant, ctx = r.plant, r.context
        n = q.shape[0]
        M, f = np.empty((n, 12, 12)), np.empty((n, 12))
        self._set_gravity(plant, effects)
        try:
            for i in range(n):
                plant.SetPositions(ctx, q[i])
                plant.SetVelocities(ctx, v[i])
                M[i] = plant.CalcMassMatrix(ctx)
                f[i] = (self.generalized_forces(q[i], v[i], effects) + plant.CalcGravityGeneralizedForces(ctx)
                        - plant.CalcBiasTerm(ctx))
        finally:
            self._set_gravity(plant, _NO_GRAVITY)
        return M, f

    def forward_dynamics(self, q, v, effects):
        M, f = self.dynamics(q, v, effects)
        return np.linalg.solve(M, f[..., None])[..., 0]

    def applied(self, effects) -> dict:
        g = "0 (off)" if effects.gravity is None else str(effects.gravity.tolist())
        forces = [n for n in effects.active() if n != "gravity"]
        return {"gravity field": g, "generalized forces (LeafSystem)": forces or "none"}

    def stepper(self, effects, dt, integrator, accuracy=None):
        """Drake's ``Simulator`` with one of ``DRAKE_SCHEMES``, fixed-step (``accuracy`` None) or error-controlled.

        Error-controlled runs keep ``dt`` as their largest step, so every
        record falls on a step. ``euler`` is Drake's ``semi_explicit_euler``
        (the same scheme); Drake has no RK4.
        """
        scheme = SAME_SCHEME.get(integrator, integrator)
        if scheme not in DRAKE_SCHEMES:
            raise EngineError(f"Drake has no {integrator!r} integrator; accepted: euler, {', '.join(DRAKE_SCHEMES)} "
                              "(a scene names Drake's in [simulate.drake] integrator)")
        builder = DiagramBuilder()
        plant = builder.AddSystem(build_plant(self.chain))
        self._set_gravity(plant, effects)
        forces = builder.AddSystem(_Effects(self, effects))
        builder.Connect(plant.get_state_output_port(), forces.get_input_port(0))
        builder.Connect(forces.get_output_port(0), plant.get_applied_generalized_force_input_port())
        diagram = builder.Build()
        simulator = Simulator(diagram)
        ResetIntegratorFromFlags(simulator, scheme, dt)
        integ = simulator.get_mutable_integrator()
        if accuracy is None:
            integ.set_fixed_step_mode(True)
        else:
            integ.set_fixed_step_mode(False)
            integ.set_target_accuracy(float(accuracy))
        context = simulator.get_mutable_context()
        pctx = plant.GetMyMutableContextFromRoot(context)
        steps = [0]

        def advance(x, w, k):
            plant.SetPositions(pctx, x)
            plant.SetVelocities(pctx, w)
            steps[0] += k
            try:
                simulator.AdvanceTo(steps[0] * dt)
            except RuntimeError as exc:  # Drake stops a run whose state has become meaningless (NaN, a step too long)
                raise IntegrationError(f"Drake's {scheme} stopped: {str(exc).splitlines()[0]}") from None
            return plant.GetPositions(pctx).copy(), plant.GetVelocities(pctx).copy()

        simulator.Initialize()
        return Stepper(advance)

    def energy_terms(self, chain, q, v, effects):
        """Drake's own kinetic and gravitational energy, and the spring's, J, for a batch of Drake states.

        Drake integrates its quaternions as coordinates (their norm may drift
        by rounding), so these come from Drake itself rather than from
        relacc's formulas, which accept unit quaternions only.
        """
        r = self.routes["quaternion"]
        plant, ctx = r.plant, r.context
        self._set_gravity(plant, effects)
        T, Vg = np.empty(len(q)), np.empty(len(q))
        try:
            for i in range(len(q)):
                plant.SetPositions(ctx, q[i])
                plant.SetVelocities(ctx, v[i])
                T[i], Vg[i] = plant.CalcKineticEnergy(ctx), plant.CalcPotentialEnergy(ctx)
        finally:
            self._set_gravity(plant, _NO_GRAVITY)
        return T, Vg, effects.spring_energy(q[:, 11:14])

    def momenta(self, chain, q, v):
        """Drake's linear (kg m/s) and angular (kg m^2/s, about R's origin) momenta, world components."""
        r = self.routes["quaternion"]
        plant, ctx = r.plant, r.context
        p, H = np.empty((len(q), 3)), np.empty((len(q), 3))
        for i in range(len(q)):
            plant.SetPositions(ctx, q[i])
            plant.SetVelocities(ctx, v[i])
            L = plant.CalcSpatialMomentumInWorldAboutPoint(ctx, np.zeros(3))
            p[i], H[i] = L.translational(), L.rotational()
        return p, H


class _Gravityless:
    gravity = None


_NO_GRAVITY = _Gravityless()


def _derivative(matrix) -> np.ndarray:
    """The first derivative component of a matrix of ``AutoDiffXd`` (0 where it has none)."""
    flat = np.asarray(matrix).ravel()
    grad = ExtractGradient(flat)
    out = grad[:, 0] if grad.shape[1] else np.zeros(flat.size)
    return out.reshape(np.shape(matrix))


def _distribution_version() -> str:
    from importlib.metadata import version

    return version("drake")
