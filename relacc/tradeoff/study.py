"""The chain's accuracy-against-cost study: its run, its Pareto fronts and its text (the package's docstring
states what is measured)."""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from relacc.tradeoff import derivatives, integrators

if TYPE_CHECKING:
    from relacc.fixtures import Fixture

QUICK: dict[str, Any] = {"states": 20, "scenes": ("tumbling", "gravity_spring"), "duration": 0.25, "factors": (8, 4, 2),
         "euler_factors": (8, 4, 2), "tolerances": (1e-6, 1e-9), "repeats": 1}
REPORT: dict[str, Any] = {"states": 1000, "scenes": None, "duration": 1.0, "factors": (16, 8, 4, 2, 1),
          "euler_factors": (2, 1, 0.5), "tolerances": (1e-4, 1e-6, 1e-8, 1e-10), "repeats": 3}
"""The report's sweep: every scene, capped at 1 s, Euler down to half the scene's step."""
FULL: dict[str, Any] = {"states": 1000, "scenes": None, "duration": None, "factors": (16, 8, 4, 2, 1),
        "euler_factors": (2, 1, 0.5, 0.25), "tolerances": (1e-4, 1e-6, 1e-8, 1e-10), "repeats": 3}


@dataclass(frozen=True)
class Tradeoff:
    """Both sweeps' rows, the integrators' reference checks and the observed orders."""

    derivatives: list
    integrators: list
    references: list
    orders: dict

    def as_json(self) -> dict:
        """The ``relacc tradeoff --json`` object."""
        return {
            "derivatives": [{k: r[k] for k in ("case", "method", "param", "error", "seconds_per_state")}
                            for r in self.derivatives],
            "integrators": [{k: r[k] for k in ("scene", "engine", "integrator", "case", "dt_or_tol", "error",
                                               "energy_drift", "seconds", "diverged")} for r in self.integrators],
            "orders": self.orders,
            "references": self.references,
        }


def pareto(rows: Iterable[dict], error: str = "error", cost: str = "seconds") -> list[dict]:
    """The rows not beaten on both error and cost by another row, cheapest first (diverged runs excluded)."""
    front, best = [], float("inf")
    for r in sorted((r for r in rows if not r.get("diverged")), key=lambda r: (r[cost], r[error])):
        if r[error] < best:
            front.append(r)
            best = r[error]
    return front


def scene_paths(cfg: dict) -> list:
    """The shipped chain scenes a profile's integrator sweep runs (``cfg["scenes"]``: their names, or None for all)."""
    from relacc.fixtures import shipped

    return [p for p in shipped.scene_paths("chain") if not cfg["scenes"] or p.stem in cfg["scenes"]]


def scene_sweep(path: str | os.PathLike, cfg: dict) -> tuple[list, dict]:
    """``(rows, reference)`` of one scene's integrator sweep under a profile (:func:`integrators.sweep`), the scene
    capped at ``cfg["duration"]``; a function of its arguments alone, so that it can run in another process."""
    from relacc.simulate import scenes

    scene = scenes.load(path)
    if cfg["duration"]:
        scene = scene.replace(duration=round(min(scene.duration, cfg["duration"]) / scene.dt) * scene.dt)
    return integrators.sweep(scene, cfg["factors"], cfg["tolerances"], cfg["euler_factors"])


def derivative_sweep(fixture: Fixture, cfg: dict, seed: int = 0) -> list:
    """The acceleration's rows: every method on ``cfg["states"]`` states of each case (:func:`derivatives.sweep`)."""
    from relacc.engines import chain_engines, load_engine

    engines = {n: load_engine(n, fixture) for n in chain_engines()}
    return derivatives.sweep(fixture.chain, cfg["states"], seed, cfg["repeats"], engines)


def assemble(drows: list, sweeps: list) -> Tradeoff:
    """The study from its derivative rows and its scenes' ``(rows, reference)`` in scene order, with the observed
    orders (median over scenes)."""
    irows = [r for rows, _ in sweeps for r in rows]
    refs = [ref for _, ref in sweeps]
    orders = {}
    for engine, names in integrators.FIXED.items():
        for integrator in names:
            per_scene = [o for o in (integrators.observed_order(irows, engine, integrator, r["scene"])
                                     for r in refs) if o is not None]
            if per_scene:
                per_scene.sort()
                orders[f"{engine}/{integrator}"] = per_scene[len(per_scene) // 2]
    return Tradeoff(drows, irows, refs, orders)


def run(quick: bool = False, seed: int = 0, progress: Callable[[str], object] | None = None,
        fixture: Fixture | None = None, profile: dict | None = None) -> Tradeoff:
    """Run both sweeps (``quick``: a small one for tests and CI; ``profile``: QUICK, REPORT or FULL)."""
    from relacc.fixtures import load

    cfg = profile if profile is not None else (QUICK if quick else FULL)
    fixture = fixture if fixture is not None else load()
    if progress:
        progress("derivative sweep")
    drows = derivative_sweep(fixture, cfg, seed)
    sweeps = []
    for path in scene_paths(cfg):
        if progress:
            progress(f"integrator sweep: {path.stem}")
        sweeps.append(scene_sweep(path, cfg))
    return assemble(drows, sweeps)


def format_text(result: Tradeoff) -> str:
    """The human-readable report printed by ``relacc tradeoff``: Pareto fronts and observed orders."""
    out = []
    out.append("relacc tradeoff: what accuracy costs in time (errors: acceleration normalized by its term scale; "
               "trajectories: |r_G2(T) - reference| in m)")
    out.append("\nAcceleration, Pareto front per case (cheapest method for each accuracy level):")
    out.append(f"  {'case':4s} {'method':20s} {'h':>9s} {'error':>9s} {'s/state':>10s}")
    for case in sorted({r["case"] for r in result.derivatives}):
        for r in pareto([r for r in result.derivatives if r["case"] == case], cost="seconds_per_state"):
            h = "-" if r["param"] is None else f"{r['param']:.1e}"
            out.append(f"  {case:<4d} {r['method']:20s} {h:>9s} {r['error']:9.1e} {r['seconds_per_state']:10.2e}")
    for ref in result.references:
        out.append(f"\nTrajectories, scene {ref['scene']} (reference: {ref['reference']}; {ref['check']} agrees to "
              f"{ref['agreement_m']:.1e} m), Pareto front:")
        out.append(f"  {'engine':10s} {'integrator':12s} {'dt or tol':>10s} {'error (m)':>10s} {'seconds':>9s}")
        for r in pareto([r for r in result.integrators if r["scene"] == ref["scene"]]):
            out.append(f"  {r['engine']:10s} {r['integrator']:12s} {r['dt_or_tol']:10.1e} {r['error']:10.1e} "
                  f"{r['seconds']:9.4f}")
    out.append("\nObserved order of convergence (median over scenes) vs theory:")
    from relacc.tradeoff.integrators import THEORY

    for key, order in result.orders.items():
        out.append(f"  {key:22s} {order:5.2f}   (theory {THEORY[key.split('/')[1]]})")
    return "\n".join(out)


__all__ = ["FULL", "QUICK", "REPORT", "Tradeoff", "assemble", "derivative_sweep", "format_text", "pareto", "run",
           "scene_paths", "scene_sweep"]
