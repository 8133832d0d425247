"""Throughput: relacc's batched kernels against looping the engines, measured on this machine."""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt

from relacc.report import svg
from relacc.tradeoff.throughput import recorded_runs

ID = "throughput"
TITLE = "Throughput"

RECORDED_COLUMNS = tuple((case, output) for case in (1, 2, 3) for output in ("acceleration", "full"))
"""(case, output) columns of the recorded-runs table."""

WHO = ("relacc", "relacc-1-thread", "relacc-reference", "pinocchio", "mujoco")
COLORS = {"relacc": "black", "relacc-1-thread": "#555555", "relacc-reference": "#999999", "pinocchio": "#1f77b4",
          "mujoco": "#d62728"}


def _plot(rows) -> str:
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.0), sharey=True)
    for ax, output in zip(axes, ("acceleration", "full")):
        present = [w for w in WHO if any(r["who"] == w and r["output"] == output for r in rows)]
        width = 0.8 / len(present)
        for k, who in enumerate(present):
            xs, ys = [], []
            for case in (1, 2, 3):
                row = next((r for r in rows if (r["case"], r["who"], r["output"]) == (case, who, output)), None)
                if row:
                    xs.append(case + (k - (len(present) - 1) / 2) * width)
                    ys.append(row["states_per_second"])
            ax.bar(xs, ys, width=width, color=COLORS[who], label=who)
        ax.set_yscale("log")
        ax.set_xticks([1, 2, 3], ["case 1", "case 2", "case 3"])
        ax.set_title("acceleration only" if output == "acceleration" else "position, velocity, acceleration, V, Vdot",
                     fontsize=9)
    axes[0].set_ylabel("states per second")
    svg.legend_below(fig, axes[0], ncol=5, offset=-0.1, fontsize=8)
    return svg.figure(fig)


def build(ctx) -> dict:
    t = ctx.throughput
    rows = t["rows"]
    table = []
    for case in (1, 2, 3):
        for output in ("acceleration", "full"):
            by = {r["who"]: r for r in rows if r["case"] == case and r["output"] == output}
            table.append({
                "case": case, "output": output,
                "relacc": by["relacc"]["states_per_second"],
                "pinocchio": by["pinocchio"]["states_per_second"],
                "mujoco": by["mujoco"]["states_per_second"],
                "vs_pinocchio": by["pinocchio"]["relacc_speedup_over_this"],
                "vs_pinocchio_best": by["pinocchio"].get("relacc_speedup_over_this_best"),
                "vs_mujoco": by["mujoco"]["relacc_speedup_over_this"],
                "reference": by.get("relacc-reference", {}).get("states_per_second"),
                "one_thread": by.get("relacc-1-thread", {}).get("states_per_second"),
                "one_thread_vs_pinocchio": (by["pinocchio"]["seconds"] / by["relacc-1-thread"]["seconds"]
                                            if "relacc-1-thread" in by else None),
            })
    recorded = [{
        "file": run["file"], "date": run["machine"]["date"], "cpu": run["machine"]["cpu"],
        "cpus": run["machine"]["logical_cpus"], "commit": run["machine"].get("relacc_commit") or "-",
        "n_states": run["n_states"],
        "cells": [run["ratios"].get(key, {}) for key in RECORDED_COLUMNS],
    } for run in recorded_runs()]
    return {"machine": t["machine"], "n_states": t["n_states"], "repeats": t["repeats"], "table": table,
            "figure": _plot(rows), "min_vs_pinocchio": float(np.min([r["vs_pinocchio"] for r in table])),
            "recorded": recorded, "recorded_columns": RECORDED_COLUMNS}
