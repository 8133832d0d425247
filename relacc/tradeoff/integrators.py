"""Accuracy against cost for whole trajectories: each engine's integrators over a sweep of dt or tolerance.

Reference solution per scene: relacc's equations with scipy's DOP853 at
``rtol = 1e-13`` (in the scene's coordinates, charts re-based on SO(3)),
checked against an independent one, MuJoCo's RK4 at a sixteenth of the
scene's step; their agreement is part of the output. The error of a run is
the distance of G2 at the final time from the reference's (m); the energy
drift ``|E(T) - E(0)| / |E(0)|`` is reported where only conservative effects
act. Observed orders are least-squares slopes of log error against log dt
over the points between 1e-12 m (rounding) and 5e-2 m (outside the
asymptotic range).
"""

from __future__ import annotations

import time

import numpy as np

from relacc import dynamics
from relacc.core.cases import Case
from relacc.core.kinematics import g2_kinematics
from relacc.dynamics.integrate import CaseSpace, solve_on_space
from relacc.dynamics.steps import collect
from relacc.engines import TRAITS, TRUTH_ENGINE, chain_engines, load_engine, with_capability, with_trait
from relacc.engines.capabilities import ManifoldRates
from relacc.errors import IntegrationError
from relacc.kernels.dynamics import Rates
from relacc.simulate.scenes import Scene

THEORY = {"rk4": 4, "euler": 1, "implicit": 1, "implicitfast": 1, "runge_kutta2": 2, "runge_kutta3": 3,
          "runge_kutta5": 5}
"""Theoretical order of each fixed-step integrator (MuJoCo's implicit ones are first order)."""

SCIPY = ("RK45", "DOP853")
"""scipy's ``solve_ivp`` methods, run on SO(3) charts (relacc) or on an engine's manifold
(:class:`relacc.engines.capabilities.ManifoldRates`)."""

FIXED = {"relacc": ("rk4", "euler"),
         **{name: tuple(i for i in t.integrators if i in THEORY) for name, t in TRAITS.items()}}
"""Each evaluator's fixed-step integrators the sweep runs: relacc's, and those of each engine's with a known order."""

ADAPTIVE = {"relacc": SCIPY, **{name: SCIPY for name in with_capability(ManifoldRates)},
            **{name: t.adaptive for name, t in TRAITS.items() if t.adaptive}}
"""Error-controlled methods: scipy's ``solve_ivp`` on SO(3) charts (relacc) or on an engine's manifold, and an engine's
own (its traits' ``adaptive``)."""


def _final_g2(engine_name, engine, scene, x, v):
    """G2's final position (fixed components, m) and the energy (J) of a final state."""
    chain = scene.fixture.chain
    if engine_name == "relacc":
        return g2_kinematics(chain, scene.case, x, v).position, float(
            dynamics.energy(chain, scene.case, x, v, scene.effects))
    position = engine.points("quaternion", x[None], v[None], None).position[0]
    return position, float(sum(e[0] for e in engine.adapter.energy(x[None], v[None], scene.engine_effects)))


def _adaptive(name, engine, scene, method, rtol):
    """One ``solve_ivp`` run: final state and the number of function evaluations."""
    chain, eff = scene.fixture.chain, scene.effects
    if name == "relacc":
        space = CaseSpace(scene.case)
        derivs = Rates(chain, scene.case, eff)
        rotations = () if scene.case == Case.ANGLE_RATES else (slice(3, 6), slice(9, 12))
        x0, v0 = scene.q.astype(float), scene.u.astype(float)
        return solve_on_space(space, x0, v0, derivs, scene.duration, method, rtol, rtol * 1e-2, rotations)
    x0, v0 = engine.initial_state(scene.case, scene.q, scene.u)
    if name in with_trait("error_controlled"):  # Drake's own error control, its largest step the whole run
        _, X, V = collect(engine.adapter.stepper(scene.engine_effects, scene.duration, method, rtol), x0, v0,
                          scene.duration, 1, 1, who=name, integrator=method)
        return X[-1], V[-1], None
    adapter = engine.adapter
    if not isinstance(adapter, ManifoldRates):
        raise IntegrationError(f"{name} offers no manifold for scipy's {method}")
    return solve_on_space(adapter.space(), x0, v0, adapter.derivs(eff.for_tree()), scene.duration, method, rtol,
                          rtol * 1e-2, (slice(3, 6), slice(9, 12)))


def _fixed(name, engine, scene, integrator, dt):
    steps = max(int(round(scene.duration / dt)), 1)
    if name == "relacc":
        from relacc.simulate.runs import relacc_trajectory

        tr = relacc_trajectory(scene.replace(dt=scene.duration / steps, integrator=integrator, engines=(name,)))
        return tr.q[-1], tr.u[-1], tr.seconds
    q0, v0 = engine.initial_state(scene.case, scene.q, scene.u)
    start = time.perf_counter()
    dt = scene.duration / steps
    _, Q, V = collect(engine.adapter.stepper(scene.engine_effects, dt, integrator), q0, v0, dt, steps,
                      steps, who=name, integrator=integrator)  # the final state is all the sweep reads
    return Q[-1], V[-1], time.perf_counter() - start


def reference(scene: Scene, engines):
    """``(r_G2(T), E(0), agreement)``: DOP853 at 1e-13 on relacc, and its distance from an engine's RK4 at dt/16
    (:data:`relacc.engines.TRUTH_ENGINE`, MuJoCo)."""
    x, v, _ = _adaptive("relacc", None, scene, "DOP853", 1e-13)
    r_ref, _ = _final_g2("relacc", None, scene, x, v)
    E0 = float(dynamics.energy(scene.chain, scene.case, scene.q, scene.u, scene.chain_effects))
    xm, vm, _ = _fixed(TRUTH_ENGINE, engines[TRUTH_ENGINE], scene, "rk4", scene.dt / 16)
    r_mj, _ = _final_g2(TRUTH_ENGINE, engines[TRUTH_ENGINE], scene, xm, vm)
    return r_ref, E0, float(np.linalg.norm(r_mj - r_ref))


def sweep(scene: Scene, factors=(16, 8, 4, 2, 1), tolerances=(1e-4, 1e-6, 1e-8, 1e-10), euler_factors=None):
    """Every engine x integrator x step (or tolerance) on one scene. Returns ``(rows, reference_info)``."""
    engines = {n: load_engine(n, scene.fixture) for n in chain_engines()}
    r_ref, E0, agreement = reference(scene, engines)
    rows = []
    conserves = scene.effects.conserves_energy

    def add(name, integrator, param, kind, run):
        row = {"scene": scene.name, "engine": name, "integrator": integrator, "case": scene.case,
               "dt_or_tol": param, "kind": kind, "diverged": False}
        start = time.perf_counter()
        try:
            x, v, seconds = run()
            r, E = _final_g2(name, engines.get(name), scene, x, v)
            row.update(error=float(np.linalg.norm(r - r_ref)),
                       energy_drift=abs(E - E0) / abs(E0) if conserves else None,
                       seconds=seconds if seconds is not None else time.perf_counter() - start)
        except IntegrationError:  # a diverged run is a result: infinite error, left out of fits and fronts
            row.update(error=float("inf"), energy_drift=None, seconds=time.perf_counter() - start, diverged=True)
        rows.append(row)

    for name, integrators in FIXED.items():
        if name != "relacc" and name not in engines:
            continue
        for integrator in integrators:
            fs = euler_factors if (euler_factors and THEORY[integrator] == 1) else factors
            for f in fs:
                dt = scene.dt * f
                add(name, integrator, dt, "fixed",
                    lambda: _fixed(name, engines.get(name), scene, integrator, dt))
    for name, methods in ADAPTIVE.items():
        if name != "relacc" and name not in engines:
            continue
        for method in methods:
            for tol in tolerances:
                add(name, method, tol, "adaptive",
                    lambda: _adaptive(name, engines.get(name), scene, method, tol)[:2] + (None,))
    return rows, {"scene": scene.name, "reference": "relacc DOP853 rtol 1e-13",
                  "check": f"{TRUTH_ENGINE} RK4 at dt/16", "agreement_m": agreement}


MIN_FIT_POINTS = 3
"""Steps needed in the asymptotic window to read an order: two points cannot tell the order from the
pre-asymptotic bend (Drake's fifth-order Runge-Kutta goes from 3e-11 to 8e-13 m between 8 and 4 ms, slope 5.6,
and is at rounding by 2 ms)."""


def observed_order(rows, engine: str, integrator: str, scene: str | None = None):
    """Least-squares slope of log(error) vs log(dt) over errors in [1e-12, 5e-2] m; None with fewer than
    :data:`MIN_FIT_POINTS` steps there."""
    pts = [(r["dt_or_tol"], r["error"]) for r in rows if r["engine"] == engine and r["integrator"] == integrator
           and r["kind"] == "fixed" and (scene is None or r["scene"] == scene) and 1e-12 <= r["error"] <= 5e-2]
    if len({p[0] for p in pts}) < MIN_FIT_POINTS:
        return None
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])
