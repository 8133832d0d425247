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

from dataclasses import dataclass, field

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
from relacc.testing.truth import states as draw_states
from relacc.testing.truth import truth
from relacc.testing.user import CallError, evaluate_user


@dataclass(frozen=True)
class Grade:
    """The verdict on a user's formula.

    Attributes:
        ok: it agrees with every reference on every state, within the error model.
        worst_error: its largest normalized error (dimensionless), against ``worst_source``.
        worst_state: that state's index (ordinary states first, then hard ones).
        columns: the generalized-speed blocks that disagree, as the note names them.
        matches: the note's equation ids whose printed form alone reproduces the user's output.
        seed: the seed of the states.
    """

    ok: bool
    quantity: str
    case: int
    worst_error: float
    worst_source: str
    worst_state: int
    columns: tuple
    matches: tuple
    seed: int
    n_states: int
    sources: tuple = field(default=())
    body: str | None = None
    """A model's body (then ``columns`` names joints, and there are no printed slips to match), or None: G2."""
    called: str = "one state at a time"
    """How the function was called for its worst value: ``one state at a time`` or ``a batch``."""
    not_evaluated: tuple = ()
    """One line per kind of element of a model file the truth leaves out (``Reading.unevaluated``)."""

    def as_json(self) -> dict:
        """``relacc grade --json``."""
        worst = self.worst_error if np.isfinite(self.worst_error) else None  # strict JSON has no Infinity or NaN
        return {"ok": self.ok, "worst_error": worst, "columns": list(self.columns),
                "matches": list(self.matches), "seed": self.seed, "quantity": self.quantity, "case": self.case,
                "worst_source": self.worst_source, "worst_state": self.worst_state, "n_states": self.n_states,
                "sources": list(self.sources), "body": self.body, "called": self.called,
                "not_evaluated": list(self.not_evaluated)}

    def text(self) -> str:
        """The human-readable verdict."""
        what = self.quantity if self.body is None else f"{self.quantity} of body {self.body}"
        head = (f"{what} for case {self.case}: {'right' if self.ok else 'WRONG'} on {self.n_states} states "
                f"(seed {self.seed}; ordinary and hard), against {', '.join(self.sources)}; worst normalized error "
                f"{self.worst_error:.3g} ({self.worst_source}, state {self.worst_state}, called {self.called})")
        head += "".join(f"\nnot evaluated: {line}" for line in self.not_evaluated)
        if self.ok:
            return head
        cols = ", ".join(self.columns) if self.columns else "none found by the probes"
        if self.body is not None:
            return f"{head}\njoints whose speeds show it: {cols}"
        slips = ", ".join(self.matches) if self.matches else "none of the note's known slips"
        return f"{head}\ncolumns that disagree: {cols}\nreproduced by: {slips}"


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


def check_formula(fn, *, quantity: str, case, n: int = 200, seed: int = 0, chain=None, engines=None, model=None,
                  body=None) -> Grade:
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
    ok = worst[0] <= 1.0
    columns = () if ok else _column_diagnosis(fn, chain, c, quantity, s, tol, shape)
    matches = () if ok else _matches(forms.one, chain, c, quantity, s, tol)
    return Grade(ok, quantity, c, worst[3], worst[1], worst[2], columns, matches, seed, len(s),
                 tuple(t.source for t in truths), called=worst[4])


def worst_against(truths, forms, tol) -> tuple:
    """``(ratio, source, state, normalized error, how called)`` of the user's worst value over every form of the call
    (:class:`relacc.testing.user.Forms`) against every reference ``(source, values, scale, bound)``: the ratio of the
    normalized error to ``tol + bound`` (at most 1: right). A non-finite value is infinitely wrong."""
    worst = (-1.0, "", 0, 0.0, "")
    for how, mine in forms.each():
        finite = np.all(np.isfinite(mine.reshape(len(mine), -1)), axis=1)
        for source, values, scale, bound in truths:
            err = np.where(finite, np.atleast_1d(normalized_error(mine, values, scale)), np.inf)
            ratio = err / (tol + bound)
            i = int(np.argmax(ratio))
            if ratio[i] > worst[0]:
                worst = (float(ratio[i]), source, i, float(err[i]), how)
    return worst
