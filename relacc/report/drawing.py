"""The robot as each engine reads it, drawn: ``relacc compare``'s page (plain data in, an inline SVG out).

Two orthographic views of the reference configuration (front: x-z, side: y-z, world components, m), the page's full
width. For each reading that took part, its joints' anchors (squares) with their axes (a short segment) and its links'
mass centres, one marker style per reading so that agreeing readings overlay exactly; where an audit row names a
joint or a link, each engine whose value differs from the reference reading's (relacc's) has it ringed in red and
numbered, and the numbers are listed under the figure (element, engine). Numbers are placed where no other label or
marker is (:func:`place_labels`): labels never overlap. The SVG is inline, its text real ``<text>`` elements (so that
a browser can measure them), its size set by its ``viewBox``.
"""

from __future__ import annotations

import re

import numpy as np

from relacc.engines import TRAITS

STYLES = {"relacc": ("black", "o", 7), **{name: (t.color, t.marker, t.marker_size) for name, t in TRAITS.items()}}
"""Each reading's colour, marker and size: relacc's, then each engine's traits (others: grey dots)."""

OFFSETS = [(dx, dy) for r in (10, 18, 28) for dx, dy in ((r, r), (r, -r), (-r, r), (-r, -r), (r, 0), (-r, 0),
                                                          (0, r), (0, -r))]
"""Candidate label positions around a point, in points, nearest first."""


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


def drawing(geometry: dict, audit: list, reference: str = "relacc") -> dict | None:
    """``{"svg": inline SVG markup, "marked": [(number, element, engine)]}``, or None when no reading gave a joint or a
    link."""
    points = [x["anchor"] for g in geometry.values() for x in g["joints"] if x["anchor"] is not None]
    points += [x["com"] for g in geometry.values() for x in g["links"]]
    if not points:
        return None
    from relacc.report.svg import inline, legend_below, plt

    size = max(float(np.ptp(np.array(points), axis=0).max()), 1e-3)
    bad = flagged(audit, reference)
    marked: dict[tuple[str, str], int] = {}  # (kind name, engine) -> its number
    spots = []  # (axes, x, y, number)
    fig, axes = plt.subplots(1, 2, figsize=(12.0, 5.0))
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
            here = [(f"joint {x['name']}", x["anchor"]) for x in g["joints"]
                    if (engine, "joint", x["name"]) in bad and x["anchor"] is not None]
            here += [(f"link {x['name']}", x["com"]) for x in g["links"] if (engine, "link", x["name"]) in bad]
            for what, p in here:
                number = marked.setdefault((what, engine), len(marked) + 1)
                ax.plot(p[i], p[j], ls="none", marker="o", ms=13, mfc="none", mec="red", mew=1.2)
                spots.append((ax, p[i], p[j], number))
        ax.set_title(title)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"{'xyz'[i]} (m)")
        ax.set_ylabel(f"{'xyz'[j]} (m)")
    legend_below(fig, axes[0], ncol=4, offset=-0.12)
    place_labels(fig, spots)
    return {"svg": inline(fig), "marked": [(n, what, engine) for (what, engine), n in marked.items()]}


def place_labels(fig, spots) -> list:
    """Each spot ``(axes, x, y, number)``'s number written beside it where its box meets no label placed before (one
    label for the numbers of spots drawn at one place), nearest candidate first (:data:`OFFSETS`); returns the label
    boxes (display units)."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    groups: dict = {}
    for ax, x, y, number in spots:
        key = (id(ax), round(float(x), 9), round(float(y), 9))
        groups.setdefault(key, (ax, x, y, []))[3].append(number)
    placed = []
    for ax, x, y, numbers in groups.values():
        text = ",".join(str(n) for n in sorted(set(numbers)))
        label = None
        for dx, dy in OFFSETS:
            label = ax.annotate(text, (x, y), xytext=(dx, dy), textcoords="offset points", fontsize=7, color="red",
                                ha="center", va="center",
                                bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "red", "lw": 0.5})
            box = label.get_window_extent(renderer)
            if not any(box.overlaps(other) for other in placed):
                break
            label.remove()
            label = None
        if label is None:  # every candidate taken: the farthest one (it is listed under the figure all the same)
            label = ax.annotate(text, (x, y), xytext=OFFSETS[-1], textcoords="offset points", fontsize=7, color="red",
                                ha="center", va="center")
        placed.append(label.get_window_extent(renderer))
    return placed
