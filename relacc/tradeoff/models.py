"""``relacc tradeoff --model FILE``: what accuracy costs for any model's trajectory.

The model's default scene (:func:`relacc.simulate.scenes.model_scene`: tumbling in space from its reference
configuration, seeded speeds, nothing acting) run by every engine's fixed-step integrators over a sweep of steps.
The error of a run is the distance of the observed point (the first body's mass centre) at the final time from
the reference's, in m; the reference is MuJoCo's RK4 at a sixteenth of the scene's step, checked against an
independent one, Drake's error-controlled fifth-order Runge-Kutta at accuracy 1e-12 (their distance is part of
the output). Seconds are each engine's integration alone. Orders are read as in
:func:`relacc.tradeoff.integrators.observed_order`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from relacc.core.conventions import ENGINE_INTEGRATORS
from relacc.errors import IntegrationError
from relacc.tradeoff.integrators import THEORY, observed_order

FACTORS = {True: (8, 4, 2), False: (16, 8, 4, 2, 1)}
"""Multiples of the scene's step, quick or not."""
DURATION = {True: 0.05, False: 0.25}
"""Seconds simulated, quick or not (relacc's tree integrator runs in Python, one state at a time)."""
DT = 1e-3
REFERENCE_DIVISOR = 16
CHECK_ACCURACY = 1e-12


@dataclass(frozen=True)
class ModelTradeoff:
    """Rows ``{engine, integrator, dt, error (m), seconds, diverged}``, the reference's check and the orders."""

    model: str
    point: str
    duration: float
    rows: list
    reference: dict
    orders: dict

    def as_json(self) -> dict:
        """The ``relacc tradeoff --model FILE --json`` object."""
        return {"model": self.model, "point": self.point, "duration": self.duration, "integrators": self.rows,
                "reference": self.reference, "orders": self.orders}


def _final(scene):
    """The observed point's final position (fixed components, m) of each engine in ``scene``, and its seconds."""
    from relacc import simulate

    result = simulate.run(scene)
    return {name: (np.asarray(tr.position[-1]), tr.seconds) for name, tr in result.trajectories.items()}


def run(model, *, quick: bool = False, seed: int = 0, progress=None) -> ModelTradeoff:
    """Sweep every engine's fixed-step integrators on ``model``'s default scene (module docstring)."""
    from relacc.simulate import scenes

    base = scenes.model_scene(model, seed=seed, duration=DURATION[bool(quick)], dt=DT)
    if progress:
        progress(f"reference: mujoco rk4 at dt/{REFERENCE_DIVISOR}, checked by drake runge_kutta5 at "
                 f"accuracy {CHECK_ACCURACY}")
    ref = _final(base.replace(engines=("mujoco",), dt=DT / REFERENCE_DIVISOR, integrator="rk4",
                              record_every=10**6))["mujoco"][0]
    reference = {"reference": f"mujoco rk4 at dt = {DT / REFERENCE_DIVISOR} s"}
    if "drake" in base.engines:
        check = _final(base.replace(engines=("drake",), drake_integrator="runge_kutta5",
                                    drake_accuracy=CHECK_ACCURACY, record_every=10**6))["drake"][0]
        reference.update(check=f"drake runge_kutta5, accuracy {CHECK_ACCURACY}",
                         agreement_m=float(np.linalg.norm(check - ref)))
    rows = []
    for engine in base.engines:
        for integrator in ENGINE_INTEGRATORS[engine]:
            if integrator not in THEORY:
                continue
            if progress:
                progress(f"{engine} {integrator}")
            for factor in FACTORS[bool(quick)]:
                dt = DT * factor
                steps = max(int(round(base.duration / dt)), 1)
                scene = base.replace(engines=(engine,), dt=base.duration / steps, record_every=10**6,
                                     **({"drake_integrator": integrator} if engine == "drake"
                                        else {"integrator": integrator}))
                row = {"engine": engine, "integrator": integrator, "dt": scene.dt, "kind": "fixed",
                       "dt_or_tol": scene.dt, "diverged": False}
                try:
                    position, seconds = _final(scene)[engine]
                    row.update(error=float(np.linalg.norm(position - ref)), seconds=float(seconds))
                except IntegrationError:  # a diverged run is a result: infinite error, left out of fits
                    row.update(error=float("inf"), seconds=None, diverged=True)
                rows.append(row)
    runs = dict.fromkeys((r["engine"], r["integrator"]) for r in rows)
    orders = {f"{e}/{i}": observed_order(rows, e, i) for e, i in runs}
    return ModelTradeoff(str(model), base.observe, base.duration, rows, reference,
                         {k: v for k, v in orders.items() if v is not None})


def format_text(result: ModelTradeoff) -> str:
    """What ``relacc tradeoff --model FILE`` prints."""
    ref = result.reference
    out = [f"relacc tradeoff {result.model}: the default scene, {result.duration} s; error = |r(T) - reference| at "
           f"the mass centre of {result.point} (m); reference {ref['reference']}"
           + (f", {ref['check']} agrees to {ref['agreement_m']:.1e} m" if "check" in ref else ""),
           f"  {'engine':10s} {'integrator':14s} {'dt':>9s} {'error (m)':>10s} {'seconds':>9s}"]
    for r in result.rows:
        err = "diverged" if r["diverged"] else f"{r['error']:10.1e}"
        sec = "-" if r["seconds"] is None else f"{r['seconds']:9.4f}"
        out.append(f"  {r['engine']:10s} {r['integrator']:14s} {r['dt']:9.1e} {err:>10s} {sec:>9s}")
    out.append("\nObserved order of convergence vs theory:")
    for key, order in result.orders.items():
        out.append(f"  {key:26s} {order:5.2f}   (theory {THEORY[key.split('/')[1]]})")
    return "\n".join(out)
