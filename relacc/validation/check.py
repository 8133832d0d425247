"""Cross-validation of the core against the engines: the harness behind ``relacc check``.

For every case x engine x route x quantity, the core's corrected formulas
and the engine are evaluated on the same seeded states and compared through
the normalized error of :mod:`relacc.core.tolerances`.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass

import numpy as np

import relacc
from relacc.core.cases import as_case, check_int
from relacc.core.conventions import QUANTITIES
from relacc.core.kinematics import G2Kinematics, resolve_variant
from relacc.core.scales import term_scales
from relacc.core.states import States, random_states
from relacc.core.tolerances import rounding_tolerance
from relacc.engines import ENGINES, load_engine
from relacc.errors import EngineError
from relacc.fixtures import Fixture, load
from relacc.validation.compare import Comparison, against_engines, compare


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
        """The core (``variant``) against one engine route, one quantity (:func:`relacc.validation.compare.compare`).

        The engine's value is its own, the reference the core's: the error
        is symmetric, and the bound is the engine's accuracy model.
        """
        s = self.states(case)
        return compare(case, engine, route, quantity, getattr(self.engine_result(case, engine, route), quantity),
                       getattr(self.core_result(case, variant), quantity), self.scales(case).of(quantity),
                       self.engines[engine].bound(route, quantity, self.chain, case, s.q, s.u, s.udot))

    def check(self, cases=(1, 2, 3), quantities=QUANTITIES) -> "CheckReport":
        """Every case x engine x route x quantity comparison of the corrected core."""
        comps = []
        for c in cases:
            s = self.states(c)
            comps += against_engines(self.engines, self.chain, c, s.q, s.u, s.udot, self.core_result(c),
                                     self.scales(c), quantities=quantities,
                                     evaluate=lambda name, _, route, c=c: self.engine_result(c, name, route))
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
