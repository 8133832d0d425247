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
from relacc.engines import ENGINES, chain_engines, installed, load_engine
from relacc.errors import EngineError
from relacc.fixtures import Fixture, load
from relacc.validation.compare import Comparison, against_engines, compare_values
from relacc.validation.referee import referee
from relacc.validation.summary import Summary

CHUNK = 20_000
"""States per chunk: a sweep is generated, evaluated and reduced this many states at a time."""


class Harness:
    """Engines, fixture and seeded states, evaluated chunk by chunk.

    The states of case ``c`` are chunks of at most :data:`CHUNK`: chunk ``k``
    comes from ``numpy.random.default_rng([seed, c, k])`` (never from one
    shared stream), so any chunk can be made, and checked, alone. The
    evaluations of one chunk per case are cached.

    Args:
        fixture: the chain's fixture (default: the shipped ``two_body.toml``).
        engines: engine names to load (default: every engine installed), or ``{name: Engine}`` already loaded.
        n_states: states per case.
        seed: base seed (an integer >= 0).
        progress: callable taking one line of progress text, or None.
    """

    def __init__(self, fixture: Fixture | None = None, engines=None, n_states=1000, seed=0, progress=None):
        n_states = check_int("number of states", n_states, minimum=1)
        seed = check_int("seed", seed, minimum=0)
        self.fixture = fixture if fixture is not None else load()
        self.chain = self.fixture.chain
        if isinstance(engines, dict):  # engines already loaded (a test's, or one with a planted fault)
            self.engines = dict(engines)
        else:
            engines = chain_engines() if engines is None else (
                tuple(engines) if isinstance(engines, (list, tuple)) else (engines,))
            unknown = [e for e in engines if e not in ENGINES]
            if unknown:
                raise EngineError(f"unknown engines {unknown}: accepted are {', '.join(ENGINES)}")
            self.engines = {name: load_engine(name, self.fixture) for name in engines}
        self.n_states = int(n_states)
        self.seed = int(seed)
        self.progress = progress
        self._chunk = {}  # case -> (k, {key: value}): the evaluations of the cached chunk
        self._last_progress = 0.0

    def versions(self) -> dict:
        """Versions of relacc, Python, numpy and every loaded engine."""
        out = {"relacc": relacc.__version__, "python": sys.version.split()[0], "numpy": np.__version__}
        out.update({name: e.version for name, e in self.engines.items()})
        out.update({name: "not installed" for name in ENGINES if name not in self.engines and not installed(name)})
        return out

    def chunks(self) -> list[tuple[int, int, int]]:
        """``(k, start, size)`` of every chunk of a case's states."""
        return [(k, start, min(CHUNK, self.n_states - start)) for k, start in
                enumerate(range(0, self.n_states, CHUNK))]

    def chunk_seed(self, case, k: int = 0) -> list:
        """The seed of chunk ``k`` of a case: ``[seed, case, k]``."""
        return [self.seed, int(case), int(k)]

    def _cached(self, case, k, key, make):
        c = int(as_case(case))
        if c not in self._chunk or self._chunk[c][0] != k:
            self._chunk[c] = (k, {})
        store = self._chunk[c][1]
        if key not in store:
            store[key] = make()
        return store[key]

    def states(self, case, k: int = 0) -> States:
        """Chunk ``k`` of a case's states."""
        size = self.chunks()[k][2]
        return self._cached(case, k, "states", lambda: random_states(int(case), size, self.chunk_seed(case, k)))

    def scales(self, case, k: int = 0):
        s = self.states(case, k)
        return self._cached(case, k, "scales", lambda: term_scales(self.chain, int(case), s.q, s.u, s.udot))

    def engine_result(self, case, engine, route, k: int = 0) -> G2Kinematics:
        s = self.states(case, k)

        def run():
            start = time.perf_counter()
            out = self.engines[engine].g2_kinematics(case, s.q, s.u, s.udot, route=route)
            now = time.perf_counter()
            if self.progress and (len(self.chunks()) == 1 or now - self._last_progress > 1.0):
                self._last_progress = now
                self.progress(f"case {int(case)} {engine:9s} {route:10s} chunk {k + 1}/{len(self.chunks())}, "
                              f"{len(s)} states in {now - start:.2f} s")
            return out

        return self._cached(case, k, ("engine", engine, route), run)

    def core_result(self, case, variant="corrected", k: int = 0) -> G2Kinematics:
        s = self.states(case, k)
        return self._cached(case, k, ("core", tuple(sorted(resolve_variant(variant)))),
                            lambda: relacc.g2_kinematics(self.chain, case, s.q, s.u, s.udot, variant=variant))

    def comparison(self, case, engine, route, quantity, variant="corrected", k: int = 0) -> Comparison:
        """The core (``variant``) against one engine route, one quantity, on chunk ``k``, state by state.

        The engine's value is its own, the reference the core's: the error
        is symmetric, and the bound is the engine's accuracy model.
        """
        s = self.states(case, k)
        value = getattr(self.engine_result(case, engine, route, k), quantity)
        return compare_values(case, engine, route, quantity, value,
                              getattr(self.core_result(case, variant, k), quantity), self.scales(case, k).of(quantity),
                              self.engines[engine].bound(route, quantity, self.chain, case, s.q, s.u, s.udot))

    def check_chunk(self, case, k: int, quantities=QUANTITIES) -> list[Summary]:
        """Every engine x route x quantity of the corrected core on chunk ``k`` of a case, summarized."""
        s = self.states(case, k)
        comps = against_engines(self.engines, self.chain, case, s.q, s.u, s.udot, self.core_result(case, k=k),
                                self.scales(case, k), quantities=quantities,
                                evaluate=lambda name, _, route: self.engine_result(case, name, route, k))
        return [Summary.of(c, self.chunks()[k][1], self.chunk_seed(case, k)) for c in comps]

    def check(self, cases=(1, 2, 3), quantities=QUANTITIES) -> "CheckReport":
        """Every case x engine x route x quantity comparison of the corrected core, chunk by chunk.

        Memory is set by :data:`CHUNK`, whatever ``n_states``.
        """
        summaries = []
        for c in cases:
            merged: list | None = None
            for k, _, _ in self.chunks():
                part = self.check_chunk(c, k, quantities)
                merged = part if merged is None else [a.merge(b) for a, b in zip(merged, part)]
            summaries += merged or []
        verdicts = tuple(referee(self, s.case, s.quantity, s.route, s.worst_seed[2])
                         for s in summaries if not s.passed)
        return CheckReport(tuple(summaries), self.n_states, self.seed, self.versions(), verdicts)


@dataclass(frozen=True)
class CheckReport:
    """All comparisons of one ``relacc check`` run."""

    comparisons: tuple[Summary, ...]
    n_states: int
    seed: int
    versions: dict
    referee: tuple = ()
    """:class:`relacc.validation.referee.Verdict` of each failed comparison: which evaluators are the odd ones out."""

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.comparisons)

    @property
    def failures(self) -> list[Summary]:
        return [c for c in self.comparisons if not c.passed]

    def as_json(self) -> dict:
        return {
            "passed": self.passed,
            "n_states": self.n_states,
            "seed": self.seed,
            "tolerance": rounding_tolerance(),
            "error": "max |x - x_engine| / magnitude of the terms (relacc.core.scales.term_scales)",
            "bound": "per state: tolerance * condition + lost offset (relacc.engines.chain.ChainEngine.bound)",
            "states": f"chunk k of case c: {CHUNK} states from numpy.random.default_rng([seed, c, k])",
            "versions": self.versions,
            "comparisons": [c.as_json() for c in self.comparisons],
            "referee": [v.as_json() for v in self.referee],
        }
