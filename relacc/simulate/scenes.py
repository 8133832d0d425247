"""Scenes: TOML files that say which chain, from which state, under which effects, for how long.

Schema (``models/scenes/*.toml``; every table but ``[effects]`` required)::

    title = "Torque-free tumbling"           # optional
    description = "..."                      # optional

    [model]
    fixture = "two_body"                     # models/<fixture>.toml, or inline fields instead:
    # q2 = [...]  r2 = [...]  r1 = [...]  m1 = 2.0  m2 = 0.8  I1 = [[...]]  I2 = [[...]]

    [initial]
    case = 2                                 # 1, 2 or 3: the coordinates q and speeds u below
    q = [...]                                # 14 (cases 1-2) or 12 (case 3) numbers
    u = [...]                                # 12 numbers

    [effects]                                # only what is listed acts; no table: nothing acts
    gravity = [0.0, 0.0, -9.81]              # m/s^2, fixed components
    ball_damping = 0.02                      # N m s/rad on the spherical joint
    force_G2 = [1.0, 0.0, 0.0]               # N at G2, fixed components
    torque_B1 = [0.0, 0.0, 0.1]              # N m on B1, fixed components
    torque_B2 = [0.0, 0.0, 0.1]              # N m on B2, fixed components
    [effects.spring]                         # on the prismatic offset s2' (B1 axes)
    stiffness = 50.0                         # N/m, one number or 3
    damping = 0.5                            # N s/m, one number or 3 (optional)
    rest = [0.0, 0.0, 0.0]                   # m, B1 components (optional)

    [simulate]
    duration = 2.0                           # s
    dt = 0.001                               # s
    integrator = "rk4"                       # rk4 | euler (all engines); implicit | implicitfast (mujoco only)
    engines = ["relacc", "pinocchio", "mujoco"]
    record_every = 1                         # optional: record every n-th step
"""

from __future__ import annotations

import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from relacc.core.cases import as_case, check_q, check_u
from relacc.core.chain import TwoBodyChain
from relacc.dynamics.effects import Effects
from relacc.errors import FixtureError, InputError, RelaccError
from relacc.fixtures import Fixture, tomlfile, write
from relacc.fixtures import load as load_fixture

SIM_ENGINES = ("relacc", "pinocchio", "mujoco")
INTEGRATORS = ("rk4", "euler", "implicit", "implicitfast")
MUJOCO_ONLY = ("implicit", "implicitfast")


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

    def __post_init__(self):
        problem = check_simulate(self.duration, self.dt, self.integrator, list(self.engines), self.record_every)
        if problem:
            raise InputError(f"scene {self.name}: {problem[0]}: {problem[1]}")

    @property
    def n_steps(self) -> int:
        return int(round(self.duration / self.dt))

    def replace(self, **changes) -> "Scene":
        """A copy with some fields changed (``dt``, ``integrator``, ``engines``, ``duration``...)."""
        kw = {k: getattr(self, k) for k in self.__dataclass_fields__}
        kw.update(changes)
        return Scene(**kw)


def check_simulate(duration, dt, integrator, engines, record_every):
    """The first problem with the ``[simulate]`` fields as ``(field, message)``, or None."""
    for key, value in (("duration", duration), ("dt", dt)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) or value <= 0:
            return key, f"expected a positive number of seconds, got {value!r}"
    if dt > duration:
        return "dt", f"dt = {dt} is longer than the duration {duration}"
    if duration / dt > 1e7:
        return "dt", f"{duration / dt:.3g} steps is more than 1e7; use a larger dt or a shorter duration"
    if integrator not in INTEGRATORS:
        return "integrator", f"unknown integrator {integrator!r}; accepted: {', '.join(INTEGRATORS)}"
    if not isinstance(engines, (list, tuple)) or not engines or any(e not in SIM_ENGINES for e in engines):
        return "engines", f"expected a non-empty list of {', '.join(SIM_ENGINES)}, got {engines!r}"
    if integrator in MUJOCO_ONLY and set(engines) - {"mujoco"}:
        return "integrator", f"{integrator!r} exists in MuJoCo only; list engines = [\"mujoco\"]"
    if isinstance(record_every, bool) or not isinstance(record_every, int) or record_every < 1:
        return "record_every", f"expected a positive integer, got {record_every!r}"
    return None


_EFFECT_KEYS = {"gravity", "ball_damping", "force_G2", "torque_B1", "torque_B2", "spring"}
_SPRING_KEYS = {"stiffness", "damping", "rest"}


def load(path) -> Scene:
    """Read and validate a scene file.

    Raises:
        FixtureError: missing file, TOML error, missing or invalid field,
            unknown key (path, line and field named).
    """
    path = Path(path)
    data, text = tomlfile.read(path)

    def err(table, key, message):
        return tomlfile.field_error(path, text, table, key, message)

    def table(name, required=True):
        t = data.get(name)
        if t is None and not required:
            return {}
        if not isinstance(t, dict):
            raise FixtureError(f"{path}: missing table [{name}] (see relacc/scenes.py for the schema)")
        return t

    def get(tab, name, key, default=...):
        if key not in tab:
            if default is ...:
                raise FixtureError(f"{path}: missing field [{name}].{key}")
            return default
        return tab[key]

    unknown = set(data) - {"title", "description", "model", "initial", "effects", "simulate"}
    if unknown:
        raise FixtureError(f"{path}: unknown top-level keys {sorted(unknown)}; accepted: title, description, "
                           "[model], [initial], [effects], [simulate]")
    fixture = _model(path, text, table("model"), err)
    ini = table("initial")
    try:
        case = int(as_case(get(ini, "initial", "case")))
    except RelaccError as exc:
        raise err("initial", "case", str(exc)) from None
    try:
        q = check_q(case, get(ini, "initial", "q"))
    except RelaccError as exc:
        raise err("initial", "q", str(exc)) from None
    try:
        u = check_u("u", get(ini, "initial", "u"))
    except RelaccError as exc:
        raise err("initial", "u", str(exc)) from None
    effects = _effects(path, text, table("effects", required=False), err)
    sim = table("simulate")
    duration, dt = get(sim, "simulate", "duration"), get(sim, "simulate", "dt")
    integrator = get(sim, "simulate", "integrator", "rk4")
    engines = get(sim, "simulate", "engines", list(SIM_ENGINES))
    record_every = get(sim, "simulate", "record_every", 1)
    problem = check_simulate(duration, dt, integrator, engines, record_every)
    if problem:
        raise err("simulate", *problem)
    extra = set(sim) - {"duration", "dt", "integrator", "engines", "record_every"}
    if extra:
        raise err("simulate", sorted(extra)[0], "unknown key; accepted: duration, dt, integrator, engines, "
                                                "record_every")
    return Scene(name=path.stem, title=str(data.get("title", path.stem)), description=str(data.get("description", "")),
                 fixture=fixture, case=case, q=q, u=u, effects=effects, duration=float(duration), dt=float(dt),
                 integrator=integrator, engines=tuple(engines), record_every=record_every, source=path)


def _model(path, text, model, err) -> Fixture:
    if "fixture" in model:
        if set(model) != {"fixture"}:
            raise err("model", "fixture", "give either a fixture name or inline fields, not both")
        name = model["fixture"]
        if not isinstance(name, str) or not name or "/" in name or "\\" in name:
            raise err("model", "fixture", f"expected a fixture name such as \"two_body\", got {name!r}")
        from relacc.fixtures import shipped

        source = shipped.models_dir() / f"{name}.toml"
        if not source.is_file():
            raise err("model", "fixture", f"no model file {name}.toml among the shipped models "
                      f"({', '.join(p.stem for p in sorted(shipped.models_dir().glob('*.toml')))})")
        return load_fixture(source)
    keys = {"q2", "r2", "r1", "m1", "m2", "I1", "I2"}
    unknown = set(model) - keys
    if unknown or not {"q2", "r2"} <= set(model):
        raise FixtureError(f"{path}: [model] needs fixture = \"name\" or inline q2, r2 (and optionally r1, m1, "
                           f"m2, I1, I2); got keys {sorted(model)}")
    for key in model:
        try:
            TwoBodyChain(**{"q2": (0, 0, 0), "r2": (0, 0, 0), key: model[key]})
        except RelaccError as exc:
            raise err("model", key, str(exc)) from None
    chain = TwoBodyChain(**model)
    # The engines read model files: write them, from the inline values, to a temporary directory.
    source = Path(tempfile.mkdtemp(prefix=f"relacc-{path.stem}-")) / "two_body.toml"
    fixture = Fixture(f"{path.stem}_inline", chain, source)
    write(fixture)
    return fixture


def _effects(path, text, eff, err) -> Effects:
    unknown = set(eff) - _EFFECT_KEYS
    if unknown:
        raise err("effects", sorted(unknown)[0], f"unknown effect; accepted: {', '.join(sorted(_EFFECT_KEYS))}")
    kw = {}
    for key in ("gravity", "ball_damping", "force_G2", "torque_B1", "torque_B2"):
        if key in eff:
            kw[key] = eff[key]
    spring = eff.get("spring")
    if spring is not None:
        if not isinstance(spring, dict) or set(spring) - _SPRING_KEYS or not spring:
            raise FixtureError(f"{path}: [effects.spring] takes stiffness, damping, rest; got {spring!r}")
        for key, target in (("stiffness", "spring_stiffness"), ("damping", "spring_damping"),
                            ("rest", "spring_rest")):
            if key in spring:
                kw[target] = spring[key]
    try:
        return Effects(**kw)
    except RelaccError as exc:
        bad = next((k for k in kw if k.replace("spring_", "") in str(exc) or k in str(exc)), "effects")
        table = "effects.spring" if bad.startswith("spring_") else "effects"
        key = bad.replace("spring_", "") if bad.startswith("spring_") else bad
        raise err(table, key, str(exc)) from None
