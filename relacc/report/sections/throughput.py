"""Throughput: relacc's kinematics against looping the engines, and its dynamics and simulation against the
engines' batched APIs, measured on this machine; the recorded runs of both benchmarks."""

from __future__ import annotations

from matplotlib import pyplot as plt

from relacc.engines import TRAITS, anchors, label
from relacc.report import svg
from relacc.tradeoff import batched
from relacc.tradeoff.throughput import recorded_runs

ID = "throughput"
TITLE = "Throughput"
READS = ("throughput", "batched")
"""What ``build`` reads of the context: the report draws this section as soon as they are known."""

RECORDED_COLUMNS = tuple((case, output) for case in (1, 2, 3) for output in ("acceleration", "full"))
"""(case, output) columns of the recorded-runs table."""

WHO = ("relacc", "relacc-1-thread", "relacc-reference", *TRAITS)
"""Who the throughput plot shows, in order: relacc's three rows, then each engine timed."""
COLORS = {"relacc": "black", "relacc-1-thread": "#555555", "relacc-reference": "#999999",
          **{name: t.color for name, t in TRAITS.items()}}


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


BATCHED_LINES = (
    # (what, unit, relacc's row, the anchors' kind, case); rows as named by relacc.tradeoff.batched
    *((f"forward dynamics, case {c}", "ns/state", "relacc", "batched_forward", c) for c in (1, 2, 3)),
    ("one scene, a step per call from Python", "µs/step", "relacc, step per call", "step", None),
    ("one scene, the compiled loop", "µs/step", "relacc, compiled loop", "rollout", None),
    ("ensemble", "steps/s", "relacc", "rollout", None),
)
"""The lines of the dynamics-and-simulation table: relacc's row against each engine's anchor of a kind
(:func:`relacc.engines.anchors`)."""


def _machine_line(m: dict) -> str:
    return f"{m['date']}: {m['cpu']}, {m['logical_cpus']} logical CPUs, commit {m.get('relacc_commit') or '-'}"


def batched_table(result: dict) -> dict:
    """Plain data for the dynamics-and-simulation table: per line, relacc and the anchor at each thread count."""
    rows = result["rows"]
    threads = sorted({r["threads"] for r in rows if r["threads"] is not None})

    def values(section, who, case):
        return {r["threads"]: r["value"] for r in rows if r["section"] == section and r["who"] == who
                and r.get("case") == case}

    lines = []
    for what, unit, mine, kind, case in BATCHED_LINES:
        section = "dynamics" if what.startswith("forward") else "ensemble" if what == "ensemble" else "step"
        for anchor in anchors(kind):
            a, b = values(section, mine, case), values(section, anchor, None)  # an anchor: one model for every case
            if not b:
                continue
            top = max(set(a) & set(b))
            speedup = a[top] / b[top] if unit == "steps/s" else b[top] / a[top]
            lines.append({"what": what, "unit": unit, "anchor": anchor, "relacc": [a.get(t) for t in threads],
                          "engine": [b.get(t) for t in threads], "speedup": speedup, "at": top})
    memory = [{"who": r["who"], "value": r["value"], "best": r["value_best"]} for r in rows if r["section"] == "memory"]
    return {"threads": threads, "lines": lines, "memory": memory, "n_states": result["n_states"],
            "n_steps": result["n_steps"], "members": result["members"], "ensemble_steps": result["ensemble_steps"],
            "scene": result["scene"], "dt": result["dt"], "integrator": result["integrator"],
            "repeats": result["repeats"]}


def build(ctx) -> dict:
    t = ctx.throughput
    rows = t["rows"]
    engines = [e for e in TRAITS if any(r["who"] == e for r in rows)]  # the engines' loops that were timed
    table = []
    for case in (1, 2, 3):
        for output in ("acceleration", "full"):
            by = {r["who"]: r for r in rows if r["case"] == case and r["output"] == output}
            one = by.get("relacc-1-thread")
            table.append({
                "case": case, "output": output,
                "relacc": by["relacc"]["states_per_second"],
                "engines": [{"states_per_second": by[e]["states_per_second"],
                             "vs": by[e]["relacc_speedup_over_this"],
                             "vs_best": by[e].get("relacc_speedup_over_this_best"),
                             "one_thread_vs": by[e]["seconds"] / one["seconds"] if one else None}
                            for e in engines],
                "reference": by.get("relacc-reference", {}).get("states_per_second"),
                "one_thread": one["states_per_second"] if one else None,
            })
    recorded = [{
        "file": run["file"], "machine_line": _machine_line(run["machine"]), "n_states": run["n_states"],
        "cells": [run["ratios"].get(key, {}) for key in RECORDED_COLUMNS],
    } for run in recorded_runs()]
    recorded_batched = [{"file": run["file"], "date": run["machine"]["date"],
                         "machine_line": _machine_line(run["machine"]),
                         "commit": run["machine"].get("relacc_commit") or "-", **run["ratios"]}
                        for run in batched.recorded_runs()]
    return {"batched": batched_table(ctx.batched), "recorded_batched": recorded_batched,
            "machine": t["machine"], "n_states": t["n_states"], "repeats": t["repeats"], "table": table,
            "figure": _plot(rows), "engines": [{"name": e, "label": label(e)} for e in engines],
            "goal": {"name": engines[0], "label": label(engines[0])} if engines else None,
            "recorded": recorded, "recorded_columns": RECORDED_COLUMNS}
