"""Dynamics: Kane's equations of any tree (the chain's too) in each case's speeds, and the effects that act on it.

Layer rule: imports the core (and the kernels at the first batched call);
never an engine.

* :mod:`~relacc.dynamics.effects`: what may act (absent means off, and not computed).
* :mod:`~relacc.dynamics.tree`: ``M udot = f`` of any tree from its bodies' partial velocities;
  :mod:`~relacc.dynamics.tree_energy`: energy, momenta;
* :mod:`~relacc.dynamics.kane`: the same for the chain, in its names (its tree's), and its compiled form.

The names below are the public API: ``relacc.dynamics.equations_of_motion(chain, case, q, u, effects)``.
"""

from relacc.dynamics.effects import NONE, Effects
from relacc.dynamics.kane import (
    accelerations,
    energy,
    energy_terms,
    equations_of_motion,
    generalized_forces,
    momenta,
)

__all__ = ["NONE", "Effects", "accelerations", "energy", "energy_terms", "equations_of_motion", "generalized_forces",
           "momenta"]
