"""Hard cases: the catalogue's accuracy models hold, values stay finite, the inverse map refuses gimbal lock."""

import numpy as np
import pytest

import relacc
from relacc.core import speeds
from relacc.core.tolerances import MAX_CONDITION
from relacc.validation.hardcases import Runner, catalogue
from relacc.validation.hardsearch import hypothesis_search

from .conftest import SEED

CATALOGUE = catalogue()


@pytest.fixture(scope="module")
def runner(fixture):
    return Runner(fixture, seed=SEED)


@pytest.mark.parametrize("entry", CATALOGUE, ids=lambda h: h.name)
def test_catalogue_entry_within_its_accuracy_model(runner, entry):
    """Core vs complex step and engines vs core stay within the entry's model; every value is finite."""
    results = runner.run(entry)
    assert results, "no comparison ran"
    bad = [r for r in results if not r.passed]
    assert not bad, "; ".join(
        f"case {r.case} {r.evaluator} {r.quantity}: {r.max_ratio:.3g} x bound, finite={r.finite}" for r in bad[:5]
    ) + f" (seed {SEED}, model: {entry.model})"


def test_catalogue_covers_the_issue():
    """Every family is present, with gimbal deltas down to 1e-12 and exactly 0, spin to 1e6, distance to 1e8."""
    fam = {}
    for h in CATALOGUE:
        fam.setdefault(h.family, []).append(h.parameter)
    assert {1e-12, 0.0} <= set(fam["gimbal"]) and max(fam["spin"]) == 1e6 and max(fam["far"]) == 1e8
    assert {0.0, 1e-12, 1e3} <= set(fam["geometry"]) and len(fam["quaternion"]) >= 4
    assert len({h.name for h in CATALOGUE}) == len(CATALOGUE)


def test_far_from_origin_engines_lose_digits_but_core_does_not(runner):
    """At |s1| = 1e8 m the engines' V errors exceed 1e6 eps (global coordinates) while the core stays at c eps."""
    entry = next(h for h in CATALOGUE if h.name == "far-1e+08")
    res = runner.run(entry)
    eps = np.finfo(float).eps
    core = [r for r in res if r.evaluator == "relacc"]
    assert max(r.max_error for r in core) <= 64 * eps
    for engine in ("pinocchio", "mujoco", "drake"):
        v = [r for r in res if r.evaluator.startswith(engine) and r.quantity == "V"]
        assert max(r.max_error for r in v) > 1e6 * eps, f"{engine} unexpectedly exact far from the origin"


@pytest.mark.parametrize("delta", [1e-1, 1e-4, 1e-7])
def test_inverse_condition_matches_numpy(delta):
    """speeds.inverse_condition equals numpy's 2-norm condition of W(theta) and grows like 2/delta."""
    q = np.zeros(12)
    q[4] = np.pi / 2 - delta
    ref = np.linalg.cond(relacc.omega_partials_123(q[3:6]))
    got = speeds.inverse_condition(3, q)
    assert got == pytest.approx(ref, rel=1e-6)
    assert got == pytest.approx(2 / delta, rel=delta)


@pytest.mark.parametrize("body,index", [("theta_B1", 4), ("theta_B2", 10)])
@pytest.mark.parametrize("angle", [np.pi / 2, -np.pi / 2, np.pi / 2 - 1e-12, np.pi / 2 + 3e-9])
def test_inverse_map_refuses_gimbal_lock(body, index, angle):
    """Asking for 1-2-3 rates at or within ~2e-8 rad of gimbal lock raises, naming angle and distance."""
    q = np.zeros(12)
    q[index] = angle
    with pytest.raises(relacc.SingularityError, match=rf"{body}\[1\] = .* rad from the 1-2-3 gimbal lock") as info:
        speeds.case_speeds(3, q, np.ones(12))
    assert "condition number" in str(info.value) and "use case 1 or 2" in str(info.value)


def test_inverse_map_round_trips_away_from_the_lock(rng):
    """case_speeds inverts to_body_speeds (u and udot) where the condition is below the limit."""
    q = rng.uniform(-1.2, 1.2, (200, 12))
    u, udot = rng.normal(size=(2, 200, 12))
    _, nu, nu_dot = speeds.to_body_speeds(3, q, u, udot)
    u2, udot2 = speeds.case_speeds(3, q, nu, nu_dot)
    cond = speeds.inverse_condition(3, q)[:, None]
    assert np.all(cond < MAX_CONDITION)
    eps = np.finfo(float).eps
    assert np.all(np.abs(u2 - u) <= 64 * eps * cond * np.abs(u).max(axis=1, keepdims=True))
    assert np.all(np.abs(udot2 - udot) <= 64 * eps * cond**2 * (1 + np.abs(u).max(axis=1, keepdims=True) ** 2 +
                                                                  np.abs(udot).max(axis=1, keepdims=True)))


def test_forward_map_stays_accurate_at_the_lock(chain):
    """At exactly theta2 = pi/2 the forward formulas give finite results equal to the quaternion route."""
    q3 = np.zeros(12)
    q3[4] = np.pi / 2
    u = np.arange(12.0) / 10
    k3 = relacc.g2_kinematics(chain, 3, q3, u, u)
    q14, nu, nu_dot = speeds.to_body_speeds(3, q3, u, u)
    k2 = relacc.g2_kinematics(chain, 2, q14, nu, nu_dot)
    assert np.all(np.isfinite(k3.acceleration))
    assert np.allclose(k3.acceleration, k2.acceleration, rtol=0, atol=1e-14 * np.abs(k2.acceleration).max())


def test_overflow_is_an_error_not_inf(chain):
    """Speeds so large that the acceleration overflows float64 raise InputError instead of returning inf."""
    q = np.r_[0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0.0]
    u = np.full(12, 1e200)
    with pytest.raises(relacc.InputError, match="overflowed"):
        relacc.g2_kinematics(chain, 1, q, u, u)


@pytest.mark.slow
def test_hypothesis_search_finds_no_state_outside_the_model(fixture):
    """Hypothesis, targeting error / bound over decades of magnitudes, finds nothing above the bound."""
    worst = hypothesis_search(fixture, max_examples=60, seed=SEED)
    assert worst.examples >= 60
    assert worst.ratio <= 1.0, f"worst: {worst}"
