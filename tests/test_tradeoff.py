"""Work-precision machinery on a small sweep: orders, best steps, references, Pareto fronts."""

import json

import numpy as np
import pytest

from relacc import tradeoff
from relacc.cli import main
from relacc.core.tolerances import rounding_tolerance
from relacc.tradeoff.derivatives import FORMULAS, best_step, theory_step

ORDER_BAND = 0.5
"""Observed orders must lie within theory +- 0.5 (the fit uses steps 2x apart, outside rounding)."""


@pytest.fixture(scope="module")
def quick():
    return tradeoff.run(quick=True)


@pytest.mark.slow
def test_fitted_orders_match_theory(quick):
    """RK4 (relacc, Pinocchio, MuJoCo) fits order 4, Euler and MuJoCo's implicit integrators order 1."""
    from relacc.tradeoff.integrators import THEORY

    assert set(quick.orders) >= {"relacc/rk4", "pinocchio/rk4", "mujoco/rk4", "mujoco/euler", "mujoco/implicit"}
    for key, order in quick.orders.items():
        assert abs(order - THEORY[key.split("/")[1]]) <= ORDER_BAND, (key, order)


@pytest.mark.slow
@pytest.mark.parametrize("method", ["forward", "central"])
def test_finite_difference_minimum_where_theory_puts_it(quick, method):
    """The best h is within 1.5 decades of eps^(1/2) (forward) and eps^(1/3) (central), every case."""
    for case in (1, 2, 3):
        h = best_step(quick.derivatives, method, case)
        assert abs(np.log10(h / theory_step(method))) <= 1.5, (method, case, h)


@pytest.mark.slow
def test_finite_difference_error_falls_then_rises(quick):
    """Each stencil's error decreases with h down to its best step, then grows again from round-off."""
    for method in FORMULAS:
        pts = sorted((r for r in quick.derivatives if r["case"] == 1 and r["method"] == method),
                     key=lambda r: -r["param"])
        errors = np.array([r["error"] for r in pts])
        i = int(np.argmin(errors))
        assert 0 < i < len(errors) - 1, method
        assert errors[0] > 100 * errors[i] and errors[-1] > 100 * errors[i], method


@pytest.mark.slow
def test_exact_methods_reach_rounding(quick):
    """Analytic formulas, engines and the complex step at h <= 1e-10 are within c eps of the reference."""
    for r in quick.derivatives:
        if r["method"] in ("analytic", "analytic-reference", "pinocchio", "mujoco") or (
                r["method"] == "complex-step" and r["param"] <= 1e-10):
            assert r["error"] <= rounding_tolerance(), r


@pytest.mark.slow
def test_reference_solutions_agree(quick):
    """The two independent reference trajectories (DOP853 1e-13; MuJoCo RK4 at dt/16) agree to 1e-10 m."""
    assert quick.references
    for ref in quick.references:
        assert ref["agreement_m"] <= 1e-10, ref


def test_pareto_front():
    """pareto keeps exactly the points no other point beats on both error and cost."""
    rows = [{"error": e, "seconds": s} for e, s in ((1e-2, 1), (1e-4, 2), (1e-3, 3), (1e-8, 10), (1e-8, 11))]
    assert [(r["error"], r["seconds"]) for r in tradeoff.pareto(rows)] == [(1e-2, 1), (1e-4, 2), (1e-8, 10)]


@pytest.mark.slow
def test_cli_tradeoff_json(capsys):
    """relacc tradeoff --quick --json prints derivatives, integrators and orders with the documented keys."""
    assert main(["tradeoff", "--quick", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out["derivatives"][0]) >= {"method", "param", "error", "seconds_per_state"}
    assert set(out["integrators"][0]) >= {"engine", "integrator", "case", "dt_or_tol", "error", "energy_drift",
                                          "seconds"}
    assert "relacc/rk4" in out["orders"]


def _fastest_by_mujoco(path, seed: int = 0) -> str:
    """The body whose mass centre moves fastest at the start of a model's default scene (qpos0, standard-normal speeds
    from ``default_rng(seed)``), by MuJoCo itself: a central difference of its ``xipos`` along ``qvel`` (exact to
    rounding for the linear part; the step 1e-7 s is far below any motion's time scale)."""
    import mujoco
    import numpy as np

    m = mujoco.MjModel.from_xml_path(str(path))
    d = mujoco.MjData(m)
    qvel = np.random.default_rng(seed).standard_normal(m.nv)
    h, at = 1e-7, []
    for sign in (1.0, -1.0):
        qpos = m.qpos0.copy()
        mujoco.mj_integratePos(m, qpos, qvel, sign * h)
        d.qpos[:] = qpos
        mujoco.mj_kinematics(m, d)
        at.append(d.xipos.copy())
    speed = np.linalg.norm(at[0] - at[1], axis=1) / (2 * h)
    speed[m.body_mass == 0] = -1.0  # bodies with mass first, as the default scene's choice
    return mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(np.argmax(speed)))


@pytest.mark.slow
def test_tradeoff_takes_a_model_file(tmp_path):
    """relacc tradeoff --model hopper.xml: every engine's fixed-step integrators on the model's default scene, observed
    at the body whose mass centre moves fastest at the start (MuJoCo's own reading says which); the
    reference (MuJoCo RK4 at dt/16) and its independent check (Drake's error-controlled RK5) agree to rounding, and
    the observed orders are the theory's (a first-order method reads 1 to +-0.1 over a factor 4 of steps; Drake's
    RK2 2 and RK3 3 likewise)."""
    import subprocess
    import sys
    from pathlib import Path

    import gymnasium

    hopper = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "hopper.xml"
    out = subprocess.run([sys.executable, "-m", "relacc", "tradeoff", "--model", str(hopper), "--quick", "--json"],
                         capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    assert data["point"] == _fastest_by_mujoco(hopper) and data["reference"]["agreement_m"] <= 1e-12
    assert {r["engine"] for r in data["integrators"]} == {"relacc", "pinocchio", "mujoco", "drake"}
    for key, theory in (("relacc/euler", 1), ("mujoco/euler", 1), ("pinocchio/euler", 1), ("drake/runge_kutta2", 2),
                        ("drake/runge_kutta3", 3)):
        assert abs(data["orders"][key] - theory) <= 0.1, (key, data["orders"])
    assert list(tmp_path.iterdir()) == []
