"""What accuracy costs in time: the two work-precision diagrams and their Pareto fronts."""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt
from matplotlib.ticker import NullFormatter

from relacc.engines import TRAITS
from relacc.report import svg
from relacc.tradeoff.derivatives import THEORY as FD_THEORY
from relacc.tradeoff.derivatives import theory_step
from relacc.tradeoff.integrators import THEORY
from relacc.tradeoff.study import pareto

ID = "tradeoff"
TITLE = "What accuracy costs"

MARK = {"analytic": ("black", "*"), "analytic-reference": ("#555555", "P"),
        **{name: (t.color, t.marker) for name, t in TRAITS.items()},
        "forward": ("#ff7f0e", "."), "central": ("#bcbd22", "."), "central4": ("#9467bd", "."),
        "richardson": ("#8c564b", "."), "complex-step": ("#e377c2", ".")}
"""Each method's colour and marker: relacc's analytic formulas, each engine's traits, the finite differences."""


def _derivative_plot(rows) -> str:
    cases = sorted({r["case"] for r in rows})
    fig, axes = plt.subplots(1, len(cases), figsize=(11.5, 3.4), sharey=True)
    for ax, case in zip(np.atleast_1d(axes), cases):
        for method, (color, marker) in MARK.items():
            pts = sorted((r for r in rows if r["case"] == case and r["method"] == method),
                         key=lambda r: r["param"] or 0)
            if not pts:
                continue
            t = [r["seconds_per_state"] for r in pts]
            e = [max(r["error"], 1e-18) for r in pts]
            ax.plot(t, e, marker=marker, color=color, ls="-" if len(pts) > 1 else "none", ms=6 if len(pts) == 1 else 4,
                    lw=1, label=method)
        svg.log_axes(ax, f"case {case}", "seconds per state")
        ax.xaxis.set_minor_formatter(NullFormatter())
    np.atleast_1d(axes)[0].set_ylabel("max normalized error of a_G2")
    svg.legend_below(fig, np.atleast_1d(axes)[0], ncol=9, offset=-0.12)
    return svg.figure(fig)


def _step_plot(rows) -> str:
    """Error against h for the finite-difference methods (case 1), theory's best h marked."""
    fig, ax = plt.subplots(figsize=(6.5, 3.4))
    for method in ("forward", "central", "central4", "richardson", "complex-step"):
        pts = sorted((r for r in rows if r["case"] == 1 and r["method"] == method), key=lambda r: r["param"])
        if pts:
            color = MARK[method][0]
            ax.loglog([r["param"] for r in pts], [max(r["error"], 1e-18) for r in pts], marker=".", color=color,
                      label=method)
            if method in FD_THEORY:
                ax.axvline(theory_step(method), color=color, ls=":", lw=1)
    ax.set_xlabel("step h (s)")
    ax.set_ylabel("max normalized error")
    ax.set_title("case 1: error against step; dotted: eps^(1/2), eps^(1/3), eps^(1/5)", fontsize=9)
    ax.legend(fontsize=7)
    return svg.figure(fig)


def _integrator_plot(rows, scenes) -> str:
    fig, axes = plt.subplots(1, len(scenes), figsize=(11.5, 3.2), sharey=True)
    styles = {"rk4": "-", "euler": "--", "implicit": ":", "implicitfast": "-.", "RK45": (0, (1, 1)),
              "DOP853": (0, (3, 1, 1, 1)), "runge_kutta2": (0, (5, 2)), "runge_kutta3": (0, (5, 1, 1, 1)),
              "runge_kutta5": (0, (8, 2))}
    colors = {"relacc": "black", **{name: t.color for name, t in TRAITS.items()}}
    for ax, scene in zip(np.atleast_1d(axes), scenes):
        for engine in colors:
            for integrator in styles:
                pts = sorted((r for r in rows if r["scene"] == scene and r["engine"] == engine
                              and r["integrator"] == integrator and not r["diverged"]), key=lambda r: r["seconds"])
                if pts:
                    ax.plot([r["seconds"] for r in pts], [max(r["error"], 1e-16) for r in pts], marker=".",
                            ls=styles[integrator], color=colors[engine], lw=1, label=f"{engine}/{integrator}")
        svg.log_axes(ax, scene, "wall time (s)")
    np.atleast_1d(axes)[0].set_ylabel("|r_G2(T) - reference| (m)")
    svg.legend_below(fig, np.atleast_1d(axes)[0], ncol=6, offset=-0.3)
    return svg.figure(fig)


def build(ctx) -> dict:
    t = ctx.tradeoff
    scenes = [r["scene"] for r in t.references]
    fronts = {
        "derivatives": [{"case": c, "rows": pareto([r for r in t.derivatives if r["case"] == c],
                                                    cost="seconds_per_state")}
                        for c in sorted({r["case"] for r in t.derivatives})],
        "integrators": [{"scene": s, "rows": pareto([r for r in t.integrators if r["scene"] == s])} for s in scenes],
    }
    orders = [{"key": k, "observed": v, "theory": THEORY[k.split("/")[1]]} for k, v in t.orders.items()]
    diverged = [f"{r['scene']}: {r['engine']}/{r['integrator']} at {r['dt_or_tol']:g} s"
                for r in t.integrators if r["diverged"]]
    return {"derivatives": _derivative_plot(t.derivatives), "steps": _step_plot(t.derivatives),
            "integrators": _integrator_plot(t.integrators, scenes), "fronts": fronts, "orders": orders,
            "references": t.references, "diverged": diverged, "quick": ctx.quick,
            "machine": ctx.throughput["machine"]}
