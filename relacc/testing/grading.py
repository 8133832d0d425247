"""A grade: the verdict on a user's formula, and the worst of its values against the references (for the chain's G2
and for any body of a tree alike)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from relacc.core.tolerances import normalized_error


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


@dataclass(frozen=True)
class Worst:
    """A user's worst value over every form of the call against every reference.

    Attributes:
        ratio: its normalized error over ``tol + bound`` (at most 1: right; infinite for a non-finite value).
        source: the reference it is worst against. state: the state's index. error: its normalized error.
        called: how the function was called for it (``one state at a time`` or ``a batch``).
    """

    ratio: float
    source: str
    state: int
    error: float
    called: str

    @property
    def ok(self) -> bool:
        return self.ratio <= 1.0


def worst_against(truths, forms, tol) -> Worst:
    """The user's :class:`Worst` value over every form of the call (:class:`relacc.testing.user.Forms`) against every
    reference ``(source, values, scale, bound)``: the ratio of the normalized error to ``tol + bound`` (at most 1:
    right). A non-finite value is infinitely wrong."""
    worst = Worst(-1.0, "", 0, 0.0, "")
    for how, mine in forms.each():
        finite = np.all(np.isfinite(mine.reshape(len(mine), -1)), axis=1)
        for source, values, scale, bound in truths:
            err = np.where(finite, np.atleast_1d(normalized_error(mine, values, scale)), np.inf)
            ratio = err / (tol + bound)
            i = int(np.argmax(ratio))
            if ratio[i] > worst.ratio:
                worst = Worst(float(ratio[i]), source, i, float(err[i]), how)
    return worst


__all__ = ["Grade", "Worst", "worst_against"]
