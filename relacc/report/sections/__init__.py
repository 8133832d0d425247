"""Report sections, in page order. Each module has ``ID``, ``TITLE`` and ``build(ctx) -> dict``."""

from relacc.report.sections import (
    agreement,
    conventions,
    errata,
    hardcases,
    simulation,
    summary,
    system,
    throughput,
    tradeoff,
)

SECTIONS = (summary, system, conventions, agreement, errata, hardcases, simulation, tradeoff, throughput)
