"""Engine adapters: one package per engine behind one interface (:class:`relacc.engines.base.Adapter`).

* :mod:`relacc.engines.mujoco_` -- MuJoCo (imports only ``mujoco``);
* :mod:`relacc.engines.pinocchio_` -- Pinocchio (imports only ``pinocchio``);
* :mod:`relacc.engines.drake_` -- Drake (imports only ``pydrake``);
* :mod:`relacc.engines.pybullet_` -- PyBullet (imports only ``pybullet``), as users load a URDF and with
  ``URDF_USE_INERTIA_FROM_FILE`` (two cards, ``pybullet`` and ``pybullet_file``);
* :mod:`relacc.engines.idyntree_` -- iDynTree (imports only ``idyntree``).

An adapter is one model in one engine (a model file, or relacc's tree where the engine's parser would read it
otherwise) and serves the chain and any robot alike: loading, speed maps to relacc's coordinates, batched dynamics
and points, a stepper. :mod:`relacc.engines.base` states the interface and does, once for every engine, what is
engine-free (speed maps, the equations in relacc's speeds); :mod:`relacc.engines.chain` is the note's chain on the
adapters (G2 is a point of its model).

Layer rule: adapters import the core, the kernels, the dynamics, the fixtures, relacc's reading and their own
engine, and only their own; nothing outside ``engines/`` imports an engine package or an adapter's module:
everything goes through :func:`load` and :func:`load_engine` (:mod:`relacc.engines.registry`), which import an
adapter when it is asked for, and each adapter's class says what its engine can do (:class:`Adapter`'s class
attributes), so no caller outside ``engines/`` branches on an engine's name.
"""

from relacc.engines.registry import (
    CHAIN_ENGINES,
    ENGINES,
    MESH_ENGINE,
    ROUTES,
    TRAITS,
    TRUTH_ENGINE,
    Adapter,
    ChainEngine,
    Traits,
    adapter_module,
    anchor,
    anchors,
    available,
    chain_engines,
    chain_exports,
    file_readings,
    installed,
    judges,
    label,
    load,
    load_engine,
    mesh_inertia,
    readings,
    reads,
    steppers,
    traits,
    with_capability,
    with_trait,
)

__all__ = ["CHAIN_ENGINES", "ENGINES", "MESH_ENGINE", "ROUTES", "TRAITS", "TRUTH_ENGINE", "Adapter", "ChainEngine",
           "Traits", "adapter_module", "anchor", "anchors", "available", "chain_engines", "chain_exports",
           "file_readings", "installed", "judges", "label", "load", "load_engine", "mesh_inertia", "reads",
           "readings", "steppers", "traits", "with_capability", "with_trait"]
