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

    def as_dict(self) -> dict:
        """Exactly the keys of ``relacc errata --json``."""
        return {
            "id": self.id,
            "status": self.status,
            "printed_error": self.printed_error,
            "corrected_error": self.corrected_error,
            "explanation": self.equation.explanation,
        }


def _max_error(harness: Harness, eq: Equation, variant) -> tuple[float, float]:
    worst, tol = 0.0, 0.0
    for engine in harness.engines:
        for route in routes_for(eq.case):
            comp = harness.compare(eq.case, engine, route, eq.quantity, variant)
            worst, tol = max(worst, comp.max_error), comp.tolerance
    return worst, tol


def erratum(harness: Harness, eq: Equation) -> Erratum:
    """Evaluate one equation id against the harness's engines."""
    corrected, tol = _max_error(harness, eq, "corrected")
    if eq.kind == "missing":
        return Erratum(eq, "missing", None, corrected, tol)
    printed, _ = _max_error(harness, eq, {eq.id})
    if printed <= tol:
        status = "ok"
    else:
        status = "ambiguous" if eq.kind == "ambiguous" else "wrong"
    return Erratum(eq, status, printed, corrected, tol)


def errata(harness: Harness, equations=EQUATIONS) -> list[Erratum]:
    """Every equation id's verdict, in the note's order."""
    return [erratum(harness, eq) for eq in equations]
