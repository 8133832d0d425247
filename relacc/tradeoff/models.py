"""``relacc tradeoff --model FILE``: what accuracy costs for any model's trajectory.

The model's default scene (:func:`relacc.simulate.scenes.model_scene`: tumbling in space from its reference
configuration, seeded speeds, nothing acting) run by every engine's fixed-step integrators over a sweep of steps.
The error of a run is the distance of the observed point (the first body's mass centre) at the final time from
the reference's, in m; the reference is RK4 at a sixteenth of the scene's step (MuJoCo's, or the first engine that
reads the model as relacc does), checked against an independent one, Drake's error-controlled fifth-order
Runge-Kutta at accuracy 1e-12 (their distance is part of the output). Seconds are each engine's integration alone.
Orders are read as in :func:`relacc.tradeoff.integrators.observed_order`.

First, every engine's acceleration is checked against relacc's along one run of the scene
(:attr:`relacc.simulate.runs.SimulationResult.differing`): an engine that reads the model differently integrates a
different system, so its rows measure that misreading, not its integrator. Its rows are kept and marked, it is not
the reference or the check, it has no observed order, and the command exits 1.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from relacc.engines import with_trait
from relacc.errors import IntegrationError
from relacc.simulate.scenes import integrators_of
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
    differing: dict | None = None
    """``{engine: {"error", "bound"}}``: engines whose acceleration is not relacc's at the same states."""
    left_out: dict | None = None
    """``{engine: why}``: installed engines the default scene runs without (they lack some of the model's joints)."""
    not_evaluated: tuple = ()
    """One line per kind of element of the file the scene leaves out (``Reading.unevaluated``)."""
    no_order: dict | None = None
    """``{"engine/integrator": why}``: runs whose order of convergence could not be read, and why."""

    @property
    def exit_code(self) -> int:
        return 1 if self.differing else 0

    def as_json(self) -> dict:
        """The ``relacc tradeoff --model FILE --json`` object."""
        return {"model": self.model, "point": self.point, "duration": self.duration, "integrators": self.rows,
                "reference": self.reference, "orders": self.orders, "misread": self.differing or {},
                "agree": not self.differing, "left_out": self.left_out or {},
                "not_evaluated": list(self.not_evaluated), "no_order": self.no_order or {}}


def _final(scene):
    """The observed point's final position (fixed components, m) of each engine in ``scene``, and its seconds."""
    from relacc import simulate

    result = simulate.run(scene, check=False)  # judged once, on the base run with relacc in it
    return {name: (np.asarray(tr.position[-1]), tr.seconds) for name, tr in result.trajectories.items()}


def why_no_order(rows, engine: str, integrator: str) -> str:
    """Why ``observed_order`` read no order for a run: every error at rounding, every error beyond the asymptotic
    range, or too few steps between (:data:`relacc.tradeoff.integrators.MIN_FIT_POINTS`)."""
    from relacc.tradeoff.integrators import MIN_FIT_POINTS

    errors = [r["error"] for r in rows if r["engine"] == engine and r["integrator"] == integrator
              and not r["diverged"]]
    if not errors:
        return "every run diverged"
    inside = [e for e in errors if 1e-12 <= e <= 5e-2]
    if len(inside) >= MIN_FIT_POINTS:
        return ""
    if max(errors) < 1e-12:
        return (f"every error is below 1e-12 m (at most {max(errors):.1e} m): rounding, where no order shows (the "
                "observed point moves too little, or the integrator is exact for this motion; --observe chooses "
                "another body)")
    if min(errors) > 5e-2:
        return f"every error is above 5e-2 m (at least {min(errors):.1e} m): the steps are too large to show an order"
    return (f"only {len(inside)} of its steps have errors between 1e-12 and 5e-2 m, where an order shows; it takes "
            f"{MIN_FIT_POINTS}")


def run(model, *, quick: bool = False, seed: int = 0, progress=None, observe: str | None = None) -> ModelTradeoff:
    """Sweep every engine's fixed-step integrators on ``model``'s default scene (module docstring)."""
    from relacc import simulate
    from relacc.simulate import scenes

    base = scenes.model_scene(model, seed=seed, duration=DURATION[bool(quick)], dt=DT, observe=observe)
    if progress:
        progress("every engine's acceleration against relacc's along one run")
    differing = simulate.run(base, keep=False).differing
    own = with_trait("own_steppers")
    chosen = min((e for e in base.engines if e not in differing and "rk4" in integrators_of(e)),
                 key=lambda e: (e == "relacc", e not in own), default="relacc")  # an engine's own RK4 loop first
    if progress:
        progress(f"reference: {chosen} rk4 at dt/{REFERENCE_DIVISOR}, checked by drake runge_kutta5 at "
                 f"accuracy {CHECK_ACCURACY}")
    ref = _final(base.replace(engines=(chosen,), dt=DT / REFERENCE_DIVISOR, integrator="rk4",
                              record_every=10**6))[chosen][0]
    reference: dict[str, Any] = {"reference": f"{chosen} rk4 at dt = {DT / REFERENCE_DIVISOR} s"}
    checker = next((e for e in with_trait("error_controlled", base.engines) if e not in differing), None)
    if checker is not None:
        check = _final(base.replace(engines=(checker,), drake_integrator="runge_kutta5",
                                    drake_accuracy=CHECK_ACCURACY, record_every=10**6))[checker][0]
        reference.update(check=f"{checker} runge_kutta5, accuracy {CHECK_ACCURACY}",
                         agreement_m=float(np.linalg.norm(check - ref)))
    rows: list[dict[str, Any]] = []
    for engine in base.engines:
        for integrator in integrators_of(engine):
            if integrator not in THEORY:
                continue
            if progress:
                progress(f"{engine} {integrator}")
            for factor in FACTORS[bool(quick)]:
                dt = DT * factor
                steps = max(int(round(base.duration / dt)), 1)
                scene = base.replace(engines=(engine,), dt=base.duration / steps, record_every=10**6,
                                     **({"drake_integrator": integrator} if engine in with_trait("error_controlled")
                                        else {"integrator": integrator}))
                row: dict[str, Any] = {"engine": engine, "integrator": integrator, "dt": scene.dt, "kind": "fixed",
                       "dt_or_tol": scene.dt, "diverged": False, "misread": engine in differing}
                try:
                    position, seconds = _final(scene)[engine]
                    row.update(error=float(np.linalg.norm(position - ref)), seconds=float(seconds))
                except IntegrationError:  # a diverged run is a result: infinite error, left out of fits
                    row.update(error=float("inf"), seconds=None, diverged=True)
                rows.append(row)
    runs = dict.fromkeys((r["engine"], r["integrator"]) for r in rows if not r["misread"])
    orders = {f"{e}/{i}": observed_order(rows, e, i) for e, i in runs}
    no_order = {f"{e}/{i}": why_no_order(rows, e, i) for e, i in runs if orders[f"{e}/{i}"] is None}
    return ModelTradeoff(str(model), base.observe, base.duration, rows, reference,
                         {k: v for k, v in orders.items() if v is not None}, differing,
                         dict(base.left_out), tuple(base.unevaluated), no_order)


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
        out.append(f"  {r['engine']:10s} {r['integrator']:14s} {r['dt']:9.1e} {err:>10s} {sec:>9s}"
                   + ("  misread: not an integrator error" if r.get("misread") else ""))
    out.append("\nObserved order of convergence vs theory:")
    for key, order in result.orders.items():
        out.append(f"  {key:26s} {order:5.2f}   (theory {THEORY[key.split('/')[1]]})")
    for key, why in (result.no_order or {}).items():
        out.append(f"  {key:26s}   -     no order: {why}")
    for engine, c in (result.differing or {}).items():
        out.append(f"DISAGREE: {engine} reads this model differently: at the same states its acceleration differs "
                   f"from relacc's by {c['error']:.2e} (bound {c['bound']:.1e}), so its rows measure that, not its "
                   "integrator, and it has no order (relacc compare FILE says where)")
    out += [f"left out: {name}: {why}" for name, why in (result.left_out or {}).items()]
    out += [f"not evaluated: {line}" for line in result.not_evaluated]
    return "\n".join(out)
