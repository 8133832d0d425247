"""The self-contained HTML agreement report (``relacc report``).

A report is a list of sections. Each section is one module in
:mod:`relacc.report.sections` with ``ID``, ``TITLE`` and ``build(ctx) -> dict``
(plain data), plus one template ``templates/sections/<ID>.html.j2``. Adding a
section is adding those two files and listing the module in ``SECTIONS``.

Layer rule: sections read the layers below (validation, tradeoff, simulate, the engines, reading, fixtures, dynamics,
kernels, the core) and return plain
data; only the templates render it (Jinja2, autoescaped). Never the CLI, never an engine's own package.
"""

from relacc.report.build import (
    DEFAULT_BATCHED,
    DEFAULT_BENCH,
    DEFAULT_EXAMPLES,
    DEFAULT_STATES,
    QUICK_BATCHED,
    QUICK_BENCH,
    QUICK_EXAMPLES,
    QUICK_STATES,
    SWEEP,
    ReportContext,
    build_context,
    build_report,
    default_second,
    environment,
    render,
    scene_entry,
)

__all__ = ["DEFAULT_BATCHED", "DEFAULT_BENCH", "DEFAULT_EXAMPLES", "DEFAULT_STATES", "QUICK_BATCHED", "QUICK_BENCH",
           "QUICK_EXAMPLES", "QUICK_STATES", "SWEEP", "ReportContext", "build_context", "build_report",
           "default_second", "environment", "render", "scene_entry"]
