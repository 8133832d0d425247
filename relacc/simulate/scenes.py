"""Scenes: TOML files that say which model, from which state, under which effects, for how long.

A scene's model is the note's chain (a shipped model, a chain TOML, inline fields) or any model file (MJCF,
URDF; beside the scene or inside an installed pip package). For a model, the effects are named by joint and body
(``[effects.joints.NAME]``, ``[effects.bodies.NAME]``) and every engine applies exactly those, nothing else from the
file (no contacts, actuators, joint damping, limits).

The schema is declared in :class:`relacc.fixtures.schema.SceneFile` (the
README's table is generated from it). An example::

    title = "Torque-free tumbling"           # optional
    [model]
    fixture = "two_body"                     # a shipped model; or file = "chain.toml"; or inline q2, r2, ...
    [initial]
    case = 2                                 # 1, 2 or 3: the coordinates q and speeds u below
    q = [...]                                # 14 (cases 1-2) or 12 (case 3) numbers
    u = [...]                                # 12 numbers
    [effects]                                # only what is listed acts; no table: nothing acts
    gravity = [0.0, 0.0, -9.81]              # m/s^2, fixed components
    [effects.spring]                         # on the prismatic offset s2' (B1 axes)
    stiffness = 50.0                         # N/m, one number or 3
    [simulate]
    duration = 2.0                           # s, a whole number of steps
    dt = 0.001                               # s
    integrator = "rk4"                       # rk4 | euler; implicit | implicitfast (mujoco only)
    engines = ["relacc", "pinocchio", "mujoco", "drake"]
    [simulate.drake]                         # Drake has no rk4: its own integrator, fixed steps dt
    integrator = "runge_kutta5"              # or accuracy = 1e-10 for error control
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from relacc.core.cases import as_case, check_q, check_u
from relacc.core.chain import TwoBodyChain
from relacc.dynamics.effects import Effects
from relacc.engines.registry import ENGINES, label, traits, with_trait
from relacc.errors import InputError, RelaccError
from relacc.fixtures import Fixture, tomlfile
from relacc.fixtures import load as load_fixture
from relacc.fixtures.model import inline

if TYPE_CHECKING:
    from relacc.core.tree import Tree
    from relacc.dynamics.tree_effects import TreeEffects

SIM_ENGINES = ("relacc",) + ENGINES
"""The names a scene's ``engines`` takes: relacc and every engine, in report order."""
DEFAULT_ENGINES = ("relacc",) + with_trait("in_scenes")
"""What a scene file that does not list its engines runs: relacc and the engines whose traits say so
(:attr:`relacc.engines.traits.Traits.in_scenes`)."""
INTEGRATORS = ("rk4", "euler", "implicit", "implicitfast")
"""The scene-wide integrators; each engine's own are in its traits (:func:`integrators_of`)."""
MAX_STEPS = 1e9
"""Longest run accepted, in steps: memory does not limit it (runs stream), this guards against typos."""


@dataclass(frozen=True, eq=False)
class Scene:
    """A validated scene.

    Attributes:
        name: file stem. title, description: from the file.
        fixture: the chain and, for engines, its model files (None for a model scene).
        case: coordinates of ``q``, ``u``. q: ``(nq,)``; u: ``(nv,)`` (the chain: 12).
        effects: what acts: :class:`relacc.dynamics.effects.Effects` (the chain) or
            :class:`relacc.dynamics.tree_effects.TreeEffects` (a model; gravity given, zero when absent).
        duration, dt: s. integrator: one of ``INTEGRATORS``.
        engines: names in ``SIM_ENGINES``. record_every: steps between records.
        model_path: a model scene's file (None for the chain). tree: relacc's tree of it.
        observe: the point the engines are compared at (``G2`` for the chain; a body's mass centre or a point).
        left_out: ``(engine, why)`` for each installed engine a model's default scene runs without (its reading
            lacks some of the model's joints).
        unevaluated: one line per kind of element of the model file that the run leaves out (equality constraints,
            tendons...: :attr:`relacc.reading.Reading.unevaluated`).
    """

    name: str
    title: str
    description: str
    fixture: Fixture | None
    case: int
    q: np.ndarray
    u: np.ndarray
    effects: "Effects | TreeEffects"
    duration: float
    dt: float
    integrator: str
    engines: tuple[str, ...]
    record_every: int = 1
    source: Path | None = field(default=None)
    drake_integrator: str | None = None
    drake_accuracy: float | None = None
    model_path: Path | None = None
    tree: "Tree | None" = None
    observe: str = "G2"
    left_out: tuple[tuple[str, str], ...] = ()
    unevaluated: tuple[str, ...] = ()

    def __post_init__(self):
        problem = check_simulate(self.duration, self.dt, self.integrator, list(self.engines), self.record_every,
                                 self.drake_integrator, self.drake_accuracy)
        if problem:
            raise InputError(f"scene {self.name}: {problem[0]}: {problem[1]}")

    @property
    def reference(self) -> str:
        """Whose acceleration the engines' are judged against, in words: ``"the note's"`` (its formulas, the chain),
        ``"relacc's"`` (its tree, a model); ``relacc simulate --json``'s ``reference``."""
        return self.evaluator.reference

    @property
    def evaluator(self):
        """relacc's side of the scene (:mod:`relacc.simulate.subjects`): the note's chain (its formulas and fused
        kernels, G2; :class:`relacc.simulate.subjects.NoteChain`) or a model file's tree
        (:class:`relacc.simulate.subjects.ModelTree`), one interface."""
        from relacc.simulate.subjects import MODEL_TREE, NOTE_CHAIN

        return MODEL_TREE if self.model_path is not None else NOTE_CHAIN

    @property
    def chain(self) -> TwoBodyChain:
        """The note's chain of a chain scene.

        Raises:
            InputError: a model file's scene (it has :attr:`model_tree` instead).
        """
        if self.fixture is None:
            raise InputError(f"scene {self.name} is a model's ({self.model_path}): it has a tree, not the note's chain")
        return self.fixture.chain

    @property
    def chain_effects(self) -> Effects:
        """The effects of a chain scene (the note's chain's :class:`relacc.dynamics.effects.Effects`).

        Raises:
            InputError: a model file's scene (its effects act by joint and body name).
        """
        if not isinstance(self.effects, Effects):
            raise InputError(f"scene {self.name} is a model's ({self.model_path}): its effects act on a tree")
        return self.effects

    @property
    def model_tree(self) -> Tree:
        """The tree of a model file's scene.

        Raises:
            InputError: a chain scene (it has :attr:`chain` instead).
        """
        if self.tree is None:
            raise InputError(f"scene {self.name} is the note's chain: it has no model file's tree")
        return self.tree

    @property
    def subject_tree(self) -> Tree:
        """The tree the scene runs on: a model file's, or the chain's (:func:`relacc.core.tree.model.chain_tree`,
        with G2 a named point)."""
        if self.tree is not None:
            return self.tree
        from relacc.core.tree.model import chain_tree

        return chain_tree(self.chain)

    @property
    def conserves_momentum(self) -> bool:
        """No external force or torque: the effects exert none, and every root body is free (a body jointed to the
        world takes reaction forces from it)."""
        return self.effects.conserves_momentum and all(b.joints and b.joints[0].type == "free"
                                                       for b in self.subject_tree.bodies if b.parent < 0)

    @property
    def engine_effects(self) -> TreeEffects:
        """The effects as the engines' adapters take them: by joint and body name
        (:class:`relacc.dynamics.tree_effects.TreeEffects`; the chain's converted, :meth:`Effects.for_tree`)."""
        return self.effects.for_tree() if isinstance(self.effects, Effects) else self.effects

    @property
    def point(self) -> tuple[str, str]:
        """The observed point as an adapter's point spec: a named point (the chain's ``G2``), or a body's mass
        centre."""
        from relacc.engines.base import body, point

        return point(self.observe) if self.observe in self.subject_tree.point_names else body(self.observe)

    def integrator_for(self, engine: str) -> tuple[str, float | None]:
        """``(integrator, accuracy)`` an engine runs: the scene's, or for an engine with error-controlled integrators
        of its own (Drake) ``[simulate.drake]``'s."""
        if engine in with_trait("error_controlled") and self.drake_integrator is not None:
            return self.drake_integrator, self.drake_accuracy
        return self.integrator, None

    @property
    def n_steps(self) -> int:
        """Number of steps: ``duration / dt``, a whole number (checked when the scene is made)."""
        return int(round(self.duration / self.dt))

    def replace(self, **changes) -> "Scene":
        """A copy with some fields changed (``dt``, ``integrator``, ``engines``, ``duration``...)."""
        kw = {k: getattr(self, k) for k in self.__dataclass_fields__}
        kw.update(changes)
        return Scene(**kw)


def integrators_of(engine: str) -> tuple[str, ...]:
    """The integrators a scene may name for ``engine`` (one of :data:`SIM_ENGINES`): relacc's own
    (:data:`INTEGRATORS`' fixed-step schemes but ``implicit``, ``implicitfast``: MuJoCo's), or an engine's traits'."""
    return ("rk4", "euler") if engine == "relacc" else traits(engine).integrators


def check_simulate(duration, dt, integrator, engines, record_every, drake_integrator=None, drake_accuracy=None):
    """The first problem with the ``[simulate]`` fields as ``(field, message)``, or None."""
    for key, value in (("duration", duration), ("dt", dt)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or value <= 0:
            return key, f"expected a positive number of seconds, got {value!r}"
    if dt > duration:
        return "dt", f"dt = {dt} is longer than the duration {duration}"
    steps = duration / dt
    if abs(steps - round(steps)) > 1e-9 * max(1.0, steps):
        return "duration", (f"{duration} s is not a whole number of steps of dt = {dt} s ({steps:.6g} steps); "
                            "relacc does not round it: choose dt = duration / n")
    if duration / dt > MAX_STEPS:
        return "dt", (f"{duration / dt:.3g} steps is more than {MAX_STEPS:.0e} (a dt in the wrong unit?); use a "
                      "larger dt or a shorter duration")
    if integrator not in INTEGRATORS:
        return "integrator", f"unknown integrator {integrator!r}; accepted: {', '.join(INTEGRATORS)}"
    if not isinstance(engines, (list, tuple)) or not engines or any(e not in SIM_ENGINES for e in engines):
        return "engines", f"expected a non-empty list of {', '.join(SIM_ENGINES)}, got {engines!r}"
    for engine in engines:
        controlled = engine in with_trait("error_controlled")
        own = drake_integrator if (controlled and drake_integrator) else integrator
        if own not in integrators_of(engine):
            if controlled:
                return ("drake.integrator" if drake_integrator else "integrator"), (
                    f"{label(engine)} has no {own!r} integrator: name one of {label(engine)}'s in "
                    f"[simulate.{engine}] integrator ({', '.join(integrators_of(engine))})")
            only = [e for e in SIM_ENGINES if integrator in integrators_of(e)]
            return "integrator", (f"{integrator!r} exists in {', '.join(label(e) for e in only)} only; "
                                  f"list engines = {only}")
    if drake_accuracy is not None and not (isinstance(drake_accuracy, float) and 0 < drake_accuracy < 1):
        return "drake.accuracy", f"accuracy must be a number in (0, 1), got {drake_accuracy!r}"
    if isinstance(record_every, bool) or not isinstance(record_every, int) or record_every < 1:
        return "record_every", f"expected a positive integer, got {record_every!r}"
    return None


def load(path) -> Scene:
    """Read and validate a scene file.

    Raises:
        FixtureError: missing file, TOML error, missing, unknown or invalid
            field (path, line and field named).
    """
    from relacc.fixtures.schema import SceneFile, validate

    path = Path(path)
    data, text = tomlfile.read(path)
    doc = validate(SceneFile, data, path, text)

    def checked(table, key, convert):
        try:
            return convert()
        except RelaccError as exc:
            raise tomlfile.field_error(path, text, table, key, str(exc)) from None

    model_path = _model_file(path, text, doc.model, checked)
    if model_path is not None:
        return _model_scene(path, text, doc, model_path, checked)
    fixture = _model(path, text, doc.model, checked)
    case = checked("initial", "case", lambda: int(as_case(doc.initial.case)))
    if doc.initial.q == "reference":
        raise tomlfile.field_error(path, text, "initial", "q", "the chain has no reference configuration: give "
                                   "its 14 (cases 1-2) or 12 (case 3) coordinates")
    q = checked("initial", "q", lambda: check_q(case, doc.initial.q))
    u = checked("initial", "u", lambda: check_u("u", doc.initial.u))
    if doc.effects.joints or doc.effects.bodies:
        key = "joints" if doc.effects.joints else "bodies"
        raise tomlfile.field_error(path, text, "effects", key, f"[effects.{key}.NAME] names a model's joints and "
                                   "bodies; the chain's effects are gravity, spring, ball_damping, force_G2, "
                                   "torque_B1, torque_B2")
    if doc.simulate.observe not in (None, "G2"):
        raise tomlfile.field_error(path, text, "simulate", "observe", "the chain is observed at G2")
    effects = _effects(doc.effects, checked)
    sim = doc.simulate
    drake_integrator, drake_accuracy = _simulate_table(path, text, sim)
    return Scene(name=path.stem, title=doc.title or path.stem, description=doc.description, fixture=fixture,
                 case=case, q=q, u=u, effects=effects, duration=float(sim.duration), dt=float(sim.dt),
                 integrator=sim.integrator, engines=_engines(sim), record_every=sim.record_every, source=path,
                 drake_integrator=drake_integrator, drake_accuracy=drake_accuracy)


def _engines(sim) -> tuple[str, ...]:
    """A ``[simulate]`` table's engines, :data:`DEFAULT_ENGINES` where it lists none."""
    return DEFAULT_ENGINES if sim.engines is None else tuple(sim.engines)


def _simulate_table(path, text, sim):
    """``(drake_integrator, drake_accuracy)`` of a checked ``[simulate]`` table (the first problem raises)."""
    drake_integrator = sim.drake.integrator if sim.drake else None
    drake_accuracy = sim.drake.accuracy if sim.drake else None
    problem = check_simulate(sim.duration, sim.dt, sim.integrator, _engines(sim), sim.record_every, drake_integrator,
                             drake_accuracy)
    if problem:
        table, key = f"simulate.{problem[0]}".rsplit(".", 1)
        raise tomlfile.field_error(path, text, table, key, problem[1])
    return drake_integrator, drake_accuracy


def _model_file(path, text, model, checked) -> Path | None:
    """A model scene's file (MJCF or URDF, beside the scene or inside ``package``), or None for the chain."""
    if model.package is not None and model.file is None:
        raise tomlfile.field_error(path, text, "model", "package", "give file = \"path inside the package\" too")
    if model.file is None or Path(model.file).suffix.lower() == ".toml" and model.package is None:
        return None
    others = sorted(k for k, v in model.model_dump().items() if v is not None and k not in ("file", "package"))
    if others:
        raise tomlfile.field_error(path, text, "model", others[0], "a model file takes no other [model] field")
    if model.package is not None:
        import importlib.util

        spec = importlib.util.find_spec(model.package) if model.package.isidentifier() else None
        if spec is None or spec.origin is None:
            raise tomlfile.field_error(path, text, "model", "package", f"no installed package {model.package!r} "
                                       f"(pip install {model.package}), where this scene's model is")
        where = Path(spec.origin).parent / model.file
    else:
        where = path.parent / model.file
    if not where.is_file():
        raise tomlfile.field_error(path, text, "model", "file", f"no such model file: {where}")
    return where.resolve()


def _model_scene(path, text, doc, model_path, checked) -> Scene:
    """A scene on a model file: its tree, the state in the case's coordinates, effects by joint and body name."""
    from relacc.core.tree import reference_q
    from relacc.core.tree.coordinates import check_q as check_tree_q
    from relacc.core.tree.coordinates import check_u as check_tree_u
    from relacc.reading import read_moving

    reading = checked("model", "file", lambda: read_moving(model_path, "there is nothing to simulate"))
    tree = reading.tree
    case = checked("initial", "case", lambda: int(as_case(doc.initial.case)))
    if doc.initial.q == "reference":
        q = reference_q(tree, case)
    else:
        q = checked("initial", "q", lambda: check_tree_q(tree, case, doc.initial.q))
    u = checked("initial", "u", lambda: check_tree_u(tree, "u", doc.initial.u))
    chain_keys = [k for k in ("ball_damping", "force_G2", "torque_B1", "torque_B2", "spring")
                  if getattr(doc.effects, k) is not None]
    if chain_keys:
        raise tomlfile.field_error(path, text, "effects", chain_keys[0], "a chain's effect; a model's are gravity, "
                                   "[effects.joints.NAME] and [effects.bodies.NAME]")
    effects = _tree_effects(tree, doc.effects, checked)
    sim = doc.simulate
    observe = sim.observe or first_moving(tree)
    if observe not in tree.body_names and observe not in tree.point_names:
        raise tomlfile.field_error(path, text, "simulate", "observe", f"{tree.name} has no body or point "
                                   f"{observe!r}; bodies: {', '.join(tree.body_names)}")
    drake_integrator, drake_accuracy = _simulate_table(path, text, sim)
    return Scene(name=path.stem, title=doc.title or path.stem, description=doc.description, fixture=None,
                 case=case, q=np.asarray(q, dtype=float), u=np.asarray(u, dtype=float), effects=effects,
                 duration=float(sim.duration), dt=float(sim.dt), integrator=sim.integrator,
                 engines=_engines(sim), record_every=sim.record_every, source=path,
                 drake_integrator=drake_integrator, drake_accuracy=drake_accuracy, model_path=model_path, tree=tree,
                 observe=observe, unevaluated=tuple(reading.unevaluated))


def _tree_effects(tree, eff, checked):
    """A model scene's effects, names checked against its tree (gravity absent: zero, not the file's)."""
    from relacc.dynamics.tree_effects import BodyLoad, JointEffect, TreeEffects

    gravity = checked("effects", "gravity", lambda: TreeEffects(eff.gravity).gravity) if eff.gravity else None
    joints, bodies = {}, {}
    for name, j in (eff.joints or {}).items():
        table = f"effects.joints.{name}"
        checked(table, "stiffness", lambda: tree.joint(name))
        joints[name] = checked(table, "rest", lambda: JointEffect(j.stiffness or 0.0, j.damping or 0.0, j.rest))
    for name, b in (eff.bodies or {}).items():
        table = f"effects.bodies.{name}"
        checked(table, "force", lambda: tree.body(name))
        bodies[name] = checked(table, "force", lambda: BodyLoad(
            np.asarray(b.force if b.force is not None else (0.0, 0.0, 0.0), dtype=float),
            np.asarray(b.torque if b.torque is not None else (0.0, 0.0, 0.0), dtype=float),
            b.frequency or 0.0, b.phase or 0.0))
    effects = TreeEffects(np.zeros(3) if gravity is None else gravity, joints, bodies)
    checked("effects", "joints", lambda: effects.resolve(tree))
    return effects


def _model(path, text, model, checked) -> Fixture:
    """The scene's chain: a shipped model by name, a chain TOML beside the scene, or inline fields."""
    given = {k: v for k, v in model.model_dump().items() if v is not None}
    if not given:
        raise tomlfile.field_error(path, text, None, "model", "give fixture = \"two_body\", file = \"chain.toml\" "
                                   "or inline q2, r2 (and optionally r1, m1, m2, I1, I2)")
    if "fixture" in given or "file" in given:
        key = "fixture" if "fixture" in given else "file"
        if len(given) > 1:
            raise tomlfile.field_error(path, text, "model", key, "give one of fixture, file or inline fields, not "
                                       f"several (got {', '.join(sorted(given))})")
        if key == "fixture":
            from relacc.fixtures import shipped

            name = given["fixture"]
            source = shipped.models_dir() / f"{name}.toml"
            if "/" in name or "\\" in name or not source.is_file():
                names = ", ".join(p.stem for p in sorted(shipped.models_dir().glob("*.toml")))
                raise tomlfile.field_error(path, text, "model", "fixture",
                                           f"no model file {name}.toml among the shipped models ({names}); for "
                                           "your own chain give file = \"chain.toml\" (relative to the scene)")
        else:
            source = (path.parent / given["file"]).resolve()
        return checked("model", key, lambda: load_fixture(source))
    if not {"q2", "r2"} <= set(given):
        raise tomlfile.field_error(path, text, "model", sorted(given)[0], "inline chains need q2 and r2 (and "
                                   "optionally r1, m1, m2, I1, I2)")
    for key, value in given.items():
        checked("model", key, lambda: TwoBodyChain(**{"q2": (0, 0, 0), "r2": (0, 0, 0), key: value}))
    return inline(f"{path.stem}_inline", TwoBodyChain(**given))


def _effects(eff, checked) -> Effects:
    """The scene's effects, each checked by :class:`relacc.dynamics.Effects` (the field named on error)."""
    kw = {key: getattr(eff, key) for key in ("gravity", "ball_damping", "force_G2", "torque_B1", "torque_B2")
          if getattr(eff, key) is not None}
    for key in kw:
        checked("effects", key, lambda: Effects(**{key: kw[key]}))
    if eff.spring is not None:
        spring = {f"spring_{k}": v for k, v in (("stiffness", eff.spring.stiffness), ("damping", eff.spring.damping),
                                                  ("rest", eff.spring.rest)) if v is not None}
        if not spring.keys() - {"spring_rest"}:
            checked("effects", "spring", lambda: (_ for _ in ()).throw(
                InputError("[effects.spring] needs stiffness or damping (or both)")))
        for key, value in spring.items():
            checked("effects.spring", key.replace("spring_", ""), lambda: Effects(**{key: value}))
        kw.update(spring)
    return Effects(**kw)


def first_moving(tree) -> str:
    """The name of ``tree``'s first body that a joint moves (a scene's default ``observe``): a URDF's base link,
    welded to the world, moves with nothing (and MuJoCo fuses it into the world)."""
    moving: list[bool] = []
    for b in tree.bodies:
        moving.append(bool(b.joints) or (b.parent >= 0 and moving[b.parent]))
    return tree.bodies[moving.index(True)].name


def fastest_moving(tree, q, u) -> str:
    """The name of the body of ``tree`` whose mass centre moves fastest at the state ``q``, ``u`` (case 2): a model's
    default scene is observed there, at a point that moves (issue 49: the iCub's first moving body has its mass
    centre 0.5 mm from its axis and moved 0.07 mm in a second, so differences of 1e-17 m between engines said nothing
    and the orders of accuracy could not be read). Bodies with mass first; a tree of massless bodies, any."""
    from relacc.core.tree import tree_kinematics

    speed = np.linalg.norm(tree_kinematics(tree, 2, q, u, partials=False).velocity, axis=-1)
    moving = [bool(b.joints) for b in tree.bodies]
    for b, body in enumerate(tree.bodies):
        moving[b] = moving[b] or (body.parent >= 0 and moving[body.parent])
    for candidates in ([b for b in range(tree.nb) if moving[b] and tree.bodies[b].mass > 0],
                       [b for b in range(tree.nb) if moving[b]]):
        if candidates:
            return tree.bodies[max(candidates, key=lambda b: speed[b])].name
    return first_moving(tree)


def model_scene(path, *, seed: int = 0, duration: float = 1.0, dt: float = 1e-3, engines=None,
                observe: str | None = None) -> Scene:
    """The default scene of any model file (``relacc simulate --model``): tumbling in space from the reference
    configuration (MuJoCo's ``qpos0``) with seeded speeds (standard normals from ``numpy.random.default_rng(seed)``,
    m/s and rad/s), nothing acting (no gravity, no spring, no contact: energy and momenta are conserved, so their
    drift measures each integrator), RK4, observed at the mass centre of ``observe`` (a body's name; default the
    body whose mass centre moves fastest at the start, :func:`fastest_moving`). A chain TOML gets the shipped
    ``tumbling`` scene on that chain.

    Raises:
        ModelError: the file cannot be read. InputError: a bad seed, or ``observe`` names no body of the model.
    """
    from relacc.core.cases import check_int
    from relacc.core.tree import reference_q
    from relacc.dynamics.tree_effects import TreeEffects
    from relacc.engines import steppers
    from relacc.reading import read_moving

    path = Path(path)
    seed = check_int("seed", seed, minimum=0)
    # the default scene integrates with RK4: the engines that have it (or their own error-controlled schemes); an
    # engine with another scheme only (PyBullet's semi-implicit Euler) is named with --engines and --integrator euler
    names = ("relacc",) + tuple(e for e in steppers() if "rk4" in integrators_of(e) or e in with_trait(
        "error_controlled")) if engines is None else tuple(engines)
    drake = "runge_kutta5" if with_trait("error_controlled", names) else None
    if path.suffix.lower() == ".toml":
        from relacc.fixtures.shipped import scene_path

        base = load(scene_path("tumbling"))
        return base.replace(fixture=load_fixture(path), name=f"{path.stem}_tumbling", engines=names,
                            drake_integrator=drake)
    reading = read_moving(path, "there is nothing to simulate")
    tree = reading.tree
    u = np.random.default_rng(seed).standard_normal(tree.nv)
    if observe is not None and observe not in tree.body_names:
        raise InputError(f"--observe {observe!r}: no body of {path.name} is named so; its bodies are "
                         f"{', '.join(tree.body_names[:12])}{', ...' if tree.nb > 12 else ''}")
    scene = Scene(name=f"{path.stem}_tumbling", title=f"{tree.name} tumbling in space (seed {seed})",
                 description="the model's default scene: its reference configuration, seeded speeds, nothing acting",
                 fixture=None, case=2, q=reference_q(tree, 2), u=u, effects=TreeEffects(np.zeros(3)),
                 duration=float(duration), dt=float(dt), integrator="rk4", engines=names,
                 record_every=max(1, int(round(duration / dt)) // 100), source=None, drake_integrator=drake,
                 model_path=path.resolve(), tree=tree,
                 observe=observe or fastest_moving(tree, reference_q(tree, 2), u),
                 unevaluated=tuple(reading.unevaluated))
    if engines is not None:
        return scene
    from relacc.simulate.subjects import usable

    kept, left_out = usable(scene)
    return scene.replace(engines=kept, left_out=left_out,
                         drake_integrator=drake if with_trait("error_controlled", kept) else None)
