"""Grading a user's formula for one body of any model (``relacc grade --model FILE --body NAME``).

``fn(tree, q, u, udot)`` takes one state of the case (``q (nq,)``, ``u (nv,)``, ``udot (nv,)``: the case's
coordinates of :mod:`relacc.core.tree.coordinates`; in case 2 a MuJoCo ``qpos``, ``qvel``, ``qacc``) and
returns the body's ``position``, ``velocity``, ``acceleration`` (classical), ``omega`` or ``alpha`` ``(3,)``, or
its ``V``, ``Vdot``, ``Omega``, ``Omegadot`` ``(3, nv)``: at the body's mass centre, fixed-frame components. A
function taking whole batches is used as such. References: relacc's tree, and MuJoCo where it has the quantity
for the case (:func:`relacc.testing.trees.model_truth`). When the function is wrong, ``columns`` names the joints
whose speeds show it (the columns of a matrix; one joint's speeds or rates at a time for a vector).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from relacc.core.cases import as_case, check_int
from relacc.core.tolerances import normalized_error, rounding_tolerance
from relacc.core.tree import tree_kinematics
from relacc.core.tree.scales import tree_scales
from relacc.errors import InputError
from relacc.limits import GRADE_DOUBLES, require_memory, tree_states_bytes
from relacc.testing.grading import Grade, worst_against
from relacc.testing.trees import PHYSICAL, TREE_QUANTITIES, as_tree, model_states, model_truth
from relacc.testing.user import CallError, evaluate_user


def _joint_columns(tree):
    """``[(joint name, its speed indices)]`` in order."""
    return [(j.name, list(range(d, d + j.nv))) for (_, j), d in zip(tree.joints, tree.dofadr)]


def grade_body(fn, *, model, body, quantity: str, case, n: int = 200, seed: int = 0, engines=None):
    """Grade ``fn(tree, q, u, udot)`` for one body's quantity in one case (module docstring).

    Returns:
        :class:`relacc.testing.grading.Grade` (``matches`` is empty: the note's printed slips are the chain's).

    Raises:
        CallError: ``fn`` cannot be called as a formula. InputError: an unknown body, quantity or case.
    """
    if quantity not in TREE_QUANTITIES:
        raise InputError(f"unknown quantity {quantity!r} for a model's body: accepted are {', '.join(TREE_QUANTITIES)}")
    notes: tuple = ()
    if isinstance(model, (str, os.PathLike)) and Path(model).suffix.lower() in (".xml", ".urdf"):
        from relacc.reading import read

        reading = read(model)
        tree, notes = reading.tree, tuple(reading.unevaluated)
    else:
        tree = as_tree(model)
    b = tree.body(body)
    c = int(as_case(case))
    n, seed = check_int("n", n, minimum=1), check_int("seed", seed, minimum=0)
    if not callable(fn):
        raise CallError(f"{fn!r} is not callable; give a function fn(tree, q, u, udot)")
    require_memory(2.0 * n * (8.0 * GRADE_DOUBLES * tree.nb * tree.nv) + 2 * tree_states_bytes(tree, n, c),
                   f"grading {tree.name!r} ({tree.nb} bodies, {tree.nv} speeds) on {n} ordinary and {n} hard states",
                   "ask for fewer states (--states)")
    ordinary, hard = model_states(tree, c, n, seed), model_states(tree, c, n, seed, hard=True)
    s = ordinary.and_then(hard, seed)
    shape = (3,) if quantity in PHYSICAL else (3, tree.nv)
    # the truth first, and apart from anything the user's code touches (it runs in a child process, on copies)
    truths = []
    for engine in ("relacc",) + tuple(("mujoco",) if engines is None else engines):
        t = model_truth(s, engine, (quantity,))
        if quantity in t:  # an evaluator may lack the quantity in this case (MuJoCo's V of case 1, say)
            e = t[quantity]
            truths.append((engine, e.values[:, b], e.scale[:, b], e.bound[:, b]))
    forms = evaluate_user(fn, tree, c, s.q, s.u, s.udot, shape, called="f(tree, q, u, udot)")
    tol = rounding_tolerance()
    worst = worst_against(truths, forms, tol)
    ok = worst.ok
    columns = () if ok else _columns(fn, tree, c, b, quantity, s, tol, shape)
    return Grade(ok, quantity, c, worst.error, worst.source, worst.state, columns, (), seed, len(s),
                 tuple(t[0] for t in truths), body=tree.body_names[b], called=worst.called, not_evaluated=notes)


def _columns(fn, tree, c, b, quantity, s, tol, shape) -> tuple:
    """The joints whose speeds show the disagreement with relacc's tree."""
    def disagrees(u, ud, cols=None):
        ref = getattr(tree_kinematics(tree, c, s.q, u, ud), quantity)[:, b]
        scale = tree_scales(tree, c, s.q, u, ud).of(quantity)[:, b]
        part = Ellipsis if cols is None else (Ellipsis, cols)
        return any(bool(np.any(normalized_error(mine[part], ref[part], scale) > tol))
                   for _, mine in evaluate_user(fn, tree, c, s.q, u, ud, shape, called="f(tree, q, u, udot)").each())

    def only(x, *groups):
        out = np.zeros_like(x)
        for cols in groups:
            out[:, cols] = x[:, cols]
        return out

    joints = _joint_columns(tree)
    if quantity == "position":
        return ()
    if quantity in ("V", "Vdot", "Omega", "Omegadot"):
        return tuple(name for name, cols in joints if disagrees(s.u, s.udot, cols))
    if quantity in ("velocity", "omega"):
        return tuple(name for name, cols in joints if disagrees(only(s.u, cols), s.udot))
    zu, zd = np.zeros_like(s.u), np.zeros_like(s.udot)
    bad = [name for name, cols in joints if disagrees(zu, only(s.udot, cols)) or disagrees(only(s.u, cols), zd)]
    if not bad:  # a term with two joints' speeds in it shows only when both are there: name both
        for i, (a, ca) in enumerate(joints):
            for b_, cb in joints[i + 1:]:
                if disagrees(only(s.u, ca, cb), zd):
                    bad += [a, b_]
    return tuple(dict.fromkeys(bad))
