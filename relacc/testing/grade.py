"""Grading a user's own formula: right or wrong, and if wrong, where (``relacc grade``).

``fn(chain, q, u, udot)`` takes one state of a case (``q (nq,)``, ``u (12,)``,
``udot (12,)``, the case's coordinates and speeds) and returns one quantity
in relacc's conventions: G2's ``position``, ``velocity`` or classical
``acceleration`` ``(3,)``, or ``V`` / ``Vdot`` ``(3, 12)``, fixed-frame
components. A function that takes whole batches (``q (n, nq)``...) and
returns ``(n, ...)`` is used as such.

The grade covers ordinary and hard states (the hard-case catalogue), against
every installed engine and relacc's corrected formulas, each with its own
accuracy bound. When the function is wrong it says:

* ``columns``: which generalized-speed blocks disagree (V and Vdot: their
  columns; velocity: probing one block of ``u`` at a time; acceleration:
  one block of ``udot``, then one block of ``u``, at a time);
* ``matches``: which of the note's known slips reproduce the user's output,
  each equation id's printed form taken alone (``variant={id}``).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from relacc.core.cases import U_BLOCKS, as_case, check_int
from relacc.core.conventions import QUANTITIES
from relacc.core.kinematics import g2_kinematics
from relacc.core.note.equations import EQUATIONS
from relacc.core.scales import term_scales
from relacc.core.states import States
from relacc.core.tolerances import normalized_error, rounding_tolerance
from relacc.errors import InputError
from relacc.testing.agree import SPEED_NAMES
from relacc.testing.grading import Grade, worst_against
from relacc.testing.truth import states as draw_states
from relacc.testing.truth import truth
from relacc.testing.user import CallError, evaluate_user

if TYPE_CHECKING:
    from relacc.core.chain import TwoBodyChain
    from relacc.core.tree import Tree


def _column_diagnosis(fn, chain, case, quantity, s: States, tol, shape) -> tuple:
    """The generalized-speed blocks whose columns (or probes) disagree with relacc's corrected formulas.

    V and Vdot: their own columns. Velocity: ``u`` restricted to one block at a time (``v`` is linear
    in ``u``). Acceleration: ``udot`` restricted to one block (V's columns), then ``u`` restricted to one
    block, and when no single block shows it, to pairs of blocks: a term with two speeds in it (``Vdot``
    depends on ``u``) shows only when both are there, and both are named.
    """
    names = SPEED_NAMES[case]
    blocks = list(U_BLOCKS.values())
    if quantity == "position":
        return ()

    def disagrees(u, ud, part=Ellipsis):
        ref = getattr(g2_kinematics(chain, case, s.q, u, ud), quantity)
        scale = term_scales(chain, case, s.q, u, ud).of(quantity)
        return any(bool(np.any(normalized_error(mine[part], ref[part], scale) > tol))
                   for _, mine in evaluate_user(fn, chain, case, s.q, u, ud, shape).each())

    def only(x, *sls):
        out = np.zeros_like(x)
        for sl in sls:
            out[:, sl] = x[:, sl]
        return out

    if quantity in ("V", "Vdot"):
        return tuple(n for n, sl in zip(names, blocks) if disagrees(s.u, s.udot, (Ellipsis, sl)))
    if quantity == "velocity":
        return tuple(n for n, sl in zip(names, blocks) if disagrees(only(s.u, sl), s.udot))
    zero_u, zero_ud = np.zeros_like(s.u), np.zeros_like(s.udot)
    bad = [n for n, sl in zip(names, blocks)
           if disagrees(zero_u, only(s.udot, sl)) or disagrees(only(s.u, sl), zero_ud)]
    if not bad:
        for i in range(4):
            for j in range(i + 1, 4):
                if disagrees(only(s.u, blocks[i], blocks[j]), zero_ud):
                    bad += [names[i], names[j]]
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


def check_formula(fn: Callable, *, quantity: str, case: int, n: int = 200, seed: int = 0,
                  chain: TwoBodyChain | None = None, engines: Sequence[str] | None = None,
                  model: str | os.PathLike | Tree | None = None, body: str | None = None) -> Grade:
    """Grade ``fn(chain, q, u, udot)`` for one quantity and case (module docstring).

    With ``model`` (an MJCF, URDF or chain TOML path, or a relacc.Tree) and ``body`` (a body's name), grade
    ``fn(tree, q, u, udot)`` for that body instead: :func:`relacc.testing.grade_tree.grade_body`.

    Args:
        quantity: ``position``, ``velocity``, ``acceleration``, ``V`` or ``Vdot``.
        n: ordinary states, and as many hard ones.
        chain: a :class:`relacc.TwoBodyChain` (default the shipped chain).
        engines: engine names to judge against (default: every installed one), besides relacc.

    Raises:
        CallError: ``fn`` cannot be called as a formula (it raised, or returned the wrong shape).
        InputError: an unknown quantity or case, a bad n or seed.
    """
    if model is not None or body is not None:
        if model is None or body is None:
            raise InputError("grading a model's body needs both model= and body=")
        if chain is not None:
            raise InputError("give chain= (the note's G2) or model= and body= (a model's body), not both")
        from relacc.testing.grade_tree import grade_body

        return grade_body(fn, model=model, body=body, quantity=quantity, case=case, n=n, seed=seed, engines=engines)
    if quantity not in QUANTITIES:
        raise InputError(f"unknown quantity {quantity!r}: accepted are {', '.join(QUANTITIES)}")
    c = int(as_case(case))
    n, seed = check_int("n", n, minimum=1), check_int("seed", seed, minimum=0)
    if chain is None:
        from relacc.fixtures import load

        chain = load().chain
    if not callable(fn):
        raise CallError(f"{fn!r} is not callable; give a function fn(chain, q, u, udot)")
    from relacc.engines import available

    ordinary, hard = draw_states(c, n, seed), draw_states(c, n, seed, hard=True)
    s = ordinary.and_then(hard, seed)
    shape = (3,) if quantity in ("position", "velocity", "acceleration") else (3, 12)
    # the truth first, and apart from anything the user's code touches (it runs in a child process, on copies)
    truths = [truth(s, name, chain=chain).of(quantity)
              for name in ("relacc",) + tuple(available() if engines is None else engines)]
    forms = evaluate_user(fn, chain, c, s.q, s.u, s.udot, shape)
    tol = rounding_tolerance()
    worst = worst_against([(t.source, t.values, t.scale, t.bound) for t in truths], forms, tol)
    ok = worst.ok
    columns = () if ok else _column_diagnosis(fn, chain, c, quantity, s, tol, shape)
    matches = () if ok else _matches(forms.one, chain, c, quantity, s, tol)
    return Grade(ok, quantity, c, worst.error, worst.source, worst.state, columns, matches, seed, len(s),
                 tuple(t.source for t in truths), called=worst.called)
