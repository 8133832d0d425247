"""The sections in page order."""

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


__all__ = ["SECTIONS"]
