"""What a comparison over any number of states keeps: a :class:`Summary` that merges chunk by chunk.

A :class:`relacc.validation.compare.Comparison` holds one error per state;
a sweep of 1e8 states cannot. A :class:`Summary` keeps what ``relacc check``
reports, in bounded memory, and two summaries of disjoint chunks merge into
the summary of their union (in any order, on any machine):

* the number of states, the largest error and its bound, the largest
  error / bound and the state where it occurs (its index in the whole sweep
  and the seed of its chunk), the number of states above their bound;
* a histogram of the errors on log-spaced bins (:data:`EDGES`, eight per
  decade), from which the median is read when the per-state errors are not
  kept (they are kept while the sweep is one chunk).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from relacc.core.conventions import CONVENTIONS
from relacc.core.tolerances import EPS, rounding_tolerance

EDGES = EPS * 10.0 ** np.arange(-3.0, 13.0 + 1e-9, 0.125)
"""Histogram bin edges of the normalized error: 1e-3 eps to 1e13 eps, eight bins per decade.

Bin 0 holds errors below the first edge (zero included), the last bin those
at or above the last edge (and non-finite ones).
"""


@dataclass(frozen=True, eq=False)
class Summary:
    """One case x engine x route x quantity over a sweep of states, in bounded memory.

    Attributes:
        n: states compared.
        max_error: largest normalized error (dimensionless).
        max_bound: largest bound of the engine's accuracy model.
        max_ratio: largest error / bound (passes when <= 1; inf if a value was not finite).
        worst_state: index in the whole sweep of the state with the largest error / bound.
        worst_seed: the seed of the chunk holding it (``numpy.random.default_rng(worst_seed)``).
        worst_in_chunk: its index within that chunk.
        over: states whose error exceeds their bound.
        finite: every value the engine returned was finite.
        counts: ``(len(EDGES) + 1,)`` histogram of the errors.
        errors: ``(n,)`` per-state errors while the sweep is one chunk, else None.
    """

    case: int
    engine: str
    route: str
    quantity: str
    n: int
    max_error: float
    max_bound: float
    max_ratio: float
    worst_state: int
    worst_seed: tuple
    worst_in_chunk: int
    over: int
    finite: bool
    counts: np.ndarray = field(repr=False)
    errors: np.ndarray | None = field(default=None, repr=False)
    tolerance: float = field(default_factory=rounding_tolerance)

    @classmethod
    def of(cls, comp, start: int, seed) -> "Summary":
        """The summary of one chunk's :class:`~relacc.validation.compare.Comparison`.

        Args:
            start: index of the chunk's first state in the whole sweep.
            seed: the chunk's seed.
        """
        ratio = comp.errors / comp.bounds
        worst = int(np.argmax(ratio))
        return cls(comp.case, comp.engine, comp.route, comp.quantity, int(comp.errors.size), comp.max_error,
                   comp.max_bound, comp.max_ratio, start + worst, tuple(np.atleast_1d(seed).tolist()), worst,
                   int(np.count_nonzero(~(comp.errors <= comp.bounds))), comp.finite,
                   np.bincount(np.searchsorted(EDGES, np.nan_to_num(comp.errors, nan=np.inf), side="right"),
                               minlength=EDGES.size + 1), comp.errors, comp.tolerance)

    def merge(self, other: "Summary") -> "Summary":
        """The summary of both sweeps' states (disjoint chunks of the same comparison).

        Associative and commutative (ties in the worst ratio go to the earlier state), so chunks may be
        merged in any grouping, on any machine, to the same summary.
        """
        first = (self.max_ratio, -self.worst_state) >= (other.max_ratio, -other.worst_state)
        a = self if first else other  # ties: the earlier state, whatever the order of merging
        return replace(a, n=self.n + other.n, max_error=max(self.max_error, other.max_error),
                       max_bound=max(self.max_bound, other.max_bound), over=self.over + other.over,
                       finite=self.finite and other.finite, counts=self.counts + other.counts, errors=None)

    @property
    def passed(self) -> bool:
        return self.finite and self.over == 0

    @property
    def median_error(self) -> float:
        """The median error: exact while per-state errors are kept, else the histogram's (within 1/8 decade)."""
        if self.errors is not None:
            return float(np.median(self.errors))
        k = int(np.searchsorted(np.cumsum(self.counts), (self.n + 1) / 2))
        if k == 0:
            return 0.0
        return float(np.sqrt(EDGES[k - 1] * EDGES[min(k, EDGES.size - 1)]))  # the bin's geometric middle

    @property
    def evaluator(self) -> str:
        return f"{self.engine}/{self.route}"

    def as_json(self) -> dict:
        """Plain data (``relacc check --json``)."""
        return {
            "case": self.case, "engine": self.engine, "route": self.route, "quantity": self.quantity,
            "n_states": self.n, "max_error": self.max_error, "median_error": self.median_error,
            "median_from": "every state" if self.errors is not None else "histogram, 8 bins per decade",
            "max_error_eps": self.max_error / EPS, "tolerance": self.tolerance, "max_bound": self.max_bound,
            "max_ratio": self.max_ratio, "passed": self.passed, "states_over_bound": self.over,
            "worst_state": self.worst_state, "worst_seed": list(self.worst_seed),
            "worst_in_chunk": self.worst_in_chunk, "convention": CONVENTIONS[self.quantity],
        }
