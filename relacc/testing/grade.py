"""Grading a user's own formula: right or wrong, and if wrong, where (``relacc grade``).

Two subjects, one grader:

* the note's G2: ``fn(chain, q, u, udot)`` takes one state of a case (``q (nq,)``, ``u (12,)``, ``udot (12,)``,
  the case's coordinates and speeds) and returns G2's ``position``, ``velocity`` or classical ``acceleration``
  ``(3,)``, or ``V`` / ``Vdot`` ``(3, 12)`` (:func:`check_formula`). References: relacc's corrected formulas and
  every installed engine, each with its own accuracy bound (:func:`relacc.testing.truth.truth`);
* one body of any model: ``fn(tree, q, u, udot)`` (``q (nq,)``, ``u (nv,)``, ``udot (nv,)``: the case's coordinates
  of :mod:`relacc.core.tree.coordinates`; in case 2 a MuJoCo ``qpos``, ``qvel``, ``qacc``) returns the body's
  ``position``, ``velocity``, ``acceleration`` (classical), ``omega`` or ``alpha`` ``(3,)``, or its ``V``, ``Vdot``,
  ``Omega``, ``Omegadot`` ``(3, nv)`` (:func:`grade_body`). References: relacc's tree, and MuJoCo where it has the
  quantity for the case (:func:`relacc.testing.trees.model_truth`).

Both at the mass centre, fixed-frame components; a function taking whole batches (``q (n, nq)``...) and returning
``(n, ...)`` is used as such. The grade covers ordinary and hard states. When the function is wrong it says:

* ``columns``: which blocks of speeds show it, probed against relacc's tree (the chain's is
  :func:`relacc.core.tree.model.chain_tree`, G2 its B2's mass centre): the note's four blocks for G2, the joints
  for a model's body. Matrices: their columns. Vectors: one block of ``u`` at a time (``v`` is linear in ``u``);
  accelerations: one block of ``udot``, then of ``u``, then pairs of blocks of ``u`` (a term with two speeds in it
  shows only when both are there, and both are named);
* ``matches`` (G2 only): which of the note's known slips reproduce the user's output, each equation id's printed
  form taken alone (``variant={id}``).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from relacc.core.cases import U_BLOCKS, as_case, check_int
from relacc.core.conventions import QUANTITIES
from relacc.core.kinematics import g2_kinematics
from relacc.core.note.equations import EQUATIONS
from relacc.core.scales import term_scales
from relacc.core.states import States
from relacc.core.tolerances import normalized_error, rounding_tolerance
from relacc.core.tree import tree_kinematics
from relacc.core.tree.model import chain_tree
from relacc.core.tree.scales import tree_scales
from relacc.errors import InputError
from relacc.limits import GRADE_DOUBLES, require_memory, tree_states_bytes
from relacc.testing.agree import SPEED_NAMES
from relacc.testing.grading import Grade, worst_against
from relacc.testing.trees import PHYSICAL, TREE_QUANTITIES, as_tree, model_states, model_truth
from relacc.testing.truth import states as draw_states
from relacc.testing.truth import truth
from relacc.testing.user import CALL_TIMEOUT, CallError, UserFunction, evaluate_user

if TYPE_CHECKING:
    from relacc.core.chain import TwoBodyChain
    from relacc.core.tree import Tree

CHAIN_CALL, TREE_CALL = "f(chain, q, u, udot)", "f(tree, q, u, udot)"


def check_formula(fn: Callable | UserFunction, *, quantity: str, case: int, n: int = 200, seed: int = 0,
                  chain: TwoBodyChain | None = None, engines: Sequence[str] | None = None,
                  model: str | os.PathLike | Tree | None = None, body: str | None = None,
                  timeout: float = CALL_TIMEOUT) -> Grade:
    """Grade ``fn(chain, q, u, udot)`` for one quantity of G2 and a case (module docstring).

    With ``model`` (an MJCF, URDF or chain TOML path, or a relacc.Tree) and ``body`` (a body's name), grade
    ``fn(tree, q, u, udot)`` for that body instead: :func:`grade_body`.

    Args:
        quantity: ``position``, ``velocity``, ``acceleration``, ``V`` or ``Vdot``.
        n: ordinary states, and as many hard ones (the hard-case catalogue's).
        chain: a :class:`relacc.TwoBodyChain` (default the shipped chain).
        engines: engine names to judge against (default: every installed one), besides relacc.
        timeout: seconds each child running ``fn`` on a batch of states may take.

    Raises:
        CallError: ``fn`` cannot be called as a formula (it raised, or returned the wrong shape).
        InputError: an unknown quantity or case, a bad n or seed.
    """
    if model is not None or body is not None:
        if model is None or body is None:
            raise InputError("grading a model's body needs both model= and body=")
        if chain is not None:
            raise InputError("give chain= (the note's G2) or model= and body= (a model's body), not both")
        return grade_body(fn, model=model, body=body, quantity=quantity, case=case, n=n, seed=seed, engines=engines,
                          timeout=timeout)
    if quantity not in QUANTITIES:
        raise InputError(f"unknown quantity {quantity!r}: accepted are {', '.join(QUANTITIES)}")
    c = int(as_case(case))
    n, seed = check_int("n", n, minimum=1), check_int("seed", seed, minimum=0)
    if chain is None:
        from relacc.fixtures import load

        chain = load().chain
    if not (callable(fn) or isinstance(fn, UserFunction)):
        raise CallError(f"{fn!r} is not callable; give a function fn(chain, q, u, udot)")
    from relacc.engines import chain_engines

    s = draw_states(c, n, seed).and_then(draw_states(c, n, seed, hard=True), seed)
    # the truth first, and apart from anything the user's code touches (it runs in a child process, on copies)
    truths = [truth(s, name, chain=chain).of(quantity)
              for name in ("relacc",) + tuple(chain_engines() if engines is None else engines)]
    blocks = [(name, list(range(sl.start, sl.stop))) for name, sl in zip(SPEED_NAMES[c], U_BLOCKS.values())]
    refs = [(t.source, t.values, t.scale, t.bound) for t in truths]
    references_agree(refs, f"G2's {quantity} in case {c}", "relacc check says which engine reads the chain apart")
    return _grade(fn, chain, chain_tree(chain), 1, quantity, s, seed, refs, blocks, CHAIN_CALL, timeout,
                  matches=lambda mine, tol: _matches(mine, chain, c, quantity, s, tol))


def grade_body(fn: Callable | UserFunction, *, model: str | os.PathLike | Tree, body: str, quantity: str, case: int,
               n: int = 200, seed: int = 0, engines: Sequence[str] | None = None,
               timeout: float = CALL_TIMEOUT) -> Grade:
    """Grade ``fn(tree, q, u, udot)`` for one body's quantity in one case (module docstring), judged against relacc
    and ``engines`` (default the plugin's truth engine, :data:`relacc.engines.TRUTH_ENGINE`).

    Returns:
        :class:`relacc.testing.grading.Grade` (``matches`` is empty: the note's printed slips are the chain's).

    Raises:
        CallError: ``fn`` cannot be called as a formula. InputError: an unknown body, quantity or case.
    """
    if quantity not in TREE_QUANTITIES:
        raise InputError(f"unknown quantity {quantity!r} for a model's body: accepted are {', '.join(TREE_QUANTITIES)}")
    notes: tuple = ()
    if isinstance(model, (str, os.PathLike)) and Path(model).suffix.lower() in (".xml", ".urdf", ".xacro"):
        from relacc.reading import read

        reading = read(model)
        tree, notes = reading.tree, tuple(reading.unevaluated)
    else:
        tree = as_tree(model)
    b = tree.body(body)
    c = int(as_case(case))
    n, seed = check_int("n", n, minimum=1), check_int("seed", seed, minimum=0)
    if not (callable(fn) or isinstance(fn, UserFunction)):
        raise CallError(f"{fn!r} is not callable; give a function fn(tree, q, u, udot)")
    require_memory(2.0 * n * (8.0 * GRADE_DOUBLES * tree.nb * tree.nv) + 2 * tree_states_bytes(tree, n, c),
                   f"grading {tree.name!r} ({tree.nb} bodies, {tree.nv} speeds) on {n} ordinary and {n} hard states",
                   "ask for fewer states (--states)")
    s = model_states(tree, c, n, seed).and_then(model_states(tree, c, n, seed, hard=True), seed)
    # the truth first, and apart from anything the user's code touches (it runs in a child process, on copies)
    truths = []
    from relacc.engines import TRUTH_ENGINE

    for engine in ("relacc",) + tuple((TRUTH_ENGINE,) if engines is None else engines):
        t = model_truth(s, engine, (quantity,))
        if quantity in t:  # an evaluator may lack the quantity in this case (MuJoCo's V of case 1, say)
            e = t[quantity]
            truths.append((engine, e.values[:, b], e.scale[:, b], e.bound[:, b]))
    references_agree(truths, f"the {quantity} of body {tree.body_names[b]!r} in case {c}",
                     f"relacc compare {model if isinstance(model, (str, os.PathLike)) else 'MODEL'} says where")
    blocks = [(j.name, list(range(d, d + j.nv))) for (_, j), d in zip(tree.joints, tree.dofadr)]
    return _grade(fn, tree, tree, b, quantity, s, seed, truths, blocks, TREE_CALL, timeout, body=tree.body_names[b],
                  not_evaluated=notes)


def references_agree(truths: list, what: str, where: str) -> None:
    """Refuse to grade when the references ``[(source, values, scale, bound)]`` disagree among themselves (each
    against the first, relacc's, within ``tol + bound_a + bound_b``): a student's answer cannot be right against both.
    Issue 50: relacc's reader applied a DTD's entities MuJoCo does not, and grade blamed a student whose answer was
    relacc's.

    Raises:
        ModelError: naming the references, the state, how far apart, and where to look.
    """
    from relacc.errors import ModelError

    tol = rounding_tolerance()
    first, values0, scale0, bound0 = truths[0]
    for source, values, scale, bound in truths[1:]:
        err = np.atleast_1d(normalized_error(values, values0, np.maximum(scale, scale0)))
        ratio = err / (tol + bound + bound0)
        i = int(np.argmax(ratio))
        if not ratio[i] <= 1.0:
            raise ModelError(f"grade's references disagree on {what}: {first} and {source} at state {i}, "
                             f"{ratio[i]:.3g} times their tolerance apart, so no answer can be graded right against "
                             f"both; nothing graded ({where})")


def _grade(fn, subject, tree, b: int, quantity: str, s: States, seed: int, truths: list, blocks: list, called: str,
           timeout: float, matches: Callable | None = None, **extra: Any) -> Grade:
    """The user's worst value against every reference ``(source, values, scale, bound)`` and, when wrong, where:
    ``blocks`` ``[(name, speed indices)]`` probed against relacc's tree at body ``b``'s mass centre, and ``matches``
    ``(mine, tol) -> equation ids`` (G2's printed slips)."""
    c = int(s.case)
    shape = (3,) if quantity in PHYSICAL else (3, tree.nv)
    forms = evaluate_user(fn, subject, c, s.q, s.u, s.udot, shape, called=called, timeout=timeout)
    tol = rounding_tolerance()
    worst = worst_against(truths, forms, tol)
    columns = () if worst.ok else _columns(fn, subject, tree, b, quantity, s, tol, shape, blocks, called, timeout)
    slips = () if worst.ok or matches is None else matches(forms.one, tol)
    return Grade(worst.ok, quantity, c, worst.error, worst.source, worst.state, columns, slips, seed, len(s),
                 tuple(t[0] for t in truths), called=worst.called, **extra)


def _columns(fn, subject, tree, b, quantity, s, tol, shape, blocks, called, timeout) -> tuple:
    """The named blocks of speeds whose columns (or probes) show the disagreement with relacc's tree at body ``b``'s
    mass centre (module docstring)."""
    c = int(s.case)

    def disagrees(u, ud, cols=None):
        ref = getattr(tree_kinematics(tree, c, s.q, u, ud), quantity)[:, b]
        scale = tree_scales(tree, c, s.q, u, ud).of(quantity)[:, b]
        part = Ellipsis if cols is None else (Ellipsis, cols)
        return any(bool(np.any(normalized_error(mine[part], ref[part], scale) > tol))
                   for _, mine in evaluate_user(fn, subject, c, s.q, u, ud, shape, called=called,
                                                timeout=timeout).each())

    def only(x, *groups):
        out = np.zeros_like(x)
        for cols in groups:
            out[:, cols] = x[:, cols]
        return out

    if quantity == "position":
        return ()
    if quantity in ("V", "Vdot", "Omega", "Omegadot"):
        return tuple(name for name, cols in blocks if disagrees(s.u, s.udot, cols))
    if quantity in ("velocity", "omega"):
        return tuple(name for name, cols in blocks if disagrees(only(s.u, cols), s.udot))
    zu, zd = np.zeros_like(s.u), np.zeros_like(s.udot)
    bad = [name for name, cols in blocks if disagrees(zu, only(s.udot, cols)) or disagrees(only(s.u, cols), zd)]
    if not bad:  # a term with two blocks' speeds in it shows only when both are there: name both
        for i, (a, ca) in enumerate(blocks):
            for b_, cb in blocks[i + 1:]:
                if disagrees(only(s.u, ca, cb), zd):
                    bad += [a, b_]
    return tuple(dict.fromkeys(bad))


def _matches(mine, chain, case, quantity, s: States, tol) -> tuple:
    """The equation ids of the case whose printed form alone gives the user's numbers (and differs from the truth)."""
    corrected = getattr(g2_kinematics(chain, case, s.q, s.u, s.udot), quantity)
    scale = term_scales(chain, case, s.q, s.u, s.udot).of(quantity)
    out = []
    for eq in EQUATIONS:
        if eq.case != case or eq.kind == "missing":
            continue
        printed = getattr(g2_kinematics(chain, case, s.q, s.u, s.udot, variant={eq.id}), quantity)
        if np.all(normalized_error(printed, corrected, scale) <= tol):
            continue  # this id's slip does not show in this quantity
        if np.all(normalized_error(mine, printed, scale) <= tol):
            out.append(eq.id)
    return tuple(out)
