"""The one comparison primitive of the harness: an evaluation against a reference, state by state.

Every comparison relacc makes (``relacc check``, the errata, the hard-case
catalogue, the Hypothesis search, the report) is a :class:`Comparison`: the
normalized error of one quantity per state (:func:`relacc.core.tolerances.normalized_error`,
normalized by :func:`relacc.core.scales.term_scales`) against that state's
bound from the evaluator's accuracy model. Two sources of comparisons:

* :func:`against_engines`: each engine and route against the core
  (the engine's bound: :meth:`relacc.engines.chain.ChainEngine.bound`);
* :func:`against_derivatives`: the core against complex-step derivatives
  of its own position, velocity and V along the motion (bound ``c eps``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from relacc.core.conventions import CONVENTIONS, QUANTITIES, Route
from relacc.core.derivatives import along_motion
from relacc.core.kinematics import g2_kinematics
from relacc.core.tolerances import EPS, normalized_error, rounding_tolerance

CORE = "relacc"
"""The evaluator name of the core checked against its own complex-step derivatives."""

DERIVED = ("velocity", "V", "acceleration", "Vdot")
"""Quantities the core is checked against complex-step derivatives for (``V`` through ``V u``)."""


def routes_for(case) -> tuple[str, ...]:
    """Engine routes that apply to a case: quaternion always, euler for case 3."""
    return (Route.QUATERNION, Route.EULER) if int(case) == 3 else (Route.QUATERNION,)


@dataclass(frozen=True, eq=False)
class Comparison:
    """One evaluator x route x case x quantity, state by state: the one comparison result, for the chain and for
    any model (a model's rows carry what explains them too: :class:`ModelComparison`).

    Attributes:
        case: 1, 2 or 3.
        engine: the evaluator: an engine's name, :data:`CORE` for the core
            against complex-step derivatives, ``relacc (case c)`` for relacc's tree of a model.
        route: ``quaternion`` or ``euler`` for the chain's engines, ``complex-step`` for the core,
            ``model`` for a model file's.
        quantity: one of :data:`relacc.core.conventions.QUANTITIES`, or of a model's
            (:data:`relacc.core.conventions.MODEL_QUANTITIES`).
        errors: ``(n,)`` normalized error per state (dimensionless; inf where a value is undefined).
        bounds: ``(n,)`` the evaluator's accuracy model per state (``c eps``
            times a condition, plus any offset the engine's model loses).
        finite: every value the evaluator returned is finite.
        tolerance: ``c eps``, the error model's bound for a condition of 1.
    """

    case: int
    engine: str
    route: str
    quantity: str
    errors: np.ndarray = field(repr=False)
    bounds: np.ndarray = field(repr=False)
    finite: bool = True
    tolerance: float = field(default_factory=rounding_tolerance)

    @property
    def evaluator(self) -> str:
        """``relacc`` for the core, else ``<engine>/<route>``."""
        return CORE if self.engine == CORE else f"{self.engine}/{self.route}"

    @property
    def max_error(self) -> float:
        return float(np.max(self.errors))

    @property
    def median_error(self) -> float:
        return float(np.median(self.errors))

    @property
    def worst_state(self) -> int:
        """Index (in the batch) of the state with the largest error / bound."""
        return int(np.argmax(self.errors / self.bounds))

    @property
    def max_ratio(self) -> float:
        """Largest error relative to its state's bound; passes when <= 1 (inf if a value is not finite)."""
        return float(np.max(self.errors / self.bounds)) if self.finite else float("inf")

    @property
    def max_bound(self) -> float:
        return float(np.max(self.bounds))

    @property
    def passed(self) -> bool:
        return self.finite and bool(np.all(self.errors <= self.bounds))

    def as_json(self) -> dict:
        """Plain data (``relacc check --json``)."""
        out = {
            "case": self.case,
            "engine": self.engine,
            "route": self.route,
            "quantity": self.quantity,
            "max_error": _finite(self.max_error),
            "median_error": _finite(self.median_error),
            "max_error_eps": _finite(self.max_error / EPS),
            "tolerance": self.tolerance,
            "max_bound": self.max_bound,
            "max_ratio": _finite(self.max_ratio),
            "passed": self.passed,
            "worst_state": self.worst_state,
        }
        if self.quantity in CONVENTIONS:
            out["convention"] = CONVENTIONS[self.quantity]
        return out


def _finite(x: float) -> float | None:
    """JSON has no infinity: an undefined or infinite error or difference is written ``null``."""
    return x if np.isfinite(x) else None


@dataclass(frozen=True, eq=False)
class ModelComparison(Comparison):
    """A model file's :class:`Comparison` (``relacc compare``, ``relacc check --model``), with what explains it.

    Attributes:
        max_difference: the largest absolute difference over the states, in the quantity's units.
        cause: why it differs, reproduced (empty where it agrees).
        singular: ``{evaluator: [joints]}`` where a mass matrix over the shared speeds is exactly singular.
        per_link: ``{link: worst normalized error over the states}`` for the quantities of each link's mass centre
            (empty otherwise).
        cause_kind: what kind of cause ``cause`` is (:mod:`relacc.validation.robots.causes`): ``explained``, ``not
            explained``, ``finding``, ``taken``, ``singular``, ``urdf`` or empty.
    """

    max_difference: float = 0.0
    cause: str = ""
    singular: dict = field(default_factory=dict)
    per_link: dict = field(default_factory=dict)
    cause_kind: str = ""

    def as_row(self) -> dict:
        """A model's row (``relacc compare --json``): worst error and state, tolerance, largest difference, cause."""
        row: dict[str, object] = {"max_error": _finite(self.max_error), "tolerance": self.tolerance, "ok": self.passed,
               "state": self.worst_state, "max_difference": _finite(self.max_difference), "cause": self.cause,
               "cause_kind": self.cause_kind}
        if self.singular:
            row["singular"] = self.singular
        return row


def compare_values(case, engine: str, route: str, quantity: str, value, reference, scale, bounds) -> Comparison:
    """Compare ``value`` with ``reference`` (both ``(n, ...)``) through the normalized error.

    Args:
        scale: ``(n,)`` magnitude of the terms (:func:`relacc.core.scales.term_scales`).
        bounds: ``(n,)`` or scalar, the evaluator's accuracy model per state.
    """
    errors = np.atleast_1d(normalized_error(value, reference, scale))
    bounds = np.broadcast_to(np.asarray(bounds, dtype=float), errors.shape)
    return Comparison(int(case), engine, route, quantity, errors, bounds, bool(np.all(np.isfinite(value))))


def against_engines(engines: dict, chain, case, q, u, udot, core, scales, *, quantities=QUANTITIES,
                    evaluate=None) -> list[Comparison]:
    """Each engine and route of ``case`` against the core's result ``core``, every quantity.

    Args:
        engines: ``{name: Engine}``.
        core: the core's :class:`relacc.G2Kinematics` for the states ``q, u, udot``.
        scales: :class:`relacc.core.scales.TermScales` of those states.
        evaluate: ``(name, engine, route) -> G2Kinematics``; default
            ``engine.g2_kinematics(case, q, u, udot, route=route)`` (a harness passes its cache).
    """
    out = []
    for name, engine in engines.items():
        for route in routes_for(case):
            ke = (evaluate(name, engine, route) if evaluate is not None
                  else engine.g2_kinematics(case, q, u, udot, route=route))
            for qty in quantities:
                out.append(compare_values(case, name, route, qty, getattr(ke, qty), getattr(core, qty), scales.of(qty),
                                   engine.bound(route, qty, chain, case, q, u, udot)))
    return out


def against_derivatives(chain, case, q, u, udot, core, scales, *, quantities=DERIVED) -> list[Comparison]:
    """The core against complex-step derivatives of its own outputs along the motion (bound ``c eps``).

    ``velocity`` and ``V u`` against ``d/dt position``, ``acceleration``
    against ``d/dt velocity``, ``Vdot`` against ``d/dt V`` (:func:`relacc.core.derivatives.along_motion`).
    """
    def field_of(name):
        return lambda qq, uu: getattr(g2_kinematics(chain, case, qq, uu), name)

    refs = {}
    if {"velocity", "V"} & set(quantities):
        refs["position"] = along_motion(case, q, u, None, field_of("position"))
    if "acceleration" in quantities:
        refs["velocity"] = along_motion(case, q, u, udot, field_of("velocity"))
    if "Vdot" in quantities:
        refs["V"] = along_motion(case, q, u, None, field_of("V"))
    pairs = {"velocity": (core.velocity, refs.get("position"), scales.velocity),
             "V": (np.einsum("...ij,...j->...i", core.V, u), refs.get("position"), scales.velocity),
             "acceleration": (core.acceleration, refs.get("velocity"), scales.acceleration),
             "Vdot": (core.Vdot, refs.get("V"), scales.Vdot)}
    return [compare_values(case, CORE, "complex-step", qty, *pairs[qty], rounding_tolerance()) for qty in quantities]
