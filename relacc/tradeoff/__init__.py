"""What accuracy costs in time: work-precision sweeps and their Pareto fronts (``relacc tradeoff``).

* :mod:`relacc.tradeoff.derivatives`: G2's acceleration by the analytic
  formulas, finite differences, Richardson, complex step and the engines.
* :mod:`relacc.tradeoff.integrators`: trajectories by each engine's
  integrators over a sweep of step or tolerance.
* :mod:`relacc.tradeoff.trees`: relacc's tree kernels against the engines' fastest batched calls.

Layer rule: imports the core, kernels, dynamics, fixtures, reading, simulate, validation and the
engines' adapters (:mod:`relacc.engines`), never an engine's own package, the report or the CLI.
"""

from relacc.tradeoff.study import (
    FULL,
    QUICK,
    REPORT,
    Tradeoff,
    assemble,
    derivative_sweep,
    format_text,
    pareto,
    run,
    scene_paths,
    scene_sweep,
)

__all__ = ["FULL", "QUICK", "REPORT", "Tradeoff", "assemble", "derivative_sweep", "format_text", "pareto", "run",
           "scene_paths", "scene_sweep"]
