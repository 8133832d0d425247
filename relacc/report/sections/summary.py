"""The verdict at the top: does everything agree, and what does the note get wrong."""

from __future__ import annotations

from collections import Counter

from relacc.core.tolerances import EPS
from relacc.engines import label

ID = "summary"
TITLE = "Verdict"


def build(ctx) -> dict:
    check, items = ctx.check, ctx.errata
    worst = max(check.comparisons, key=lambda c: c.max_error)
    statuses = Counter(e.status for e in items)
    failures = ctx.failures()
    agree = not failures
    names = [label(n) for n in ctx.harness.engines]
    engines = ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else names[0]
    return {
        "engines": engines,
        "referee": [v.sentence() for v in check.referee],
        "agree": agree,
        "headline": (
            f"The corrected formulas agree with {engines} in all three cases."
            if agree
            else f"{len(failures)} disagreement(s) between the corrected formulas and the engines."
        ),
        "worst_eps": worst.max_error / EPS,
        "worst_where": f"case {worst.case}, {worst.engine}/{worst.route}, {worst.quantity}",
        "tolerance_eps": worst.tolerance / EPS,
        "n_comparisons": len(check.comparisons),
        "statuses": {s: statuses.get(s, 0) for s in ("ok", "wrong", "ambiguous", "missing")},
        "not_ok": [e.id for e in items if e.status != "ok"],
        "failures": failures,
        "n_states": check.n_states,
        "seed": check.seed,
        "versions": check.versions,
        "created": ctx.created.strftime("%Y-%m-%d %H:%M UTC"),
        "machine": ctx.machine,
        "quick": ctx.quick,
        "model": str(ctx.harness.fixture.source.name),
    }
