"""What every number means: point, frame of components, classical or spatial; engine maps."""

from __future__ import annotations

from relacc.core.conventions import CASE_NAMES, COORDINATES, MEANINGS, QUANTITIES, SPEEDS
from relacc.core.tolerances import EPS, QUATERNION_NORM_TOLERANCE, ROUNDING_FACTOR
from relacc.engines import TRAITS

ID = "conventions"
TITLE = "Conventions"


def build(ctx) -> dict:
    return {
        "quantities": [
            dict(zip(("quantity", "point", "what", "components", "kind", "units"), (q, *MEANINGS[q])))
            for q in QUANTITIES
        ],
        "cases": [
            {"case": c, "name": CASE_NAMES[c], "q": COORDINATES[c], "u": SPEEDS[c]} for c in (1, 2, 3)
        ],
        "engines": [
            {"engine": engine, "route": route, "mapping": text}
            for engine, traits in TRAITS.items() if engine in ctx.harness.engines
            for route, text in traits.chain_routes.items()
        ],
        "rounding_factor": ROUNDING_FACTOR,
        "tolerance": ROUNDING_FACTOR * EPS,
        "quaternion_tolerance": QUATERNION_NORM_TOLERANCE,
    }
