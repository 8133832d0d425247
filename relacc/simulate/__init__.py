"""Simulation: scenes, integrators on the configuration manifolds, runs on every engine and their comparison.

Layer rule: imports the core, dynamics, kernels, fixtures, reading and (when a run asks
for one) the engines; nothing here is imported by ``import relacc``.

* :mod:`~relacc.simulate.scenes`: scene files (which chain, from which state, under which effects).
* :mod:`~relacc.simulate.runs`: a scene on relacc and the engines in lockstep, compared, streamed to CSV.
* :mod:`~relacc.simulate.trajectory`: what a run records and keeps.
* :mod:`~relacc.simulate.ensemble`: one scene from many initial states, on every engine's batched API;
  :mod:`~relacc.simulate.members`: the members, chunk by chunk, and what an ensemble reports.
"""

from relacc.simulate.ensemble import Ensemble, ensemble
from relacc.simulate.members import perturbed
from relacc.simulate.runs import SimulationResult, format_text, run, scene_notes
from relacc.simulate.trajectory import Trajectory

__all__ = ["Ensemble", "SimulationResult", "Trajectory", "ensemble", "format_text", "perturbed", "run", "scene_notes"]
