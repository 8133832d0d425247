"""What the differences between two descriptions do to the dynamics (``relacc diff``, :mod:`relacc.validation.diff`).

A's coordinates are mapped to B's through the matched joints: a hinge's or slide's displacement from its zero times
the joint's sign (-1 where the axis is reversed), a ball's quaternion as it is and a free joint's pose through the
placement (both only where the two files' body frames coincide: otherwise their coordinates mean different things and
the dynamics are not compared, said in one note). Speeds map by ``u_B = T u_A`` with ``T`` orthogonal (signs and
rotations), so that ``M_A`` is compared with ``T^T M_B T``, the bias forces ``f_A`` with ``T^T f_B`` and the forward
dynamics ``udot_A`` with ``T^T udot_B``: MuJoCo's speeds (case 2), relacc's own dynamics
(:func:`relacc.dynamics.tree.tree_dynamics`), gravity each file's own.

Each quantity's difference is normalized by its largest entry over A and B at that state, and is *beyond* printing
when it exceeds :func:`relacc.core.tolerances.printed_tolerance` of ``1 + 2 pi d`` (``d`` the deepest part's depth: each
orientation on a path may be off by ``rtol pi`` rad and moves an inertia's entries by twice that), times the mass
matrix's condition number for the forward dynamics. A row whose allowance reaches the largest entry itself
(``decides`` false: an ill-conditioned mass matrix) cannot tell two files apart, and says so.

A row beyond printing is then *explained* or not: the same comparison with A's parts given B's masses, mass centres,
inertias and joint armatures, and B's gravity (:func:`with_inertials_of`). Within printing then, the listed
differences of those numbers are the whole of the dynamics' difference; beyond it still, the geometry differs too
(axes, anchors, placements: the joints move the masses differently).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from relacc.core.conventions import Quantity
from relacc.core.rotations import quaternion_multiply
from relacc.core.tolerances import printed_tolerance

QUANTITIES = (Quantity.MASS_MATRIX, Quantity.BIAS_FORCES, Quantity.FORWARD_DYNAMICS)
"""The rows of the dynamics comparison, each with its worst state (0: the reference configuration)."""


def coordinate_map(ra, rb, parts_a, parts_b, m, R, p, signs, joints: dict
                   ) -> tuple[tuple[Callable, np.ndarray] | None, str]:
    """``(map, why)``: a function ``q_A (n, nq_A) -> q_B (n, nq_B)`` and the speed map ``T`` ``(nv_B, nv_A)``, or
    None and why the coordinates cannot be mapped. ``joints``: ``{(i_A, i_B): (pairs, only in A, only in B)}`` of the
    matched parts' joints (:func:`relacc.validation.diff.joint_pairs`)."""
    ta, tb = ra.tree, rb.tree
    if m.only_a or m.only_b:
        return None, "parts without a counterpart"
    if ta.nv != tb.nv:
        return None, f"A has {ta.nv} speeds, B {tb.nv}"
    jindex_a = {(body, joint.name): n for n, (body, joint) in enumerate(ta.joints)}
    jindex_b = {(body, joint.name): n for n, (body, joint) in enumerate(tb.joints)}
    qa_adr, qb_adr = ta.qadr(2), tb.qadr(2)
    T = np.zeros((tb.nv, ta.nv))
    steps: list[tuple] = []
    for i, k, _ in m.pairs:
        a, b = parts_a[i], parts_b[k]
        jp, only_a, only_b = joints[(i, k)]
        if only_a or only_b:
            return None, f"joints without a counterpart in {a.name}"
        coincide = np.allclose(a.R, R @ b.R, rtol=0, atol=1e-6) and np.allclose(a.origin, R @ b.origin + p, rtol=0,
                                                                                  atol=1e-6)
        for ja, jb in jp:
            j, jbj = a.joints[ja], b.joints[jb]
            na = jindex_a[(ta.body(a.joint_bodies[ja]), j.name)]
            nb = jindex_b[(tb.body(b.joint_bodies[jb]), jbj.name)]
            if j.type != jbj.type:
                return None, f"joint {j.name} is a {j.type} in A and a {jbj.type} in B"
            da, db = ta.dofadr[na], tb.dofadr[nb]
            qa, qb = qa_adr[na], qb_adr[nb]
            if j.type in ("hinge", "slide"):
                s = signs.get((i, ja), 1.0)
                T[db, da] = s
                steps.append(("scalar", qa, qb, s, j.ref, jbj.ref))
            elif not coincide:
                return None, f"the {j.type} joint {j.name}'s body frames differ between the files"
            elif j.type == "ball":
                T[db:db + 3, da:da + 3] = np.eye(3)
                steps.append(("ball", qa, qb))
            else:
                T[db:db + 3, da:da + 3] = R.T
                T[db + 3:db + 6, da + 3:da + 6] = np.eye(3)
                steps.append(("free", qa, qb))
    from relacc.reading.frames import quaternion_of

    turn = quaternion_of(R.T)

    def q_map(q_a: np.ndarray) -> np.ndarray:
        q_b = np.zeros((q_a.shape[0], tb.nq_in(2)))
        for step in steps:
            if step[0] == "scalar":
                _, qa, qb, s, ref_a, ref_b = step
                q_b[:, qb] = ref_b + s * (q_a[:, qa] - ref_a)
            elif step[0] == "ball":
                q_b[:, step[2]:step[2] + 4] = q_a[:, step[1]:step[1] + 4]
            else:
                qa, qb = step[1], step[2]
                q_b[:, qb:qb + 3] = (q_a[:, qa:qa + 3] - p) @ R
                q_b[:, qb + 3:qb + 7] = np.array([quaternion_multiply(turn, x) for x in q_a[:, qa + 3:qa + 7]])
        return q_b

    return (q_map, T), ""


def compare_dynamics(ra, rb, parts_a, parts_b, m, R, p, signs, joints, rtol, states, seed) -> tuple[list, str]:
    """``(rows, why)``: one row per :data:`QUANTITIES` (``quantity``, ``worst_state``, ``normalized``,
    ``tolerance``, ``beyond``), worst first, or ``([], why not compared)``."""
    from relacc.core.tree.coordinates import random_states, reference_q
    from relacc.dynamics.tree import tree_dynamics
    from relacc.errors import RelaccError

    ta, tb = ra.tree, rb.tree
    if ta.nv == 0:
        return [], "nothing moves"
    mapped, why = coordinate_map(ra, rb, parts_a, parts_b, m, R, p, signs, joints)
    if mapped is None:
        return [], why
    q_map, T = mapped
    drawn = random_states(ta, 2, states, seed, ranges=dict(ra.ranges))
    q_a = np.vstack([reference_q(ta, 2)[None], np.asarray(drawn.q)])
    u_a = np.vstack([np.zeros((1, ta.nv)), np.asarray(drawn.u)])
    q_b = q_map(q_a)
    u_b = u_a @ T.T
    try:
        da = tree_dynamics(ta, 2, q_a, u_a)
        db = tree_dynamics(tb, 2, q_b, u_b)
    except RelaccError as exc:
        return [], f"relacc's dynamics refused a state ({exc})"
    Ma, fa = np.asarray(da.M), np.asarray(da.f)
    Mb = np.einsum("ji,njk,kl->nil", T, np.asarray(db.M), T)
    fb = np.asarray(db.f) @ T
    depth = max(ta.depth) if ta.depth else 0
    base = printed_tolerance(1 + 2 * np.pi * (depth + 1), rtol)
    rows: list[dict] = []
    for name, xa, xb in zip(QUANTITIES, (Ma, fa, fa), (Mb, fb, fb)):
        if name is Quantity.FORWARD_DYNAMICS:
            try:
                xa = np.linalg.solve(Ma, fa[..., None])[..., 0]
                xb = np.linalg.solve(Mb, fb[..., None])[..., 0]
            except np.linalg.LinAlgError:
                continue
            cond = np.linalg.cond(Ma)
        else:
            cond = np.ones(len(q_a))
        n = len(q_a)
        err = np.zeros(n)
        tolerance = np.zeros(n)
        for s in range(n):
            big = max(float(np.abs(xa[s]).max(initial=0.0)), float(np.abs(xb[s]).max(initial=0.0)))
            err[s] = float(np.abs(xa[s] - xb[s]).max(initial=0.0)) / big if big > 0 else 0.0
            tolerance[s] = base * float(cond[s])
        worst = int(np.argmax(err / tolerance))
        rows.append({"quantity": name, "worst_state": worst, "normalized": float(err[worst]),
                     "tolerance": float(tolerance[worst]), "beyond": bool(err[worst] > tolerance[worst]),
                     "decides": bool(tolerance[worst] < 1.0), "states": n})
    rows.sort(key=lambda r: -float(r["normalized"]) / float(r["tolerance"]))
    return rows, ""


def with_inertials_of(ra, rb, parts_a, parts_b, m, R, p, joints):
    """A's reading with each matched part's mass, mass centre and inertia B's (B's world values at the reference
    configuration, taken to A's world by the placement ``x_A = R x_B + p``, put in the part's body that carries the
    rest; its other bodies massless), each matched joint's armature B's, and B's gravity as B writes it (in its own
    world: a placement that turns the robot stays a difference of geometry): A as it would be if the differences of
    those numbers were all there is (module docstring). ``joints`` as in :func:`coordinate_map`."""
    from relacc.core.tree.model import Tree

    t = ra.tree
    bodies = list(t.bodies)
    for i, k, _ in m.pairs:
        a, b = parts_a[i], parts_b[k]
        for name in a.bodies[1:]:
            n = t.body(name)
            bodies[n] = replace(bodies[n], mass=0.0, com=np.zeros(3), inertia=np.zeros((3, 3)), written=0.0)
        first = t.body(a.name)
        inertia = a.R.T @ (R @ b.inertia @ R.T) @ a.R
        bodies[first] = replace(  # B's numbers as written: not held to A's body's physical checks (B's may fail them)
            bodies[first], mass=b.mass, com=a.R.T @ (R @ b.com + p - a.origin), inertia=0.5 * (inertia + inertia.T),
            physical=False)
        armature = {ja: b.joints[jb].armature for ja, jb in joints[(i, k)][0]}
        ja = 0
        for name in dict.fromkeys(a.joint_bodies):  # each body with joints, root first: the part's joints in order
            n = t.body(name)
            held = bodies[n].joints
            bodies[n] = replace(bodies[n], joints=tuple(replace(j, armature=armature.get(ja + x, j.armature))
                                                        for x, j in enumerate(held)))
            ja += len(held)
    tree = Tree(t.name, tuple(bodies), gravity=rb.tree.gravity, points=t.points, source=t.source)
    return replace(ra, tree=tree)


def explain(rows: list, again: list) -> None:
    """Each row of ``rows`` beyond printing given ``"explained"``: ``{"normalized", "tolerance", "beyond"}`` of the
    same quantity in ``again``, the comparison with A's inertial numbers B's (:func:`with_inertials_of`); ``beyond``
    false there means the listed differences of masses, inertias, armatures and gravity explain the row."""
    by = {row["quantity"]: row for row in again}
    for row in rows:
        other = by.get(row["quantity"])
        if row["beyond"] and other is not None:
            row["explained"] = {k: other[k] for k in ("normalized", "tolerance", "beyond")}


def row_words(row: dict) -> str:
    """What a dynamics row adds to its numbers, in words (empty where nothing): that it cannot tell the files apart
    (``decides`` false), or whether the listed masses, inertias, armatures and gravity explain it (:func:`explain`)."""
    if not row.get("decides", True):
        return "more than its entries: this row cannot tell the files apart (an ill-conditioned mass matrix)"
    again = row.get("explained")
    if again is None:
        return ""
    return (f"A given B's masses, inertias, armatures and gravity: {'still ' if again['beyond'] else ''}"
            f"{again['normalized']:.2g}, " + ("so the geometry differs too" if again["beyond"]
                                             else "so those differences explain it"))
