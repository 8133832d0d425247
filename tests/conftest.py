"""Shared fixtures: the test chain and the seeds.

Every random state comes from ``numpy.random.default_rng(seed)`` with a seed
named here or in the test; failures print it.
"""

import numpy as np
import pytest

import relacc

SEED = 20261122
"""Base seed of the suite; tests add a fixed offset per case."""

N_STATES = 1000
"""States per case for the derivative and cross-validation checks."""


@pytest.fixture(scope="session")
def chain():
    """A chain with every geometric vector non-zero and off the axes."""
    return relacc.TwoBodyChain(q2=[0.3, -0.2, 0.5], r2=[0.4, 0.1, -0.25])


@pytest.fixture(params=[1, 2, 3], ids=["case1", "case2", "case3"])
def case(request):
    """Each of the note's three choices of generalized speeds."""
    return request.param


def seed_for(case, offset=0):
    """The seed of a case's random states (distinct per case and per test)."""
    return SEED + 1000 * int(case) + offset


@pytest.fixture
def rng():
    """A generator for tests that need a few random numbers."""
    return np.random.default_rng(SEED)


@pytest.fixture(scope="session")
def fixture():
    """The checked-in model fixture, models/two_body.toml."""
    from pathlib import Path

    from relacc.fixtures import load

    return load(Path(__file__).resolve().parents[1] / "models" / "two_body.toml")


# Hypothesis: one fixed, derandomized profile for the whole suite (bounded budget, no database).
from hypothesis import HealthCheck, settings  # noqa: E402

settings.register_profile(
    "relacc", max_examples=150, derandomize=True, database=None, deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
settings.load_profile("relacc")
