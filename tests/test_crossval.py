"""Cross-validation: the core's corrected formulas against Pinocchio and MuJoCo.

Every case x engine x route x quantity on N_STATES seeded states; case 3 also
on the Euler fixtures, where the engines' joint velocities are the angle
rates themselves (no mapping at all).
"""

import pytest

from relacc.core.conventions import QUANTITIES
from relacc.core.tolerances import EPS
from relacc.engines import CHAIN_ENGINES as ENGINES
from relacc.validation.check import Harness
from relacc.validation.compare import routes_for

from .conftest import N_STATES, SEED

COMBOS = [
    (case, engine, route, qty)
    for case in (1, 2, 3)
    for engine in ENGINES
    for route in routes_for(case)
    for qty in QUANTITIES
]


@pytest.fixture(scope="module")
def harness(fixture):
    return Harness(fixture, n_states=N_STATES, seed=SEED)


@pytest.mark.parametrize("case,engine,route,quantity", COMBOS, ids=lambda x: str(x))
def test_core_agrees_with_engine(harness, case, engine, route, quantity):
    """The corrected core equals the engine to c*eps of the terms' magnitude on every state."""
    comp = harness.comparison(case, engine, route, quantity)
    assert comp.passed, (
        f"case {case} {engine}/{route} {quantity}: max {comp.max_error / EPS:.1f} eps at state "
        f"{comp.worst_state} > {comp.tolerance / EPS:.0f} eps (seed [{SEED}, {case}])"
    )


def test_printed_variant_disagrees_with_engines(harness):
    """The note's printed formulas, taken together, disagree with both engines in every case."""
    for case in (1, 2, 3):
        for engine in ENGINES:
            comp = harness.comparison(case, engine, "quaternion", "acceleration", variant="printed")
            assert comp.median_error > 1e-3, f"case {case} {engine}: printed variant agrees"


@pytest.mark.slow
def test_check_streams_in_chunks(fixture, monkeypatch):
    """A sweep of several chunks: the merged summary equals the chunks' own, the median within its bin, memory flat."""
    import tracemalloc

    import numpy as np

    from relacc.validation import check
    from relacc.validation.summary import EDGES

    monkeypatch.setattr(check, "CHUNK", 400)
    h = Harness(fixture, engines=("mujoco",), n_states=1000, seed=SEED)
    assert [c[2] for c in h.chunks()] == [400, 400, 200]
    report = h.check(cases=(2,))
    parts = [h.comparison(2, "mujoco", "quaternion", "acceleration", k=k) for k in range(3)]
    merged = next(c for c in report.comparisons if c.quantity == "acceleration")
    errors = np.concatenate([p.errors for p in parts])
    assert merged.n == 1000 and merged.errors is None
    assert merged.max_error == errors.max() and merged.over == 0
    assert merged.worst_state == int(np.argmax(errors / np.concatenate([p.bounds for p in parts])))
    assert merged.worst_seed == (SEED, 2, merged.worst_state // 400)
    exact = float(np.median(errors))
    k = np.searchsorted(EDGES, exact, side="right")
    assert EDGES[k - 1] <= merged.median_error <= EDGES[k], (exact, merged.median_error)

    def peak(n):
        tracemalloc.start()
        Harness(fixture, engines=("mujoco",), n_states=n, seed=SEED).check(cases=(1,))
        top = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        return top

    assert peak(4000) < 1.3 * peak(800) + 1e6
