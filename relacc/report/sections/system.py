"""A figure of the two-body chain drawn from the fixture's real geometry."""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt

from relacc.core.note.common import configuration
from relacc.core.rotations import quaternion_exp
from relacc.report import svg

ID = "system"
TITLE = "The system being checked"

# The state the figure is drawn at (case 1 coordinates): a visible, generic pose.
STATE = {
    "s1": (0.30, -0.22, 0.18),
    "rot_B1": (0.25, -0.15, 0.45),  # rotation vector of quat_B1, rad
    "s2_p": (0.10, 0.06, -0.05),
    "rot_B2B1": (0.35, 0.55, -0.25),  # rotation vector of quat_B2/B1, rad
}


def _q14():
    return np.concatenate([STATE["s1"], quaternion_exp(np.array(STATE["rot_B1"])), STATE["s2_p"],
                           quaternion_exp(np.array(STATE["rot_B2B1"]))])


def _box(ax, center, half, R, **kw):
    """Wireframe box with half sizes ``half`` about ``center`` (body axes R columns)."""
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
    pts = center + corners @ R.T
    for i in range(8):
        for j in range(i + 1, 8):
            if np.sum(np.abs(corners[i] - corners[j]) > 0) == 1:
                ax.plot(*np.c_[pts[i], pts[j]], **kw)


def _arrow(ax, start, vec, color, label, offset=(0, 0, 0.02), lw=2.2):
    ax.quiver(*start, *vec, color=color, lw=lw, arrow_length_ratio=0.15)
    ax.text(*(start + 0.5 * vec + np.asarray(offset)), label, color=color, fontsize=12, fontweight="bold")


def _frame(ax, origin, R, length, name, color):
    for k, axis in enumerate("xyz"):
        ax.quiver(*origin, *(length * R[:, k]), color=color, lw=1.0, arrow_length_ratio=0.25, alpha=0.9)
        ax.text(*(origin + 1.15 * length * R[:, k]), f"{axis}{name}", color=color, fontsize=8)


def build(ctx) -> dict:
    chain = ctx.harness.chain
    cfg = configuration(chain, 1, _q14())
    s1, C1, C2 = cfg.s1, cfg.R_B1_T, cfg.R_B2_T
    Q = s1 + cfg.q2
    P = Q + cfg.s2
    G2 = P + cfg.r2
    G1 = s1 + C1 @ chain.r1

    fig = plt.figure(figsize=(9, 7))
    ax = fig.add_subplot(projection="3d")
    _frame(ax, np.zeros(3), np.eye(3), 0.12, "", "black")
    ax.text(0, 0, -0.05, "O", fontsize=10)
    _box(ax, G1, np.array([0.2, 0.15, 0.1]), C1, color="#4a78b5", lw=0.8, alpha=0.6)
    _frame(ax, s1, C1, 0.12, "'1", "#4a78b5")
    _frame(ax, P, C2, 0.10, "'2", "#c0622d")
    _arrow(ax, np.zeros(3), s1, "#333333", "s1", offset=(0, 0, -0.05))
    _arrow(ax, s1, cfg.q2, "#2e8b57", "q2", offset=(0, 0, 0.03))
    _arrow(ax, Q, cfg.s2, "#8e44ad", "s2", offset=(0, 0, -0.05))
    _arrow(ax, P, cfg.r2, "#c0622d", "r2", offset=(0, 0, 0.06))
    ax.plot(*np.c_[P, G2], color="#c0622d", lw=7, alpha=0.3, solid_capstyle="round")
    labels = ((s1, "B1 origin", "#4a78b5", (-0.02, 0, -0.06)), (G1, "G1", "#4a78b5", (0, 0, 0.03)),
              (P, "joint point", "#8e44ad", (-0.02, 0, -0.09)), (G2, "G2", "#c0622d", (0.02, 0, 0.0)))
    for point, name, color, off in labels:
        ax.scatter(*point, color=color, s=22, depthshade=False)
        ax.text(*(point + np.asarray(off)), name, fontsize=10, color=color)
    pts = np.array([np.zeros(3), s1, Q, P, G2, G1])
    lo, hi = pts.min(0) - 0.08, pts.max(0) + 0.08
    span = (hi - lo).max()
    mid = (hi + lo) / 2
    ax.set_xlim(mid[0] - span / 2, mid[0] + span / 2)
    ax.set_ylim(mid[1] - span / 2, mid[1] + span / 2)
    ax.set_zlim(mid[2] - span / 2, mid[2] + span / 2)
    ax.set_box_aspect((1, 1, 1), zoom=1.15)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.pane.set_alpha(0.15)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.view_init(elev=20, azim=-62)
    return {
        "figure": svg.figure(fig),
        "q2": chain.q2.tolist(),
        "r2": chain.r2.tolist(),
        "r1": chain.r1.tolist(),
        "m1": chain.m1,
        "m2": chain.m2,
        "state": {k: list(v) for k, v in STATE.items()},
        "model": ctx.harness.fixture.source.name,
    }
