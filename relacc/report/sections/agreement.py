"""The agreement matrix (case x engine x quantity) and the error distributions."""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt

from relacc.core.conventions import QUANTITIES
from relacc.core.tolerances import EPS
from relacc.report import svg
from relacc.validation.summary import EDGES

ID = "agreement"
TITLE = "Agreement with the engines"
READS = ("check",)
"""What ``build`` reads of the context: the report draws this section as soon as they are known."""

FLOOR_EPS = 1e-3
"""Errors of exactly zero are drawn at this many eps (log axes cannot show zero)."""


def _cell(comp) -> dict:
    ratio = comp.max_error / comp.tolerance
    return {
        "max_eps": comp.max_error / EPS,
        "median_eps": comp.median_error / EPS,
        "passed": comp.passed,
        "ratio": ratio,
        # green, darker as the error nears the tolerance; red when above
        "color": "#f4b6b6" if not comp.passed else f"hsl(130, 45%, {95 - 35 * min(ratio, 1):.0f}%)",
    }


def _plot_case(case, comps, tol_eps) -> str:
    fig, axes = plt.subplots(1, len(QUANTITIES), figsize=(11, 2.4), sharey=True)
    for ax, qty in zip(axes, QUANTITIES):
        for comp in (c for c in comps if c.quantity == qty):
            if comp.errors is not None:  # every state's error
                e = np.sort(np.maximum(comp.errors / EPS, FLOOR_EPS))
                frac = np.arange(1, e.size + 1) / e.size
            else:  # a sweep too long to keep: its histogram (8 bins per decade)
                e, frac = EDGES / EPS, np.cumsum(comp.counts)[:-1] / comp.n
            ax.step(e, frac, where="post", label=f"{comp.engine}/{comp.route}", lw=1.2)
        ax.axvline(tol_eps, color="crimson", ls="--", lw=1)
        ax.set_xscale("log")
        ax.set_xlim(FLOOR_EPS / 2, tol_eps * 4)
        ax.set_title(qty, fontsize=9)
        ax.set_xlabel("normalized error (eps)")
    axes[0].set_ylabel("fraction of states")
    axes[-1].legend(fontsize=7, loc="lower right")
    fig.suptitle(f"Case {case}: cumulative distribution of the error (dashed: tolerance)", fontsize=9, y=1.04)
    return svg.figure(fig)


def build(ctx) -> dict:
    check = ctx.check
    tol_eps = check.comparisons[0].tolerance / EPS
    rows = []
    for case in sorted({c.case for c in check.comparisons}):
        for engine, route in dict.fromkeys((c.engine, c.route) for c in check.comparisons if c.case == case):
            cells = {c.quantity: _cell(c) for c in check.comparisons
                     if (c.case, c.engine, c.route) == (case, engine, route)}
            rows.append({"case": case, "engine": engine, "route": route, "cells": cells})
    plots = [
        {"case": case, "figure": _plot_case(case, [c for c in check.comparisons if c.case == case], tol_eps)}
        for case in sorted({c.case for c in check.comparisons})
    ]
    return {"quantities": QUANTITIES, "rows": rows, "plots": plots, "tolerance_eps": tol_eps,
            "n_states": check.n_states, "floor_eps": FLOOR_EPS}
