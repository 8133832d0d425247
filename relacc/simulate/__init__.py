"""Simulation: scenes, integrators on the configuration manifolds, runs on every engine and their comparison.

Layer rule: imports the core, dynamics, kernels and (when a run asks for
one) the engines; nothing here is imported by ``import relacc``.

* :mod:`~relacc.simulate.scenes`: scene files (which chain, from which state, under which effects).
* :mod:`~relacc.dynamics.integrate`: RKMK4, semi-implicit Euler, ``solve_ivp`` on SO(3) charts.
* :mod:`~relacc.simulate.runs`: a scene on relacc and the engines, compared.
"""

from relacc.simulate.runs import SimulationResult, Trajectory, format_text, run, write_csv

__all__ = ["SimulationResult", "Trajectory", "format_text", "run", "write_csv"]
