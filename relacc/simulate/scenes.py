"""Scenes: TOML files that say which chain, from which state, under which effects, for how long.

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

import numpy as np

from relacc.core.cases import as_case, check_q, check_u
from relacc.core.chain import TwoBodyChain
from relacc.core.conventions import ENGINE_INTEGRATORS, ENGINE_LABELS
from relacc.dynamics.effects import Effects
from relacc.errors import InputError, RelaccError
from relacc.fixtures import Fixture, tomlfile
from relacc.fixtures import load as load_fixture
from relacc.fixtures.model import inline

SIM_ENGINES = ("relacc", "pinocchio", "mujoco", "drake")
INTEGRATORS = ("rk4", "euler", "implicit", "implicitfast")
"""The scene-wide integrators; each engine's own are in :data:`relacc.core.conventions.ENGINE_INTEGRATORS`."""
MAX_STEPS = 1e9
"""Longest run accepted, in steps: memory does not limit it (runs stream), this guards against typos."""


@dataclass(frozen=True, eq=False)
class Scene:
    """A validated scene.

    Attributes:
        name: file stem. title, description: from the file.
        fixture: the chain and, for engines, its model files.
        case: coordinates of ``q``, ``u``. q: ``(nq,)``; u: ``(12,)``.
        effects: what acts. duration, dt: s. integrator: one of ``INTEGRATORS``.
        engines: names in ``SIM_ENGINES``. record_every: steps between records.
    """

    name: str
    title: str
    description: str
    fixture: Fixture
    case: int
    q: np.ndarray
    u: np.ndarray
    effects: Effects
    duration: float
    dt: float
    integrator: str
    engines: tuple[str, ...]
    record_every: int = 1
    source: Path | None = field(default=None)
    drake_integrator: str | None = None
    drake_accuracy: float | None = None

    def __post_init__(self):
        problem = check_simulate(self.duration, self.dt, self.integrator, list(self.engines), self.record_every,
                                 self.drake_integrator, self.drake_accuracy)
        if problem:
            raise InputError(f"scene {self.name}: {problem[0]}: {problem[1]}")

    def integrator_for(self, engine: str) -> tuple[str, float | None]:
        """``(integrator, accuracy)`` an engine runs: the scene's, or for Drake ``[simulate.drake]``'s."""
        if engine == "drake" and self.drake_integrator is not None:
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
        own = drake_integrator if (engine == "drake" and drake_integrator) else integrator
        if own not in ENGINE_INTEGRATORS[engine]:
            if engine == "drake":
                return "integrator", (f"Drake has no {integrator!r} integrator: name one of Drake's in "
                                      f"[simulate.drake] integrator ({', '.join(ENGINE_INTEGRATORS['drake'])})")
            only = [e for e, names in ENGINE_INTEGRATORS.items() if integrator in names]
            return "integrator", (f"{integrator!r} exists in {', '.join(ENGINE_LABELS[e] for e in only)} only; "
                                  f"list engines = {only}")
    if drake_accuracy is not None and not (isinstance(drake_accuracy, float) and 0 < drake_accuracy < 1):
        return "drake", f"accuracy must be a number in (0, 1), got {drake_accuracy!r}"
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

    fixture = _model(path, text, doc.model, checked)
    case = checked("initial", "case", lambda: int(as_case(doc.initial.case)))
    q = checked("initial", "q", lambda: check_q(case, doc.initial.q))
    u = checked("initial", "u", lambda: check_u("u", doc.initial.u))
    effects = _effects(doc.effects, checked)
    sim = doc.simulate
    drake_integrator = sim.drake.integrator if sim.drake else None
    drake_accuracy = sim.drake.accuracy if sim.drake else None
    problem = check_simulate(sim.duration, sim.dt, sim.integrator, sim.engines, sim.record_every, drake_integrator,
                             drake_accuracy)
    if problem:
        table = "simulate.drake" if problem[0] == "drake" else "simulate"
        raise tomlfile.field_error(path, text, table, "accuracy" if problem[0] == "drake" else problem[0],
                                   problem[1])
    return Scene(name=path.stem, title=doc.title or path.stem, description=doc.description, fixture=fixture,
                 case=case, q=q, u=u, effects=effects, duration=float(sim.duration), dt=float(sim.dt),
                 integrator=sim.integrator, engines=tuple(sim.engines), record_every=sim.record_every, source=path,
                 drake_integrator=drake_integrator, drake_accuracy=drake_accuracy)


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
