"""What some engines offer beyond :class:`relacc.engines.base.Adapter`, one declared interface per capability (as
mink's ``lie/`` and robot_descriptions' loaders do): each is an :class:`Adapter` with more abstract methods, an adapter
class inherits each it implements (``class MujocoAdapter(Rollout, ..., Adapter)``), callers check it with
``isinstance`` (never an engine's name), and the contract test runs each over every engine that declares it.
Each is an engine's own compiled loop or batched call: the anchors relacc's benchmarks time it against (named by the
engine's :attr:`relacc.engines.traits.Traits.calls`), and the ensembles' fast paths. Imports no engine."""

from __future__ import annotations

import abc
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from relacc.engines.base import Adapter, Loop


class PointLoop(Adapter):
    """A per-state loop over one point, as a user would write it with the engine."""

    @abc.abstractmethod
    def point_loop(self, qe: np.ndarray, ve: np.ndarray, ae: np.ndarray, spec: tuple[str, str], full: bool = False
                   ) -> Loop:
        """A closure looping over the states for one point's classical acceleration (and, with ``full``, its
        position, Jacobian and its rate); the accelerations ``(n, 3)`` (m/s^2, world components) in its ``acc``."""


class KinematicsLoops(Adapter):
    """Per-state loops over many points, as a user would write them with the engine. ``LOOPS_ON_BODIES``: its bodies
    are the reference's bodies (a loop over them computes what relacc's tree does, body by body), else it loops over
    its own links' mass centres."""

    LOOPS_ON_BODIES: bool = False

    @abc.abstractmethod
    def jacobian_loop(self, qe: np.ndarray, ve: np.ndarray, specs: Sequence[tuple[str, str]]) -> Loop:
        """A closure looping over the states for every point's Jacobian and its rate."""

    @abc.abstractmethod
    def motion_loop(self, qe: np.ndarray, ve: np.ndarray, ae: np.ndarray, specs: Sequence[tuple[str, str]]) -> Loop:
        """A closure looping over the states for every point's position, velocity, classical acceleration, angular
        velocity and acceleration (no Jacobian); ``(n, P, 3)`` results in its ``pos``, ``vel``, ``acc`` attributes
        (m, m/s, m/s^2, world components)."""


class BatchedForward(Adapter):
    """The engine's own batched forward dynamics over threads."""

    @abc.abstractmethod
    def batched_forward(self, threads: int, qe: np.ndarray, ve: np.ndarray, gravity: ArrayLike | None = None) -> Loop:
        """A closure running the engine's batched forward dynamics on ``qe (nq_e, n)``, ``ve (nv_e, n)`` (columns are
        states, as the engine takes them) over ``threads`` threads."""


class Rollout(Adapter):
    """Every member's steps in the engine's own compiled loop."""

    @abc.abstractmethod
    def work_data(self, threads: int) -> list:
        """Per-thread working data for :meth:`rollout`."""

    @abc.abstractmethod
    def rollout(self, qpos: np.ndarray, qvel: np.ndarray, ends: np.ndarray, work: list) -> Any:
        """Every member's steps in the engine's own loop: ``(Q, V, first bad record, seconds)``."""

    @abc.abstractmethod
    def step_loop(self, qpos: np.ndarray, qvel: np.ndarray, n_steps: int) -> Callable[[], object]:
        """A closure stepping one state ``n_steps`` times from Python, the engine's step call by call."""

    @abc.abstractmethod
    def rollout_loop(self, qpos: np.ndarray, qvel: np.ndarray, n_steps: int, threads: int) -> Loop:
        """A closure running every state ``n_steps`` steps in the engine's own compiled loop."""


class ThreadedStepper(Adapter):
    """A stepper that advances a batch of members at once on threads (:meth:`stepper` with ``threads``), for the
    integrators in ``THREADED_INTEGRATORS``."""

    THREADED_INTEGRATORS: tuple[str, ...] = ()

    @abc.abstractmethod
    def stepper(self, effects: Any, dt: float, integrator: str, accuracy: float | None = None, threads: int = 1
                ) -> Any:
        """As :meth:`relacc.engines.base.Adapter.stepper`, its rows advanced together on ``threads`` threads."""


class ManifoldRates(Adapter):
    """The engine's configuration manifold and rates, for relacc's integrators (:mod:`relacc.dynamics.integrate`)."""

    @abc.abstractmethod
    def space(self) -> Any:
        """The engine's configuration manifold (``integrate``, ``dexpinv``)."""

    @abc.abstractmethod
    def derivs(self, effects: Any, threads: int = 1) -> Any:
        """``derivs(x, w, t) -> (w, vdot)`` under ``effects``, on :meth:`space`."""


class BodyMotion(Adapter):
    """The engine's own numbers for every body."""

    @abc.abstractmethod
    def body_motion(self, q: np.ndarray, u: np.ndarray, udot: np.ndarray) -> dict:
        """At engine states: ``position``, ``velocity``, ``omega``, ``acceleration``, ``alpha`` ``(n, nb, 3)``,
        ``V``, ``Omega`` ``(n, nb, 3, nv)``, fixed-frame components (m, m/s, rad/s, m/s^2, rad/s^2)."""


class AccelerationRoutine(Adapter):
    """A second routine for ``J_dot v``: the engine's :meth:`points` at zero rates give its points' classical
    acceleration from its acceleration routine, independently of the routine behind its Jacobian's rate, so that a
    difference in the first can be told from a difference in the model (:mod:`relacc.validation.robots.routines`)."""

    @abc.abstractmethod
    def jdot_cause(self, tree: Any) -> str:
        """The cause's sentence when the acceleration routine agrees with relacc and the Jacobian's rate does not:
        which of the engine's known cases it is, given relacc's tree."""


CAPABILITIES = (PointLoop, KinematicsLoops, BatchedForward, Rollout, ThreadedStepper, ManifoldRates, BodyMotion,
                AccelerationRoutine)
"""Every capability, for the contract test."""
