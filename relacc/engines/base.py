"""The interface every engine adapter implements.

An adapter evaluates G2's position, velocity, classical acceleration, V and
Vdot for a case's state with an established engine and returns the core's
:class:`relacc.G2Kinematics`, all in fixed-frame components.

Two routes:

* ``"quaternion"`` (cases 1, 2, 3): the MJCF fixture ``two_body.xml``. The
  case's state goes to the body speeds of :mod:`relacc.core.speeds`
  (``nu = [W] u``), then to the engine's own velocity vector
  ``v_e = [P(q)] nu`` by the adapter's documented map ``P``. With
  ``[E] = [P][W]`` (``v_e = [E] u``) and ``[E_dot] = [P_dot][W] + [P][W_dot]``,
  ``V = [J][E]``, ``Vdot = [J_dot][E] + [J][E_dot]``, and the engine is handed
  ``a_e = [E] udot + [E_dot] u``.
* ``"euler"`` (case 3 only): the Euler-angle fixtures, whose joint positions
  and velocities *are* the case-3 ``q`` and ``u``: no mapping at all.

Each adapter computes the acceleration by the engine's own acceleration
routine, independently of its Jacobian time variation.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass

import numpy as np

from relacc.core.cases import Case, as_case, check_q, check_u
from relacc.core.kinematics import G2Kinematics, check_finite_result
from relacc.core.note.common import mv
from relacc.core.rotations import angles_123_from_matrix, matrix_from_quaternion
from relacc.core.scales import global_condition, offset_error
from relacc.core.speeds import body_speed_map, check_invertible, quaternion_coordinates
from relacc.core.tolerances import rounding_tolerance
from relacc.errors import EngineError

ROUTES = ("quaternion", "euler")


@dataclass(frozen=True)
class EngineInput:
    """A batch of states in an engine's own coordinates.

    Attributes:
        q: ``(n, nq_e)`` engine positions. v: ``(n, nv_e)`` velocities.
        a: ``(n, nv_e)`` accelerations (None without udot).
        E: ``(n, nv_e, 12)``, ``v_e = [E] u``. E_dot: ``(n, nv_e, 12)`` its rate.
    """

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray | None
    E: np.ndarray
    E_dot: np.ndarray


@dataclass(frozen=True)
class PointKinematics:
    """What the engine computes for G2 over a batch, in its own velocity coordinates.

    Attributes:
        position: ``(n, 3)`` G2 in world (= fixed frame R) components, m.
        J: ``(n, 3, nv_e)`` translational Jacobian of G2, world components.
        J_dot: ``(n, 3, nv_e)`` its time derivative along the motion.
        acceleration: ``(n, 3)`` classical acceleration of G2, world components,
            from the engine's acceleration routine (None without ``a``).
    """

    position: np.ndarray
    J: np.ndarray
    J_dot: np.ndarray
    acceleration: np.ndarray | None


class Engine(abc.ABC):
    """An engine loaded with the chain's fixtures.

    Subclasses set ``name`` (and ``global_coordinates``, the quantities the
    engine forms from differences of world positions) and implement the
    abstract methods, each converting the engine's conventions locally:

    * :attr:`version`;
    * :meth:`engine_input`, :meth:`note_coordinates`: the coordinate map of a
      route and its inverse;
    * :meth:`points`: G2's position, Jacobian, its rate and classical
      acceleration for a batch, in the engine's own velocity coordinates;
    * :meth:`dynamics`, :meth:`forward_dynamics`: the engine's ``M``, ``f``
      and accelerations under exactly the given effects;
    * :meth:`stepper`: its fixed-step integrator for :mod:`relacc.dynamics.steps`;
    * :meth:`body_state`: engine coordinates back to Case 2's ``(q14, nu)``.

    Everything else (:meth:`g2_kinematics`, :meth:`equations_of_motion`,
    :meth:`simulate`, :meth:`bound`, ...) is built on these here.
    """

    name: str = ""
    global_coordinates: frozenset = frozenset()
    """Quantities the engine forms from differences of world positions; their
    accuracy follows :func:`relacc.core.scales.global_condition`."""

    def lost_offset(self, route: str) -> float:
        """Metres by which the compiled model misplaces G2 (0 unless an engine rounds the model)."""
        return 0.0

    def bound(self, route: str, quantity: str, chain, case, q, u, udot=None):
        """Per-state bound on the normalized error of ``quantity`` against the core.

        ``c eps condition + offset``: the condition is
        :func:`relacc.core.scales.global_condition` for the quantities in
        ``global_coordinates`` (else 1), the offset
        :func:`relacc.core.scales.offset_error` of :meth:`lost_offset`.
        """
        cond = global_condition(quantity, chain, case, q, u, udot) if quantity in self.global_coordinates else 1.0
        return rounding_tolerance() * cond + offset_error(self.lost_offset(route), quantity, chain, case, q, u, udot)

    @property
    @abc.abstractmethod
    def version(self) -> str:
        """The engine's version string."""

    @abc.abstractmethod
    def engine_input(self, route: str, case: Case, q, u, udot) -> EngineInput:
        """Map a batch of a case's states to the engine's coordinates."""

    @abc.abstractmethod
    def note_coordinates(self, route: str, case: Case, q_e) -> np.ndarray:
        """Inverse of the coordinate map: engine positions ``(n, nq_e)`` to the case's ``q``."""

    def note_state(self, route: str, case, x: EngineInput):
        """Inverse of :meth:`engine_input`: ``(q, u, udot)`` of the case from engine coordinates.

        ``u = [E]^-1 v_e`` and ``udot = [E]^-1 (a_e - [E_dot] u)``. For case 3 on
        the quaternion route this goes through :func:`relacc.core.rotations.angles_123_from_matrix`,
        ill-conditioned near gimbal lock; it serves round-trip tests, not comparisons.

        Raises:
            SingularityError: case 3 within ``MAX_CONDITION`` of gimbal lock.
        """
        c = as_case(case)
        q = self.note_coordinates(route, c, x.q)
        check_invertible(c, q)
        u = np.linalg.solve(x.E, x.v[..., None])[..., 0]
        udot = None if x.a is None else np.linalg.solve(x.E, (x.a - mv(x.E_dot, u))[..., None])[..., 0]
        return q, u, udot

    @abc.abstractmethod
    def dynamics(self, q, v, effects):
        """Engine equations ``M_e vdot_e = f_e`` on the quaternion route, for a batch.

        Args:
            q, v: ``(n, nq_e)``, ``(n, nv_e)`` engine coordinates.
            effects: :class:`relacc.dynamics.effects.Effects`, the only effects applied.

        Returns:
            ``M_e`` ``(n, nv_e, nv_e)`` and ``f_e`` ``(n, nv_e)``: generalized
            forces of the effects minus the bias forces, in engine coordinates.
        """

    @abc.abstractmethod
    def forward_dynamics(self, q, v, effects):
        """Engine accelerations ``vdot_e`` ``(n, nv_e)`` at ``(q, v)`` under exactly ``effects`` (quaternion route)."""

    @abc.abstractmethod
    def stepper(self, effects, dt: float, integrator: str, accuracy: float | None = None):
        """The engine's integrator under exactly ``effects``, a :class:`relacc.dynamics.steps.Stepper`.

        Its ``advance(x, v, k)`` takes ``k`` steps of ``dt`` seconds from engine
        coordinates ``(x, v)`` (:mod:`relacc.dynamics.steps`). ``accuracy``: the target of
        an error-controlled integrator (its largest step ``dt``); None for
        fixed steps, the only kind most engines have.

        Raises:
            EngineError: an integrator the engine lacks, or an accuracy it cannot honour.
        """

    def simulate(self, q, v, effects, dt: float, n_steps: int, integrator: str, record_every: int = 1,
                 progress=None, accuracy: float | None = None):
        """Integrate from engine coordinates ``(q, v)`` for ``n_steps`` steps of ``dt`` seconds.

        Through the one step loop, :func:`relacc.dynamics.steps.collect`.

        Returns:
            ``(t, Q, V)``: times ``(m,)`` (s) and engine states ``(m, nq_e)``,
            ``(m, nv_e)`` every ``record_every`` steps and at the last step,
            the initial state first.

        Raises:
            IntegrationError: the run diverged. EngineError: unknown integrator.
        """
        from relacc.dynamics.steps import collect

        return collect(self.stepper(effects, dt, integrator, accuracy), q, v, dt, n_steps, record_every,
                       who=self.name, integrator=integrator, progress=progress)

    @abc.abstractmethod
    def body_state(self, q, v):
        """Engine coordinates ``(n, nq_e)``, ``(n, nv_e)`` to Case 2's ``(q14, nu)`` (quaternion route)."""

    @staticmethod
    def fixed_step_only(name: str, accuracy) -> None:
        """Refuse an error-controlled run for an engine that has fixed-step integrators only."""
        if accuracy is not None:
            raise EngineError(f"{name} has fixed-step integrators only; drop the accuracy (got {accuracy})")

    def applied(self, effects) -> dict:
        """What the engine is told to apply for ``effects``, as plain data for reports.

        Default: gravity through the model and every other effect as a
        generalized force; adapters that switch features off say which.
        """
        g = "0 (off)" if effects.gravity is None else str(effects.gravity.tolist())
        forces = [n for n in effects.active() if n != "gravity"]
        return {"model.gravity": g, "generalized forces": forces or "none"}

    def energy_terms(self, chain, q, v, effects):
        """``(kinetic, gravity, spring)`` energies, J, ``(n,)`` each, of a batch of engine states.

        Default: relacc's formulas (:func:`relacc.dynamics.energy_terms`) at the
        engine's state mapped to Case 2 (:meth:`body_state`).
        """
        from relacc.dynamics import energy_terms

        q14, nu = self.body_state(q, v)
        return energy_terms(chain, 2, q14, nu, effects)

    def momenta(self, chain, q, v):
        """Linear (kg m/s) and angular (kg m^2/s, about R's origin) momenta ``(n, 3)``, fixed components."""
        from relacc.dynamics import momenta

        q14, nu = self.body_state(q, v)
        return momenta(chain, 2, q14, nu)

    def initial_state(self, case, q, u):
        """One state of a case, ``q (nq,)``, ``u (12,)``, in engine coordinates on the quaternion route.

        Returns:
            ``(q_e (nq_e,), v_e (nv_e,))``, the engine's own units and frames.
        """
        x = self.engine_input("quaternion", as_case(case), np.asarray(q)[None], np.asarray(u)[None], None)
        return x.q[0], x.v[0]

    def equations_of_motion(self, case, q, u, effects):
        """The engine's ``(M, f)`` mapped to a case's speeds: ``E^T M_e E`` and ``E^T (f_e - M_e E_dot u)``.

        With ``v_e = E u``, ``vdot_e = E udot + E_dot u``; quaternion route.
        """
        c = as_case(case)
        q = check_q(c, q)
        u = check_u(f"u for case {int(c)}", u)
        x = self.engine_input("quaternion", c, np.atleast_2d(q), np.atleast_2d(u), None)
        Me, fe = self.dynamics(np.ascontiguousarray(x.q), np.ascontiguousarray(x.v), effects)
        M = np.swapaxes(x.E, -1, -2) @ Me @ x.E
        f = np.einsum("nji,nj->ni", x.E, fe - np.einsum("nij,njk,nk->ni", Me, x.E_dot, np.atleast_2d(u)))
        return M.reshape(q.shape[:-1] + (12, 12)), f.reshape(q.shape[:-1] + (12,))

    @abc.abstractmethod
    def points(self, route: str, q, v, a) -> PointKinematics:
        """Evaluate G2 for a batch ``(n, nq_e)``, ``(n, nv_e)`` in engine coordinates.

        One tight loop over the states with the engine's model and data
        reused; results go straight into preallocated arrays.
        """

    def g2_kinematics(self, case, q, u, udot=None, *, route="quaternion") -> G2Kinematics:
        """G2's kinematics by this engine, in the core's conventions.

        Args:
            case: 1, 2 or 3. q: ``(..., 14)`` or ``(..., 12)``; u, udot: ``(..., 12)``.
            route: ``"quaternion"`` (any case) or ``"euler"`` (case 3 only).

        Returns:
            :class:`relacc.G2Kinematics`, fixed-frame components, classical
            acceleration; ``variant`` names the engine and route.

        Raises:
            EngineError: unknown route or the euler route for cases 1-2.
            InputError: as :func:`relacc.g2_kinematics`.
        """
        c = as_case(case)
        if route not in ROUTES:
            raise EngineError(f"unknown route {route!r}: accepted are {', '.join(ROUTES)}")
        if route == "euler" and c is not Case.ANGLE_RATES:
            raise EngineError(f"the euler route takes case 3 states only, got case {int(c)}")
        q = check_q(c, q)
        u = check_u(f"u for case {int(c)}", u)
        udot = None if udot is None else check_u(f"udot for case {int(c)}", udot)
        batch = np.broadcast_shapes(q.shape[:-1], u.shape[:-1], () if udot is None else udot.shape[:-1])
        q = np.broadcast_to(q, batch + q.shape[-1:]).reshape(-1, q.shape[-1])
        u = np.broadcast_to(u, batch + (12,)).reshape(-1, 12)
        udot = None if udot is None else np.broadcast_to(udot, batch + (12,)).reshape(-1, 12)
        x = self.engine_input(route, c, q, u, udot)
        p = self.points(route, np.ascontiguousarray(x.q), np.ascontiguousarray(x.v),
                        None if x.a is None else np.ascontiguousarray(x.a))
        pos, acc = p.position, p.acceleration
        V = p.J @ x.E
        Vdot = p.J_dot @ x.E + p.J @ x.E_dot
        check_finite_result((pos, V, Vdot, acc), q, u, udot)
        shape = lambda a, tail: a.reshape(batch + tail)  # noqa: E731
        return G2Kinematics(
            position=shape(pos, (3,)),
            velocity=shape(np.einsum("nij,nj->ni", V, u), (3,)),
            acceleration=None if udot is None else shape(acc, (3,)),
            V=shape(V, (3, 12)),
            Vdot=shape(Vdot, (3, 12)),
            case=c,
            variant=f"{self.name}:{route}",
        )


def quaternion_route_input(case: Case, q, u, udot, P, P_dot, engine_q) -> EngineInput:
    """Build an :class:`EngineInput` from body speeds and an engine's map ``P``.

    Args:
        P, P_dot: functions ``(q14, nu) -> (n, nv_e, 12)`` giving the engine
            velocity map on top of the body speeds and its rate.
        engine_q: function ``q14 -> (n, nq_e)`` engine positions.
    """
    q14 = quaternion_coordinates(case, q)
    W, W_dot = body_speed_map(case, q, u)
    nu = mv(W, u)
    Pm, Pd = P(q14, nu), P_dot(q14, nu)
    E = Pm @ W
    E_dot = Pd @ W + Pm @ W_dot
    v = mv(E, u)
    a = None if udot is None else mv(E, udot) + mv(E_dot, u)
    return EngineInput(q=engine_q(q14), v=v, a=a, E=E, E_dot=E_dot)


def note_from_quaternions(case: Case, q14) -> np.ndarray:
    """Quaternion coordinates ``(n, 14)`` back to the case's ``q`` (angles for case 3)."""
    if case is not Case.ANGLE_RATES:
        return q14
    return np.concatenate(
        [
            q14[:, 0:3],
            angles_123_from_matrix(matrix_from_quaternion(q14[:, 3:7])),
            q14[:, 7:10],
            angles_123_from_matrix(matrix_from_quaternion(q14[:, 10:14])),
        ],
        1,
    )


def identity_input(q, u, udot) -> EngineInput:
    """The euler route: engine coordinates are the case-3 ``q``, ``u``, ``udot`` themselves."""
    n = q.shape[0]
    E = np.broadcast_to(np.eye(12), (n, 12, 12))
    return EngineInput(q=q, v=u, a=udot, E=E, E_dot=np.zeros((n, 12, 12)))
