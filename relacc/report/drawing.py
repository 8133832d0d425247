"""The robot as each engine reads it, drawn: ``relacc compare``'s page (plain data in, an SVG data URI out).

Two orthographic views of the reference configuration (front: x-z, side: y-z, world components, m). For each
engine that took part, its joints' anchors (squares) with their axes (a short segment) and its links' mass centres
(circles), one marker style per engine so that agreeing engines overlay exactly; where an audit row names a joint
or a link, each engine whose value differs from the reference reading's (relacc's) has it ringed in red and labelled.
"""

from __future__ import annotations

import re

import numpy as np

STYLES = {"relacc": ("black", "o", 7), "mujoco": ("tab:green", "d", 6), "pinocchio": ("tab:blue", "x", 6),
          "drake": ("tab:orange", "+", 8)}
"""Each engine's colour, marker and size (others: grey dots)."""


def flagged(audit, reference: str = "relacc") -> set[tuple[str, str, str]]:
    """``{(engine, "joint" | "link", name)}``: what the audit rows' ``where`` ("joint NAME (...)", "link NAME ...")
    names, for each engine whose value in the row differs from the reference reading's."""
    out = set()
    for row in audit:
        engines = set(row) - {"item", "where", "cause", "cause_kind", "place", reference}
        if m := re.match(r"joint (.+?) \(", row["where"]):
            out |= {(e, "joint", m.group(1)) for e in engines}
        elif m := re.match(r"link (\S+)", row["where"]):
            out |= {(e, "link", m.group(1)) for e in engines}
    return out


def drawing(geometry: dict, audit: list, reference: str = "relacc") -> str | None:
    """The two views as an SVG data URI, or None when no engine gave a joint or a link."""
    points = [x["anchor"] for g in geometry.values() for x in g["joints"] if x["anchor"] is not None]
    points += [x["com"] for g in geometry.values() for x in g["links"]]
    if not points:
        return None
    from relacc.report.svg import figure, legend_below, plt

    size = max(float(np.ptp(np.array(points), axis=0).max()), 1e-3)
    bad = flagged(audit, reference)
    fig, axes = plt.subplots(1, 2, figsize=(8.0, 4.2))
    for ax, (i, j, title) in zip(axes, ((0, 2, "front (x, z)"), (1, 2, "side (y, z)"))):
        for engine, g in geometry.items():
            color, marker, ms = STYLES.get(engine, ("grey", ".", 5))
            anchors = [(x, x["anchor"]) for x in g["joints"] if x["anchor"] is not None]
            for joint, a in anchors:
                if joint["axis"] is not None:
                    e = 0.08 * size * np.asarray(joint["axis"])
                    ax.plot([a[i] - e[i], a[i] + e[i]], [a[j] - e[j], a[j] + e[j]], color=color, lw=1, alpha=0.7)
            if anchors:
                ax.plot([a[i] for _, a in anchors], [a[j] for _, a in anchors], ls="none", marker="s", ms=ms - 2,
                        mfc="none", color=color, label=f"{engine} joints")
            coms = [x["com"] for x in g["links"]]
            if coms:
                ax.plot([c[i] for c in coms], [c[j] for c in coms], ls="none", marker=marker, ms=ms,
                        mfc="none", color=color, label=f"{engine} mass centres")
            marked = [(x["name"], x["anchor"]) for x in g["joints"]
                      if (engine, "joint", x["name"]) in bad and x["anchor"] is not None]
            marked += [(x["name"], x["com"]) for x in g["links"] if (engine, "link", x["name"]) in bad]
            for name, p in marked:
                ax.plot(p[i], p[j], ls="none", marker="o", ms=13, mfc="none", mec="red", mew=1.2)
                ax.annotate(f"{name} ({engine})", (p[i], p[j]), fontsize=6, color="red", xytext=(4, 4),
                            textcoords="offset points")
        ax.set_title(title)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"{'xyz'[i]} (m)")
        ax.set_ylabel(f"{'xyz'[j]} (m)")
    legend_below(fig, axes[0], ncol=3)
    return figure(fig)
