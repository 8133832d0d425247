"""Core: the note's mathematics, engine-free.

Layer rule: modules here import only numpy, the standard library,
:mod:`relacc.errors` and each other. No engine, no report code, nothing
heavy at import time; the compiled kernels (:mod:`relacc.kernels`, numba)
are imported at the first batched call, inside :mod:`relacc.core.kinematics`.

* :mod:`~relacc.core.cases`, :mod:`~relacc.core.chain`: the three choices of
  generalized speeds, coordinate layouts and input checks; the chain's constants.
* :mod:`~relacc.core.rotations`, :mod:`~relacc.core.speeds`: tilde, rotation
  matrices, 1-2-3 partials; maps between the cases' speeds.
* :mod:`~relacc.core.note`: every formula of the note, by equation id.
* :mod:`~relacc.core.kinematics`: :func:`relacc.g2_kinematics`, the entry point.
* :mod:`~relacc.core.derivatives`: time derivatives along the motion (complex step).
* :mod:`~relacc.core.tolerances`, :mod:`~relacc.core.scales`: the one error
  model (tolerances, and the term magnitudes errors are normalized by). It
  lives in the core because the core's own input checks use it.
* :mod:`~relacc.core.states`, :mod:`~relacc.core.stream`,
  :mod:`~relacc.core.conventions`: seeded states, chunked evaluation, the
  meaning of every reported quantity.
"""

__all__: list[str] = []
"""The package hands on no names: import its modules."""
