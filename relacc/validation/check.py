"""Cross-validation of the core against the engines: the harness behind ``relacc check``.

For every case x engine x route x quantity, the core's corrected formulas
and the engine are evaluated on the same seeded states and compared through
the normalized error of :mod:`relacc.core.tolerances`.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field

import numpy as np

import relacc
from relacc.core.cases import as_case, check_int
from relacc.core.conventions import CONVENTIONS, QUANTITIES
from relacc.core.kinematics import G2Kinematics, resolve_variant
from relacc.core.scales import term_scales
from relacc.core.states import States, random_states
from relacc.core.tolerances import EPS, normalized_error, rounding_tolerance
from relacc.engines import ENGINES, load_engine
from relacc.errors import EngineError
from relacc.fixtures import Fixture, load


def routes_for(case) -> tuple[str, ...]:
    """Engine routes that apply to a case: quaternion always, euler for case 3."""
    return ("quaternion", "euler") if int(case) == 3 else ("quaternion",)


@dataclass(frozen=True, eq=False)
class Comparison:
    """One case x engine x route x quantity comparison.

    Attributes:
        errors: ``(n,)`` normalized error per state (dimensionless).
        tolerance: ``c eps``, the error model's bound for a condition of 1.
        bounds: ``(n,)`` the engine's accuracy model per state
            (:meth:`relacc.engines.base.Engine.bound`: ``c eps`` times the
            condition, plus any offset the engine's model loses).
    """

    case: int
    engine: str
    route: str
    quantity: str
    errors: np.ndarray = field(repr=False)
    tolerance: float
    bounds: np.ndarray = field(repr=False)

    @property
    def max_error(self) -> float:
        return float(np.max(self.errors))

    @property
    def median_error(self) -> float:
        return float(np.median(self.errors))

    @property
    def worst_state(self) -> int:
        return int(np.argmax(self.errors))

    @property
    def max_ratio(self) -> float:
        """Largest error relative to its state's bound; pass when <= 1."""
        return float(np.max(self.errors / self.bounds))

    @property
    def max_bound(self) -> float:
        return float(np.max(self.bounds))

    @property
    def passed(self) -> bool:
        return bool(np.all(self.errors <= self.bounds))

    def as_dict(self) -> dict:
        return {
            "case": self.case,
            "engine": self.engine,
            "route": self.route,
            "quantity": self.quantity,
            "max_error": self.max_error,
            "median_error": self.median_error,
            "max_error_eps": self.max_error / EPS,
            "tolerance": self.tolerance,
            "max_bound": self.max_bound,
            "max_ratio": self.max_ratio,
            "passed": self.passed,
            "worst_state": self.worst_state,
            "convention": CONVENTIONS[self.quantity],
        }


class Harness:
    """Engines, fixture and seeded states, with cached evaluations.

    States of case ``c`` come from ``numpy.random.default_rng([seed, c])``.

    Args:
        fixture: the chain's fixture (default ``models/two_body.toml``).
        engines: engine names to load.
        n_states: states per case.
        seed: base seed.
        progress: callable taking one line of progress text, or None.
    """

    def __init__(self, fixture: Fixture | None = None, engines=ENGINES, n_states=1000, seed=0, progress=None):
        n_states = check_int("number of states", n_states, minimum=1)
        seed = check_int("seed", seed, minimum=0)
        self.fixture = fixture if fixture is not None else load()
        self.chain = self.fixture.chain
        engines = tuple(engines) if isinstance(engines, (list, tuple)) else (engines,)
        unknown = [e for e in engines if e not in ENGINES]
        if unknown:
            raise EngineError(f"unknown engines {unknown}: accepted are {', '.join(ENGINES)}")
        self.engines = {name: load_engine(name, self.fixture) for name in engines}
        self.n_states = int(n_states)
        self.seed = int(seed)
        self.progress = progress
        self._states, self._engine, self._core, self._scales = {}, {}, {}, {}

    def versions(self) -> dict:
        """Versions of relacc, Python, numpy and every loaded engine."""
        out = {"relacc": relacc.__version__, "python": sys.version.split()[0], "numpy": np.__version__}
        out.update({name: e.version for name, e in self.engines.items()})
        return out

    def states(self, case) -> States:
        c = int(as_case(case))
        if c not in self._states:
            self._states[c] = random_states(c, self.n_states, [self.seed, c])
        return self._states[c]

    def scales(self, case):
        c = int(case)
        if c not in self._scales:
            s = self.states(c)
            self._scales[c] = term_scales(self.chain, c, s.q, s.u, s.udot)
        return self._scales[c]

    def engine_result(self, case, engine, route) -> G2Kinematics:
        key = (int(case), engine, route)
        if key not in self._engine:
            s = self.states(case)
            start = time.perf_counter()
            self._engine[key] = self.engines[engine].g2_kinematics(case, s.q, s.u, s.udot, route=route)
            if self.progress:
                self.progress(
                    f"case {int(case)} {engine:9s} {route:10s} {len(s)} states "
                    f"in {time.perf_counter() - start:.2f} s"
                )
        return self._engine[key]

    def core_result(self, case, variant="corrected") -> G2Kinematics:
        key = (int(case), tuple(sorted(resolve_variant(variant))))
        if key not in self._core:
            s = self.states(case)
            self._core[key] = relacc.g2_kinematics(self.chain, case, s.q, s.u, s.udot, variant=variant)
        return self._core[key]

    def compare(self, case, engine, route, quantity, variant="corrected") -> Comparison:
        """Normalized error of the core (``variant``) against one engine route."""
        core = getattr(self.core_result(case, variant), quantity)
        ref = getattr(self.engine_result(case, engine, route), quantity)
        errors = normalized_error(core, ref, self.scales(case).of(quantity))
        s = self.states(case)
        bounds = self.engines[engine].bound(route, quantity, self.chain, case, s.q, s.u, s.udot)
        return Comparison(int(case), engine, route, quantity, errors, rounding_tolerance(), bounds)

    def check(self, cases=(1, 2, 3), quantities=QUANTITIES) -> "CheckReport":
        """Every case x engine x route x quantity comparison of the corrected core."""
        comps = [
            self.compare(c, e, r, qty)
            for c in cases
            for e in self.engines
            for r in routes_for(c)
            for qty in quantities
        ]
        return CheckReport(tuple(comps), self.n_states, self.seed, self.versions())


@dataclass(frozen=True)
class CheckReport:
    """All comparisons of one ``relacc check`` run."""

    comparisons: tuple[Comparison, ...]
    n_states: int
    seed: int
    versions: dict

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.comparisons)

    @property
    def failures(self) -> list[Comparison]:
        return [c for c in self.comparisons if not c.passed]

    def as_dict(self) -> dict:
        return {
            "passed": self.passed,
            "n_states": self.n_states,
            "seed": self.seed,
            "tolerance": rounding_tolerance(),
            "error": "max |x - x_engine| / magnitude of the terms (relacc.core.scales.term_scales)",
            "bound": "per state: tolerance * condition + lost offset (relacc.engines.base.Engine.bound)",
            "versions": self.versions,
            "comparisons": [c.as_dict() for c in self.comparisons],
        }
