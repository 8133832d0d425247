"""Kernels: the fused, compiled (numba, and LLVM through llvmlite) evaluations of the core's corrected formulas.

Layer rule: imports the core, numba and llvmlite; never an engine. Nothing here is
imported by ``import relacc``: :mod:`relacc.core.kinematics` and
:mod:`relacc.dynamics` import these modules at the first batched call.

* :mod:`~relacc.kernels.jit`: the numba switch (compiled or plain Python).
* :mod:`~relacc.kernels.trig`: branch-free fdlibm ``sincos``.
* :mod:`~relacc.kernels.perstate`: the per-state arithmetic shared by the loops.
* :mod:`~relacc.kernels.kinematics`: batch loops behind :func:`relacc.g2_kinematics`.
* :mod:`~relacc.kernels.dynamics`: Kane's ``M``, ``f`` per state, and the SO(3) steps.
* :mod:`~relacc.kernels.tree_dynamics` and its ``tree_*`` modules: a tree's forward dynamics, kinematics and loads.
* :mod:`~relacc.kernels.lanes`: the tree's forward dynamics code traced once per tree and compiled over several
  states at once in vector lanes.
* :mod:`~relacc.kernels.direct`: one state's call from CPython straight into a lanes kernel (a builtin in LLVM IR).
"""

__all__: list[str] = []
"""The package hands on no names: import its modules."""
