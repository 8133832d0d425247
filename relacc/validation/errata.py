"""Where the note is wrong, and by how much: the errata behind ``relacc errata``.

For each equation id, the output it is measured through is computed twice
with the core -- once with only that id in its printed form, once with every
formula corrected -- and compared with every engine and route of its case.
The status follows from the numbers and the registry's ``kind``:

* ``ok``: the printed form agrees with the engines;
* ``wrong``: the printed form disagrees and the corrected one agrees;
* ``ambiguous``: the literal reading disagrees, the other reading (the
  corrected form) agrees;
* ``missing``: nothing printed; the derived form agrees.
"""

from __future__ import annotations

from dataclasses import dataclass

from relacc.core.note.equations import EQUATIONS, Equation
from relacc.core.tolerances import rounding_tolerance
from relacc.validation.check import Harness
from relacc.validation.compare import routes_for

STATUSES = ("ok", "wrong", "missing", "ambiguous")


@dataclass(frozen=True)
class Erratum:
    """The verdict on one equation id (see module docstring).

    Attributes:
        printed_error, corrected_error: max normalized error against all
            engines and routes (None where not applicable).
        agrees: whether the corrected (or, for ``ok``, printed) form agrees.
    """

    equation: Equation
    status: str
    printed_error: float | None
    corrected_error: float
    tolerance: float

    @property
    def id(self) -> str:
        return self.equation.id

    @property
    def agrees(self) -> bool:
        return self.corrected_error <= self.tolerance

    def as_json(self) -> dict:
        """Exactly the keys of ``relacc errata --json``."""
        return {
            "id": self.id,
            "status": self.status,
            "printed_error": self.printed_error,
            "corrected_error": self.corrected_error,
            "explanation": self.equation.explanation,
        }


def _max_errors(harness: Harness, equations) -> dict:
    """``{id: [printed, corrected]}``: each id's largest error over every chunk, engine and route."""
    worst = {eq.id: [0.0, 0.0] for eq in equations}
    for case in sorted({eq.case for eq in equations}):
        for k, _, _ in harness.chunks():
            for eq in (e for e in equations if e.case == case):
                for engine in harness.engines:
                    for route in routes_for(case):
                        for slot, variant in ((1, "corrected"), (0, {eq.id})):
                            if slot == 0 and eq.kind == "missing":
                                continue
                            comp = harness.comparison(case, engine, route, eq.quantity, variant, k=k)
                            worst[eq.id][slot] = max(worst[eq.id][slot], comp.max_error)
    return worst


def erratum(eq: Equation, printed: float, corrected: float) -> Erratum:
    """The verdict on one equation id from its largest printed and corrected errors."""
    tol = rounding_tolerance()
    if eq.kind == "missing":
        return Erratum(eq, "missing", None, corrected, tol)
    status = "ok" if printed <= tol else ("ambiguous" if eq.kind == "ambiguous" else "wrong")
    return Erratum(eq, status, printed, corrected, tol)


def errata(harness: Harness, equations=EQUATIONS) -> list[Erratum]:
    """Every equation id's verdict, in the note's order, over all of the harness's states."""
    worst = _max_errors(harness, equations)
    return [erratum(eq, *worst[eq.id]) for eq in equations]
