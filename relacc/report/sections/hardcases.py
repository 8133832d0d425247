"""Hard cases: error against distance to gimbal lock, spin rate and distance from the origin."""

from __future__ import annotations

import json
from collections import defaultdict

import numpy as np
from matplotlib import pyplot as plt

from relacc.core.conventions import QUANTITIES
from relacc.core.tolerances import EPS
from relacc.report import svg

ID = "hardcases"
TITLE = "Hard cases"
READS = ("hard", "worst")
"""What ``build`` reads of the context: the report draws this section as soon as they are known."""

FAMILIES = (
    ("gimbal", "delta (rad)", "case 3, middle angle theta2 = +-(pi/2 - delta) for B1 and B2"),
    ("spin", "angular speed (rad/s)", "all cases"),
    ("far", "|s1| (m)", "all cases, B1's origin at distance |s1| from R's origin"),
)
COLORS = {"relacc": "black", "pinocchio/quaternion": "#1f77b4", "pinocchio/euler": "#17becf",
          "drake/quaternion": "#2ca02c", "drake/euler": "#98df8a",
          "mujoco/quaternion": "#d62728", "mujoco/euler": "#ff9896"}
MARKERS = {1: "o", 2: "s", 3: "^"}
ZERO_AT = 1e-14
"""delta = 0 is drawn at this abscissa."""


def _series(results, family):
    """(evaluator, case, quantity) -> sorted arrays of parameter, max error (eps), max bound (eps)."""
    acc = defaultdict(dict)
    for r in results:
        if r.family != family:
            continue
        key = (r.evaluator, r.case, r.quantity)
        x = ZERO_AT if (family == "gimbal" and r.parameter == 0) else r.parameter
        e, b = acc[key].get(x, (0.0, 0.0))
        acc[key][x] = (max(e, r.max_error / EPS), max(b, r.max_bound / EPS))
    out = {}
    for key, pts in acc.items():
        xs = np.array(sorted(pts))
        out[key] = (xs, np.array([pts[x][0] for x in xs]), np.array([pts[x][1] for x in xs]))
    return out


def _plot(results, family, xlabel, scope) -> str:
    series = _series(results, family)
    quantities = [q for q in QUANTITIES if any(k[2] == q for k in series)]
    fig, axes = plt.subplots(1, len(quantities), figsize=(11.5, 2.9), sharey=True)
    for ax, qty in zip(np.atleast_1d(axes), quantities):
        models = {}
        for (ev, case, q), (x, err, bound) in sorted(series.items()):
            if q != qty:
                continue
            ax.plot(x, np.maximum(err, 1e-3), marker=MARKERS[case], ms=3.5, lw=0.8, color=COLORS[ev], alpha=0.85,
                    label=f"{ev}, case {case}")
            prev = models.get(ev)
            models[ev] = (x, bound if prev is None else np.maximum(prev[1], bound))
        for ev, (x, bound) in models.items():
            ax.plot(x, bound, ls="--", lw=1.1, color=COLORS[ev], alpha=0.7)
        svg.log_axes(ax, qty, xlabel)
        if family == "gimbal":
            ax.set_xticks([ZERO_AT, 1e-12, 1e-8, 1e-4, 1e-1], ["0", "1e-12", "1e-8", "1e-4", "0.1"], fontsize=7)
    np.atleast_1d(axes)[0].set_ylabel("max normalized error (eps)")
    svg.legend_below(fig, np.atleast_1d(axes)[-1], ncol=5, offset=-0.2)
    fig.suptitle(f"{family}: {scope}. Dashed: accuracy model (bound) per evaluator.", fontsize=9, y=1.02)
    return svg.figure(fig)


def build(ctx) -> dict:
    results = ctx.hard
    families = []
    for family, xlabel, scope in FAMILIES:
        rs = [r for r in results if r.family == family]
        families.append({"family": family, "figure": _plot(results, family, xlabel, scope), "n": len(rs),
                         "worst_ratio": max(r.max_ratio for r in rs), "passed": all(r.passed for r in rs)})
    table = []
    for family in sorted({r.family for r in results}):
        rs = [r for r in results if r.family == family]
        worst = max(rs, key=lambda r: r.max_ratio)
        table.append({"family": family, "entries": len({r.name for r in rs}), "comparisons": len(rs),
                      "passed": all(r.passed for r in rs), "finite": all(r.finite for r in rs),
                      "worst": f"{worst.name}, case {worst.case}, {worst.evaluator}, {worst.quantity}",
                      "worst_error_eps": worst.max_error / EPS, "worst_ratio": worst.max_ratio})
    w = ctx.worst
    state = {"case": w.case, "q": w.q, "u": w.u, "udot": w.udot}  # json writes each float's shortest exact repr
    return {
        "families": families,
        "table": table,
        "all_passed": all(r.passed for r in results),
        "n_comparisons": len(results),
        "worst": {"ratio": w.ratio, "evaluator": w.evaluator, "quantity": w.quantity, "case": w.case,
                  "error_eps": w.error / EPS, "bound_eps": w.bound / EPS, "description": w.description,
                  "examples": w.examples, "state": json.dumps(state), "passed": w.ratio <= 1.0},
    }
