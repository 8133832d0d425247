"""What an engine is and can do, declared without importing it (:class:`Traits`): each engine package's ``card``
module holds its one instance, and :mod:`relacc.engines.registry` collects them. Callers outside ``engines/`` ask an
engine's traits instead of naming it (the layout test holds them to it). This module imports nothing."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Traits:
    """One engine's declaration.

    Attributes:
        name: its name in relacc (``--engines``, JSON keys). label: how it is written in sentences. order: its place
            in reports (ascending).
        package: its Python package. pip: its distribution's name.
        color, marker, marker_size: how plots and drawings show it (a matplotlib colour and marker; points).
        integrators: the integrators a scene may name for it (``[simulate.<engine>]``), by the names scenes use;
            ``euler`` is semi-implicit Euler everywhere.
        adaptive: its own error-controlled integrators the work-precision sweep runs (those of ``integrators`` it
            can run to an accuracy; :mod:`relacc.tradeoff.integrators`).
        speeds: its own speeds at a model's joints, which its adapter maps to relacc's case 2 once (a sentence).
        capabilities: the names of the :mod:`relacc.engines.capabilities` its adapter implements, declared here so
            that a caller can choose engines without importing them (the contract test holds the two equal).
        calls: what its capabilities call, by kind (``batched_forward``, ``rollout``, ``step``, ``jacobians``,
            ``motion``): benchmark rows are named ``"<name> <call>"`` (:func:`relacc.engines.registry.anchor`).
        own_urdf: reads a URDF given beside an MJCF with its own parser, and is then compared on that file's reading.
        compiled_loops: its per-state evaluations (points, Jacobians) run as loops in its own compiled code, so
            their time is the engine's (the throughput tables time these; a loop through Python per state is not).
        error_controlled: integrates with error-controlled integrators of its own, named in a scene's
            ``[simulate.<engine>]`` table with an accuracy, rather than relacc's fixed-step schemes only.
        own_steppers: steps a model with integrators in its own compiled code (``mj_step``, Drake's ``Simulator``),
            not relacc's integrators around its dynamics.
        chain_routes: how the note's chain is written in it, route by route (``quaternion``, ``euler``): its model,
            coordinates, speeds and G2 calls (the report's conventions section).
        chain_files: how its package's ``load`` reads the chain, route by route: ``(the fixture's file, options)``,
            an option naming a fixture file (``"two_body_euler.urdf"``) given that file's path
            (:func:`relacc.engines.chain.chain_engine`).
        truth: the engine the pytest plugin's truth and the tree hard-case search use unless told (one engine:
            MuJoCo, which reads an MJCF natively and gives every body's kinematics).
        mesh_source: relacc's reading may ask its compiler for a mesh's mass properties it does not compute itself
            (a primitive fitted to a mesh), so its terms on those bodies cannot judge it.
        formats: the description formats its loader reads (``"mjcf"``, ``"urdf"``); a file of another format is not
            offered to it (said in the comparison, not an error).
        home: the engine package its adapter lives in, ``relacc/engines/<home>_/`` (default: its name); one package
            may declare several loadings of one engine (PyBullet as users load it, and with the flag its
            documentation recommends), each a card of its own.
        options: what its package's ``load`` is called with for this loading (``{"inertia_from_file": True}``).
        readings: the attribute of its package's ``readings`` module that holds this loading's ``FILE_READINGS``.
        in_scenes: a scene file that does not list its engines runs this one, beside relacc
            (:data:`relacc.simulate.scenes.DEFAULT_ENGINES`).
        file_inertias: this loading takes each body's inertia from the file (PyBullet's default loading computes its
            own from the collision shapes: ``relacc compare`` names that, but it does not judge relacc's tree in
            ``relacc check --model``).
    """

    name: str
    label: str
    order: int
    package: str
    pip: str
    color: str
    marker: str
    marker_size: float
    integrators: tuple[str, ...]
    speeds: str
    chain_routes: dict[str, str]
    chain_files: dict[str, tuple[str, dict]] = field(default_factory=dict)
    capabilities: frozenset[str] = frozenset()
    calls: dict[str, str] = field(default_factory=dict)
    adaptive: tuple[str, ...] = ()
    own_urdf: bool = False
    compiled_loops: bool = False
    error_controlled: bool = False
    own_steppers: bool = False
    mesh_source: bool = False
    truth: bool = False
    formats: tuple[str, ...] = ("mjcf", "urdf")
    home: str = ""
    options: dict = field(default_factory=dict)
    readings: str = "FILE_READINGS"
    file_inertias: bool = True
    in_scenes: bool = False

    @property
    def package_name(self) -> str:
        """Its engine package's module name, ``relacc.engines.<home>_``."""
        return f"relacc.engines.{self.home or self.name}_"
