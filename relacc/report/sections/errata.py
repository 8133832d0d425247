"""The errata table: each equation id's status, errors and formulas."""

from __future__ import annotations

from relacc.report import svg

ID = "errata"
TITLE = "Where the note is wrong"
READS = ("errata", "check")
"""What ``build`` reads of the context: the report draws this section as soon as they are known."""


def build(ctx) -> dict:
    rows = []
    for e in ctx.errata:
        eq = e.equation
        rows.append(
            {
                "id": e.id,
                "case": eq.case,
                "title": eq.title,
                "quantity": eq.quantity,
                "status": e.status,
                "printed_error": e.printed_error,
                "corrected_error": e.corrected_error,
                "explanation": eq.explanation,
                "printed_tex": eq.printed,
                "corrected_tex": eq.corrected,
                "printed_svg": svg.formula_lines(eq.printed) if eq.printed else [],
                "corrected_svg": svg.formula_lines(eq.corrected) if eq.corrected else [],
            }
        )
    return {"rows": rows, "tolerance": ctx.errata[0].tolerance if ctx.errata else None,
            "n_states": ctx.check.n_states}
