"""What the adapters of a URDF on its fixed base share (PyBullet, iDynTree; imports no engine): one-speed joints
matched by name (``T = I``), links named as the URDF's, the gravity relacc's reading gives a URDF, and forward
dynamics solved from the engine's own equations where its API offers none outside a stepper."""

from __future__ import annotations

import numpy as np

from relacc.engines.base import Adapter, fixed_base_only, heads, match_by_name, solved_forward
from relacc.reading.urdf import GRAVITY as URDF_GRAVITY

__all__ = ["GRAVITY", "FixedBaseAdapter"]

GRAVITY = np.array(URDF_GRAVITY)
"""m/s^2: the gravity relacc's reading gives a URDF (:data:`relacc.reading.urdf.GRAVITY`; a URDF has none). A
fixed-base adapter's engine is given it (PyBullet's world has none until ``setGravity``; iDynTree takes it with each
state)."""


class FixedBaseAdapter(Adapter):
    """A URDF in an engine, its root link fixed, its revolute, continuous and prismatic joints matched by name.

    Subclasses call :meth:`_fixed_base` before :meth:`Adapter.__init__` and implement :meth:`equations`,
    :meth:`points` and :meth:`stepper`."""

    def _fixed_base(self, engine: str, path, reference, why: str, joints) -> list:
        """The matches of ``joints`` (``(name, type, position index, speed index)`` in the engine's order) after the
        tree's joints are checked (:func:`relacc.engines.base.fixed_base_only`, ``why``: what the engine does with a
        floating joint); sets :attr:`heads`."""
        fixed_base_only(engine, path, reference, why)
        self.heads = heads(reference)
        return match_by_name(reference, joints)

    def default_q(self) -> np.ndarray:
        return np.zeros(self.nq_e)

    def forward(self, qe, ve, effects=None, t=0.0):
        """``M^-1 f`` of :meth:`equations` (the engine computes no forward dynamics outside its stepper); a state whose
        mass matrix is singular (a joint that moves no inertia) is NaN: undefined."""
        M, f = self.equations(qe, ve, effects, t)
        return solved_forward(M, f)
