"""Simulation: the shipped scenes on relacc and every engine, and how agreement degrades with the step."""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt

from relacc.report import svg

ID = "simulation"
TITLE = "Simulation"

AGREEMENT_M = 1e-6
"""Metres within which the engines' G2 positions agree at each scene's own step, as the page states (a larger
difference is a failure of the report, :meth:`relacc.report.build.ReportContext.failures`)."""

COLORS = {"relacc-pinocchio": "#1f77b4", "relacc-mujoco": "#d62728", "pinocchio-mujoco": "#2ca02c",
          "relacc-drake": "#9467bd", "pinocchio-drake": "#8c564b", "mujoco-drake": "#e377c2"}


def _differences_plot(entries) -> str:
    fig, axes = plt.subplots(1, len(entries), figsize=(11.5, 2.6), sharey=True)
    for ax, e in zip(np.atleast_1d(axes), entries):
        r = e["result"]
        names = list(r.trajectories)
        for i, a in enumerate(names):
            for b in names[i + 1:]:
                ta, tb = r.trajectories[a], r.trajectories[b]
                d = np.linalg.norm(ta.position - tb.position, axis=1)
                ax.plot(ta.t, np.maximum(d, 1e-17), lw=1, color=COLORS.get(f"{a}-{b}"), label=f"{a} - {b}")
        ax.set_yscale("log")
        ax.set_title(r.scene.name, fontsize=9)
        ax.set_xlabel("t (s)")
    np.atleast_1d(axes)[0].set_ylabel("|r_G2 difference| (m)")
    svg.legend_below(fig, np.atleast_1d(axes)[0], ncol=3, offset=-0.22, fontsize=8)
    return svg.figure(fig)


def _sweep_plot(entries) -> str:
    fig, ax = plt.subplots(figsize=(5.5, 3.2))
    for e in entries:
        dt = np.array([s["dt"] for s in e["sweep"]])
        pos = np.array([max(s["position"], 1e-17) for s in e["sweep"]])
        ax.loglog(dt, pos, marker="o", label=e["result"].scene.name)
    ax.axhline(AGREEMENT_M, color="crimson", ls="--", lw=1)
    ax.set_xlabel("time step (s)")
    ax.set_ylabel("largest G2 position difference (m)")
    ax.legend(fontsize=7)
    ax.set_title(f"agreement vs step (RK4); dashed: {AGREEMENT_M:.0e} m", fontsize=9)
    return svg.figure(fig)


def _order(sweep):
    """Observed order of the agreement between the two finest steps above rounding (1e-12 m), or None."""
    for a, b in zip(sweep, sweep[1:]):
        if a["position"] >= 1e-12:
            return float(np.log2(b["position"] / a["position"]) / np.log2(b["dt"] / a["dt"]))
    return None


def readable(value) -> str:
    """Plain data as a reader reads it: a dict as ``key value; ...`` (zero and empty entries left out: an effect that
    is off), a list of numbers as ``(x, y, z)``, numbers to 4 significant digits."""
    if isinstance(value, dict):
        parts = [f"{k} {readable(v)}" for k, v in value.items() if v not in (None, 0, 0.0, [], {}, "")
                 and not (isinstance(v, list) and all(x == 0 for x in v if isinstance(x, (int, float))) and v)]
        return "; ".join(parts) if parts else "none"
    if isinstance(value, (list, tuple)):
        return "(" + ", ".join(readable(v) for v in value) + ")"
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def _words(x) -> str:
    """A list of words joined, anything else :func:`readable`."""
    return ", ".join(x) if isinstance(x, list) and all(isinstance(i, str) for i in x) else readable(x)


def build(ctx) -> dict:
    entries = ctx.simulations
    rows = []
    for e in entries:
        r = e["result"]
        summary = r.summary()
        eff = r.scene.effects
        rows.append({
            "name": r.scene.name, "title": r.scene.title, "description": r.scene.description,
            "case": r.scene.case, "dt": r.scene.dt, "duration": r.scene.duration, "integrator": r.scene.integrator,
            "effects": readable(eff.describe()),
            "position": summary["max_point_position_difference"], "velocity": summary["max_point_velocity_difference"],
            "engines": [{"name": n, "energy_drift": v["energy_drift"], "momentum_drift": v["momentum_drift"],
                         "seconds": v["seconds"],
                         "applied": "; ".join(f"{k}: {_words(x)}" for k, x in v["applied"].items())}
                        for n, v in summary["engines"].items()],
            "note": summary["reference_acceleration_vs_engines"],
            "sweep": e["sweep"], "order": _order(e["sweep"]),
        })
    return {"rows": rows, "differences": _differences_plot(entries), "sweep": _sweep_plot(entries),
            "all_within": all(r["position"] <= AGREEMENT_M for r in rows), "within_m": f"{AGREEMENT_M:.0e}"}
