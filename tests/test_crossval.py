"""Cross-validation: the core's corrected formulas against Pinocchio and MuJoCo.

Every case x engine x route x quantity on N_STATES seeded states; case 3 also
on the Euler fixtures, where the engines' joint velocities are the angle
rates themselves (no mapping at all).
"""

import pytest

from relacc.core.conventions import QUANTITIES
from relacc.core.tolerances import EPS
from relacc.validation.check import Harness
from relacc.validation.compare import routes_for

from .conftest import N_STATES, SEED

COMBOS = [
    (case, engine, route, qty)
    for case in (1, 2, 3)
    for engine in ("pinocchio", "mujoco")
    for route in routes_for(case)
    for qty in QUANTITIES
]


@pytest.fixture(scope="module")
def harness(fixture):
    return Harness(fixture, n_states=N_STATES, seed=SEED)


@pytest.mark.parametrize("case,engine,route,quantity", COMBOS, ids=lambda x: str(x))
def test_core_agrees_with_engine(harness, case, engine, route, quantity):
    """The corrected core equals the engine to c*eps of the terms' magnitude on every state."""
    comp = harness.compare(case, engine, route, quantity)
    assert comp.passed, (
        f"case {case} {engine}/{route} {quantity}: max {comp.max_error / EPS:.1f} eps at state "
        f"{comp.worst_state} > {comp.tolerance / EPS:.0f} eps (seed [{SEED}, {case}])"
    )


def test_printed_variant_disagrees_with_engines(harness):
    """The note's printed formulas, taken together, disagree with both engines in every case."""
    for case in (1, 2, 3):
        for engine in ("pinocchio", "mujoco"):
            comp = harness.compare(case, engine, "quaternion", "acceleration", variant="printed")
            assert comp.median_error > 1e-3, f"case {case} {engine}: printed variant agrees"
