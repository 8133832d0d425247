"""Dynamics: Kane's equations of the chain in each case's speeds, and the effects that act on it.

Layer rule: imports the core (and the kernels at the first batched call);
never an engine.

* :mod:`~relacc.dynamics.effects`: what may act (absent means off, and not computed).
* :mod:`~relacc.dynamics.kane`: ``M udot = f`` from the partial velocities, energy, momenta.

The names below are the public API: ``relacc.dynamics.equations_of_motion(chain, case, q, u, effects)``.
"""

from relacc.dynamics.effects import NONE, Effects
from relacc.dynamics.kane import (
    BodyPartials,
    accelerations,
    body_partials,
    energy,
    energy_terms,
    equations_of_motion,
    generalized_forces,
    momenta,
)

__all__ = ["NONE", "BodyPartials", "Effects", "accelerations", "body_partials", "energy", "energy_terms",
           "equations_of_motion", "generalized_forces", "momenta"]
