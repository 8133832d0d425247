"""``relacc compare``: what each engine made of a robot description, against relacc's own reading of it.

relacc reads the file itself (:mod:`relacc.reading`), by the format's specification; MuJoCo, Pinocchio and Drake each
read it with their own parser. relacc's reading is the comparison's common ground (its case-2 coordinates, each
engine's matched joint by joint through its speed map) and one of four independent opinions:

1. the **audit** (:mod:`relacc.validation.robots.audit`): structure, inertias, armature, damping, gravity of each
   engine against relacc's reading, each difference with its cause (:mod:`relacc.validation.robots.causes`): a known
   engine behaviour reproduced (relacc's reader reading the file the engine's way), a finding about the file, or not
   explained, with the place in the file;
2. the **dynamics** (:mod:`relacc.validation.robots.agreement`) at the reference configuration and random states,
   each engine and relacc's cases 1 and 3 against relacc's case 2;
3. the **referee** (:mod:`relacc.validation.robots.referee`): every pair of evaluators compared, engine against
   engine too, and the odd one out named, whoever it is.

Physical findings (:mod:`relacc.reading.physical`), what relacc took from an engine and what the file has that relacc
does not evaluate are part of the result. Where MuJoCo (or any engine) refuses the file, the others are still
compared with relacc's reading, and the refusal is one line of the result.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from relacc.core.conventions import MODEL_QUANTITIES
from relacc.engines import ENGINES, MESH_ENGINE, adapter_module, judges, readings, traits
from relacc.engines import load as load_adapter
from relacc.engines.contain import Probe
from relacc.errors import EngineError, ModelError
from relacc.files import regular_file
from relacc.limits import require_comparable
from relacc.reading import read_moving
from relacc.reading.read import format_of
from relacc.validation.robots.agreement import away_from_lock, compare_dynamics, lock_note, padded, states_at
from relacc.validation.robots.audit import Item, Scales, differences, inertia_slack, merge
from relacc.validation.robots.causes import READINGS, Cause, CauseKind
from relacc.validation.robots.reading import BACKEND, structure
from relacc.validation.robots.referee import referee, voters
from relacc.validation.robots.tree import TreeRobot

if TYPE_CHECKING:
    from relacc.core.tree import Tree
    from relacc.engines.base import Adapter

URDF_CAUSE = "the URDF (Pinocchio's input) and the MJCF describe this element differently"

REFERENCE = "relacc"
"""The evaluator every row is measured against: relacc's own reading, case 2."""


@dataclass(frozen=True)
class EngineReport:
    """What one evaluator made of the file: read or not (``error``), its sizes, its parser's warnings."""

    name: str
    loaded: bool
    nq: int | None = None
    nv: int | None = None
    error: str | None = None
    warnings: tuple[str, ...] = ()

    def as_json(self) -> dict:
        return {"loaded": self.loaded, "nq": self.nq, "nv": self.nv, "error": self.error,
                "warnings": list(self.warnings)}


@dataclass(frozen=True)
class RobotComparison:
    """The result of :func:`compare`.

    Attributes:
        model, urdf: the files. engines: ``{name: EngineReport}``, relacc's reading first.
        audit: :class:`relacc.validation.robots.audit.Item` rows, one per element that differs, every reading's
            value (relacc's, then each engine's), the cause and the place in the file.
        dynamics: ``{quantity: {evaluator: Comparison}}`` against relacc's case 2: each engine, and relacc's cases 1
            and 3 as ``relacc (case 1)``, ``relacc (case 3)``.
        n_states, seed: the random states (plus the reference configuration, state 0).
        referee: one :class:`relacc.validation.referee.Verdict` per quantity with a disagreement.
        geometry: what each evaluator made of the model at the reference configuration (the page's drawing).
        findings: :class:`relacc.reading.Finding` per body of the file that is not physical.
        taken: ``{body: what relacc took from an engine}``. unevaluated, notes: relacc's reading's lines.
    """

    model: str
    urdf: str | None
    engines: dict
    audit: list = field(default_factory=list)
    dynamics: dict = field(default_factory=dict)
    n_states: int = 0
    seed: int = 0
    referee: list = field(default_factory=list)
    geometry: dict = field(default_factory=dict)
    findings: tuple = ()
    taken: dict = field(default_factory=dict)
    unevaluated: tuple = ()
    notes: tuple = ()

    @property
    def agree(self) -> bool:
        """No audit difference, no finding about the file, every dynamics quantity within tolerance."""
        return (not self.audit and not self.findings
                and all(r.passed for rows in self.dynamics.values() for r in rows.values()))

    @property
    def compared(self) -> list[str]:
        """The evaluators that took part: relacc's reading and each engine that read the file, shares at least one of
        its speeds and evaluated it (at least one engine, or :func:`compare` raises)."""
        return [name for name, e in self.engines.items() if e.loaded]

    @property
    def exit_code(self) -> int:
        return 0 if self.agree else 1

    def as_json(self) -> dict:
        dynamics = {}
        for quantity, rows in self.dynamics.items():
            worst = max(rows.values(), key=lambda r: r.max_ratio)
            dynamics[quantity] = {"max_error": _finite(worst.max_error), "tolerance": worst.tolerance,
                                  "ok": all(r.passed for r in rows.values()),
                                  "engines": {e: r.as_row() for e, r in rows.items()}}
        return {"model": self.model, "urdf": self.urdf, "reference": REFERENCE, "compared": self.compared,
                "engines": {k: e.as_json() for k, e in self.engines.items()},
                "audit": [i.as_json() for i in self.audit], "dynamics": dynamics, "states": self.n_states,
                "seed": self.seed, "referee": [v.as_json() for v in self.referee], "agree": self.agree,
                "findings": [f.as_json() for f in self.findings], "taken": dict(self.taken),
                "not_evaluated": list(self.unevaluated), "notes": list(self.notes), "geometry": self.geometry}


def verdict_line(data: dict) -> str:
    """The comparison's last line: its verdict in one sentence."""
    absent = [name for name, e in data["engines"].items() if not e["loaded"]]
    took = ", ".join(data["compared"])
    if not data["agree"]:
        parts = []
        if data["audit"]:
            parts.append(f"{len(data['audit'])} audit difference{'s' if len(data['audit']) != 1 else ''}")
        bad = sum(not r["ok"] for row in data["dynamics"].values() for r in row["engines"].values())
        if bad:
            parts.append(f"{bad} dynamics row{'s' if bad != 1 else ''} outside tolerance")
        if data["findings"]:
            parts.append(f"{len(data['findings'])} finding{'s' if len(data['findings']) != 1 else ''} about the file")
        return f"DISAGREE (exit 1): {', '.join(parts)}"
    if not absent:
        return "every engine reads the file as relacc does and the dynamics agree"
    return (f"every engine that took part ({took}) reads the file as relacc does and the dynamics agree; "
            f"{', '.join(absent)} did not take part (see above)")


def _one_line(engine: str, what: str, exc: BaseException) -> str:
    """An engine's failure as one line: the engine, what failed, the exception's type and message."""
    return f"{engine} {what}: {type(exc).__name__}: {' '.join(str(exc).split())}"


def _finite(x: float) -> float | None:
    """JSON has no infinity: an infinite error or difference is written ``null`` (the row's cause says why)."""
    return x if np.isfinite(x) else None


def load_robot(engine: str, path: str | os.PathLike, tree: Tree, urdf: str | os.PathLike | None = None) -> Adapter:
    """``path`` in one engine, matched to ``tree`` (relacc's reading; Pinocchio: from ``urdf`` when given).

    Raises:
        ModelError: the engine cannot read the file. EngineError: an unknown or missing engine.
    """
    options = {"urdf": urdf} if traits(engine).own_urdf and urdf is not None else {}
    return load_adapter(engine, path, tree, **options)


def compare(model: str | os.PathLike, *, urdf: str | os.PathLike | None = None, engines: Sequence[str] | None = None,
            n_states: int = 20, seed: int = 0) -> RobotComparison:
    """Compare every engine's reading of ``model`` (an MJCF or a URDF) with relacc's own (module docstring).

    Args:
        urdf: a URDF of the same robot for Pinocchio (links named as the MJCF's bodies, joints as its joints);
            when ``model`` itself is a URDF, Pinocchio reads it by its URDF parser.
        engines: among :data:`relacc.engines.ENGINES` (default: :func:`relacc.engines.judges`, those installed that
            read the file's format and take its inertias from it; an engine named that does not read the format is
            reported as not taking part).
        n_states: random states besides the reference configuration; seed: their seed.

    Raises:
        ModelError: relacc cannot read the file, nothing in it moves, or no engine takes part (the messages name the
            file, the element and each engine's reason). EngineError: an unknown or missing engine.
    """
    names = list(judges(format_of(model) or "")) if engines is None else list(engines)
    for name in names:
        if name not in ENGINES:
            raise EngineError(f"unknown engine {name!r} for compare: accepted are {', '.join(ENGINES)}")
    if urdf is not None:
        regular_file(urdf, ModelError, "model file")
    reading = read_moving(model, "there are no dynamics to compare")
    require_comparable(reading.tree, n_states, "comparing")
    if urdf is None and format_of(model) == "urdf":
        urdf = model
    reference = TreeRobot(reading, 2)
    reports = {REFERENCE: EngineReport(REFERENCE, True, reading.tree.nq_in(2), reading.tree.nv,
                                       warnings=tuple(reading.notes))}
    robots, unshared = _load(model, names, reading, urdf, reports)
    other_file = urdf is not None and Path(urdf).resolve() != Path(model).resolve()
    states = reference.states(n_states, seed)
    scales = Scales.of(reference.structure)
    audits, dynamics = [], {q: {} for q in MODEL_QUANTITIES}
    for robot in unshared:  # the user's URDF describes another robot: what differs, element by element
        audits.append(_audit(reading, reference, robot, scales, URDF_CAUSE))
    for robot in list(robots):
        from_urdf = traits(robot.engine).own_urdf and urdf is not None
        memo: dict = {}  # the causes' readings and comparisons, made once for all of this engine's rows
        try:
            items = _audit(reading, reference, robot, scales, URDF_CAUSE if other_file and from_urdf else None)
            rows = compare_dynamics(reference, robot, states)
            for quantity, row in rows.items():
                cause = Cause("", "") if row.passed else _dynamics_cause(quantity, row, reading, reference, robot,
                                                                         states, items, memo)
                if other_file and from_urdf and items and not cause.explained:
                    cause = Cause(CauseKind.URDF,
                                  "the URDF and the MJCF describe the robot differently (see the audit)")
                dynamics[quantity][robot.engine] = replace(row, cause=str(cause), cause_kind=cause.kind)
        except (Exception, SystemExit) as exc:  # an engine that fails to evaluate takes no part, and says why
            reports[robot.engine] = EngineReport(robot.engine, False, robot.structure.nq, robot.structure.nv,
                                                 error=_one_line(robot.engine, "fails to evaluate it", exc),
                                                 warnings=tuple(robot.warnings))
            robots.remove(robot)
            for rows_ in dynamics.values():
                rows_.pop(robot.engine, None)
            continue
        audits.append(items)
    _at_least_one(model, reports, robots)
    said: list[str] = []
    for case in (1, 3):  # relacc's own evaluation in the other cases, against its case 2
        evaluator, memo = TreeRobot(reading, case), {}
        keep = away_from_lock(reading.tree, states, case)
        if not keep.all():
            said.append(lock_note(keep))
            if not keep.any():
                continue
        at = states_at(states, keep)
        for quantity, row in compare_dynamics(reference, evaluator, at).items():
            cause = Cause("", "") if row.passed else _dynamics_cause(quantity, row, reading, reference, evaluator,
                                                                     at, memo=memo) if row.singular else \
                Cause(CauseKind.NOT_EXPLAINED, "relacc's case differs from its case 2 on its own reading",
                      reading.source)
            row = padded(row, keep)
            dynamics[quantity][evaluator.engine] = replace(row, case=case, cause=str(cause), cause_kind=cause.kind)
    verdicts = referee(voters(reference, robots, states, reading), states, dynamics, reading)
    geometry = {r.engine: _geometry(r.structure) for r in [reference, *robots]}
    findings = tuple(reading.findings) + _massless_speeds(reading, reference, states)
    return RobotComparison(str(model), None if urdf is None or urdf == model else str(urdf), reports, merge(audits),
                           {q: r for q, r in dynamics.items() if r}, n_states, seed, verdicts, geometry,
                           findings, dict(reading.taken), tuple(reading.unevaluated),
                           tuple(reading.notes) + tuple(said))


def _massless_speeds(reading, reference, states) -> tuple:
    """A finding per joint whose speed moves no mass or inertia (its row of relacc's mass matrix is zero at the
    reference configuration): forward dynamics is then undefined in every reading of the file."""
    from relacc.reading import Finding
    from relacc.validation.robots.agreement import inertialess

    tree = reading.tree
    M = reference.dynamics(states.q[0], np.zeros(tree.nv)).M
    out = []
    for name in inertialess(reference, M, np.arange(tree.nv)):
        joint, _, body = name.partition(" (body ")
        body = body.rstrip(")")
        b = tree.body(body)
        moved = sum(tree.bodies[k].mass for k in _subtree(tree, b))
        what = ("the mass it moves lies on its axis, with no inertia about it" if moved > 0 else
                "no body it moves has mass or inertia")
        out.append(Finding(body, "a joint that moves no mass", f"joint {joint}: {what} (its row of the mass matrix is "
                           "zero): its acceleration is undefined", reading.place("joint", joint)))
    return tuple(out)


def _subtree(tree, b: int) -> list[int]:
    """Body ``b`` and every body below it (bodies come after their parents)."""
    inside = {b}
    for k in range(b + 1, tree.nb):
        if tree.bodies[k].parent in inside:
            inside.add(k)
    return sorted(inside)


def _load(model, names, reading, urdf, reports) -> tuple[list, list]:
    """``(robots, unshared)``: each engine's adapter matched to relacc's reading (loaded first in a probe process, so
    that a C++ abort ends only the probe; the probes of all engines run at once, :class:`relacc.engines.contain.Probe`),
    and those that read a user's URDF but share no speed with it."""
    robots, unshared, probes = [], [], {}
    try:
        for name in names:  # every engine's load probed at once, each judged before this process loads it
            try:
                adapter_module(name)  # imported here once, not in the probe
            except (Exception, SystemExit) as exc:  # whatever an engine raises is that engine not taking part
                reports[name] = EngineReport(name, False, error=_one_line(name, "cannot load it", exc))
                continue
            probes[name] = Probe(f"{model}: {name} cannot load it",
                                 lambda name=name: load_robot(name, model, reading.tree, urdf))
        for name, probe in probes.items():
            _load_one(name, probe, model, reading, urdf, reports, robots, unshared)
    finally:
        for probe in probes.values():
            probe.stop()  # those not judged (an interrupt)
    return robots, unshared


def _load_one(name, probe, model, reading, urdf, reports, robots, unshared) -> None:
    """Engine ``name`` judged by its probe, then loaded here: into ``robots``, or ``unshared``, and ``reports``."""
    try:
        probe.survived()
        robot = load_robot(name, model, reading.tree, urdf)
    except ModelError as exc:
        reports[name] = EngineReport(name, False, error=str(exc))
        return
    except (Exception, SystemExit) as exc:  # whatever an engine raises is that engine not taking part
        reports[name] = EngineReport(name, False, error=_one_line(name, "cannot load it", exc))
        return
    if not len(robot.dofs):
        reports[name] = EngineReport(name, False, robot.structure.nq, robot.structure.nv,
                                     error=f"{name} shares no speed with relacc's reading: it read nq "
                                           f"{robot.structure.nq}, nv {robot.structure.nv} and none of its "
                                           "joints is one of the file's", warnings=tuple(robot.warnings))
        if traits(name).own_urdf and urdf is not None and Path(urdf).resolve() != Path(model).resolve():
            unshared.append(robot)
        return
    robots.append(robot)
    reports[name] = EngineReport(name, True, robot.structure.nq, robot.structure.nv, warnings=tuple(robot.warnings))


def _at_least_one(model, reports, robots) -> None:
    """A comparison needs relacc's reading and at least one engine over at least one shared speed.

    Raises:
        ModelError: no engine took part; the message says, engine by engine, why.
    """
    if not robots:
        why = "; ".join(r.error for r in reports.values() if r.error) or "no engine is installed"
        raise ModelError(f"{model}: nothing to compare relacc's reading with: {why}")


def _audit(reading, reference, robot, scales, unexplained: str | None) -> list[Item]:
    """``robot``'s audit against relacc's reading, each difference with its cause
    (:mod:`relacc.validation.robots.causes`): a reading of :data:`relacc.validation.robots.causes.READINGS` (relacc's
    reader reading the file as the engine does) that makes it disappear, applied one after the other and kept when
    it does, over again while one is kept (one may need another first: a mesh's unit inertia before a default's
    mass, in dm_control's Jaco arm); ``unexplained`` (a user's URDF); what relacc took from the engine; a finding
    about the file; else not explained, with the element's place in the file."""
    engine = robot.engine
    sc = scales.larger(Scales.of(robot.structure))
    slack = inertia_slack(robot, reading)
    items = differences(reference.structure, robot.structure, REFERENCE, engine, sc, slack)
    if not items:
        return []
    causes: dict = {}
    left = {i.key for i in items}
    current = reading

    def attempt(known) -> bool:
        """Apply ``known`` to the current reading; keep it where it makes a difference disappear."""
        nonlocal current, left
        try:
            candidate = known.change(current)
        except ModelError:
            return False
        after = {i.key for i in differences(structure(candidate), robot.structure, REFERENCE, engine, sc, slack)}
        gone = left - after
        for k in gone:
            causes[k] = Cause(CauseKind.EXPLAINED, known.text)
        if gone:
            current, left = candidate, after
        return bool(gone)

    unused = list(READINGS.get(engine, ()))
    while left and unused:  # again over those left, after each pass that kept one: one may need another first
        kept = [known for known in unused if left and known.applies(current) and attempt(known)]
        unused = [known for known in unused if known not in kept]
        if not kept:
            break
    out = []
    for item in items:
        cause = causes.get(item.key) or _fallback(item, reading, engine, unexplained)
        out.append(replace(item, cause=str(cause), kind=cause.kind, place=cause.place or _place(item, reading)))
    masses = [i for i in out if i.subject[0] == "link" and i.item in ("mass (kg)", "body missing")]
    if masses and all(i.kind != CauseKind.NOT_EXPLAINED for i in masses):  # the total mass follows its links' masses
        from relacc.validation.robots.causes import KINDS

        kind = max((i.kind for i in masses), key=KINDS.index)  # the least explained of theirs
        first = next(i for i in masses if i.kind == kind)
        cause = first.cause if kind in (CauseKind.TAKEN, CauseKind.URDF) else (
            "the sum of the links' masses, each explained above: " + "; ".join(dict.fromkeys(i.cause for i in masses)))
        out = [replace(i, cause=cause, kind=kind)
               if i.item == "total mass (kg)" and i.kind == CauseKind.NOT_EXPLAINED else i for i in out]
    return out


def _place(item: Item, reading) -> str:
    """The element of the file an audit item comes from (``file:line``), or the file."""
    kind, name = item.subject
    if kind == "link":
        return reading.places.get(("inertial", name)) or reading.place("body", name)
    if item.item.startswith("gravity"):
        return reading.place("option", "gravity")
    return reading.place(kind, name) if kind in ("joint", "body") else reading.source


def _fallback(item: Item, reading, engine: str, unexplained: str | None) -> Cause:
    """A difference no reading reproduces: a user's URDF, what relacc took, a finding about the file, or not
    explained."""
    if unexplained:
        return Cause(CauseKind.URDF, unexplained)
    kind, name = item.subject
    members = _link_bodies(reading, name) if kind == "link" else []
    taken = [b for b in members if b in reading.taken]
    if taken:
        source = traits(MESH_ENGINE).label
        what = f"relacc took the mass properties of {', '.join(taken)} from {source} ({reading.taken[taken[0]]})"
        return Cause(CauseKind.TAKEN, f"{what}: it cannot judge {source} there" if engine == MESH_ENGINE else
                     f"{what}: {engine}'s differ from {source}'s, and relacc, which does not compute meshes, cannot "
                     "say which reads the mesh right")
    found = [f for f in reading.findings if f.body in members]
    if found:
        return Cause(CauseKind.FINDING, f"the file gives body {found[0].body} {found[0].condition} "
                                f"({found[0].numbers}): each engine reads that its own way", found[0].place)
    if item.item == "joint type":
        return Cause(CauseKind.NOT_EXPLAINED, f"{engine} maps this joint to another type", _place(item, reading))
    return Cause(CauseKind.NOT_EXPLAINED,
                 f"not explained by a known difference between {engine}'s reading of the file and the format's",
                 _place(item, reading))


def _link_bodies(reading, name: str) -> list[str]:
    from relacc.validation.robots.reading import groups

    tree = reading.tree
    for head, members in groups(tree).items():
        if tree.bodies[head].name == name:
            return [tree.bodies[b].name for b in members]
    return [name]


EXPLAINED = 1e-6
"""A cause explains a dynamics disagreement when, applied, it leaves the quantity within tolerance or its largest
absolute difference at most this fraction of what it was (the residue of readings that need MuJoCo's minimum
body mass, 1e-14 kg, against an engine's zero)."""


def _explained(again: dict, quantity: str, before) -> bool:
    row = again.get(quantity)
    if row is None:
        return False
    return row.passed or (np.isfinite(before.max_difference)
                          and row.max_difference <= EXPLAINED * before.max_difference)


def _dynamics_cause(quantity, before, reading, reference, robot, states, items=(), memo: dict | None = None) -> Cause:
    """Why ``quantity`` disagrees: the engine's readings of the file (relacc's reader reading it the engine's way,
    every reading that applies, cumulatively), a known difference in the engine's algorithms (alone, or with those
    readings), MuJoCo's own ``mj_jacDot``, a singular mass matrix, a finding about the file or what relacc took (the
    engine's audit ``items`` all of those kinds); else not explained.

    ``memo``: one dict per evaluator for all its rows: each reading and each comparison under it is made once and
    judged for every quantity that disagrees (a comparison gives every quantity at once)."""
    from relacc.validation.robots.routines import EXPLAINS, routine_cause

    memo = {} if memo is None else memo

    def once(key, make):
        if key not in memo:
            memo[key] = make()
        return memo[key]

    engine = robot.engine
    current, texts, moving = once("read", lambda: _read_as_engine(reading, engine))
    read_as = once("read_as", lambda: TreeRobot(current, 2, reading.tree)) if texts else None
    if read_as is not None and _explained(once("read_as rows", lambda: compare_dynamics(read_as, robot, states)),
                                          quantity, before):
        return Cause(CauseKind.EXPLAINED, "explained by the audit: " + "; ".join(moving or texts))
    for k, known in enumerate(readings(engine)):
        text = known.text
        fixed = once(("fixed", k), lambda: _changed(known, robot))  # noqa: B023 - called at once
        if fixed is None:
            continue
        if _explained(once(("fixed rows", k), lambda: compare_dynamics(reference, fixed, states)),  # noqa: B023
                      quantity, before):
            return Cause(CauseKind.EXPLAINED, text)
        if read_as is not None and _explained(
                once(("fixed read_as rows", k), lambda: compare_dynamics(read_as, fixed, states)),  # noqa: B023
                quantity, before):
            return Cause(CauseKind.EXPLAINED, text + "; and the audit: " + "; ".join(texts))
    text = once("routine", lambda: routine_cause(reference, robot, states)) if quantity in EXPLAINS else ""
    if text:
        return Cause(CauseKind.EXPLAINED, text)
    if before.singular:
        return Cause(CauseKind.SINGULAR, "forward dynamics undefined: " + "; ".join(
            f"{e}'s mass matrix over the shared speeds is singular (no inertia moves with "
            f"{', '.join(joints) or 'a combination of speeds'})" for e, joints in before.singular.items()))
    for b, base in enumerate(([reading, current] if texts else [reading]) if reading.findings else []):
        as_engine = once(("findings", b), lambda: findings_as_read(base, robot))  # noqa: B023 - called at once
        if as_engine is not None and _explained(once(("findings rows", b), lambda: compare_dynamics(  # noqa: B023
                TreeRobot(as_engine, 2, reading.tree), robot, states)), quantity, before):
            f = reading.findings[0]
            return Cause(CauseKind.FINDING,
                         f"the file has bodies that are not physical (first: body {f.body}, {f.condition})"
                         f": read as {engine} reads them, the dynamics agree"
                         + ("" if base is reading else " (with its known readings: " + "; ".join(texts) + ")"),
                         f.place)
    kinds = {i.kind for i in items}
    source = traits(MESH_ENGINE).label
    judged_there = {CauseKind.TAKEN, CauseKind.EXPLAINED, CauseKind.FINDING}
    if reading.taken and (engine == MESH_ENGINE or (CauseKind.TAKEN in kinds and kinds <= judged_there)):
        return Cause(CauseKind.TAKEN, f"relacc took the mass properties of {', '.join(reading.taken)} from {source}: "
                     + (f"it cannot judge {source} there" if engine == MESH_ENGINE else
                        f"the audit's differences of {engine} there are the only ones not explained"))
    return Cause(CauseKind.NOT_EXPLAINED, f"not explained by a known difference of {engine}"
                 + (f" (its known readings of the file were applied: {'; '.join(texts)})" if texts else ""),
                 reading.source)


def _read_as_engine(reading, engine: str) -> tuple:
    """``(reading, texts, moving)``: the file read as ``engine`` reads it (every known reading of
    :data:`relacc.validation.robots.causes.READINGS` that applies, one after the other), those readings' texts, and
    the texts of those among them that change the tree's dynamics (a dropped damping, which the compared dynamics
    leave out, changes none: it never explains a dynamics row)."""
    current, texts, moving = reading, [], []
    for known in READINGS.get(engine, ()):
        if known.applies(current):
            try:
                changed = known.change(current)
            except ModelError:
                continue
            texts.append(known.text)
            if _dynamics_of(changed.tree) != _dynamics_of(current.tree):
                moving.append(known.text)
            current = changed
    return current, texts, moving


def _dynamics_of(tree) -> tuple:
    """What of a tree its rigid-body dynamics depend on: each body's place, mass properties and joints (their kinds,
    axes, anchors, reference positions and armature) and gravity, as plain values to compare."""
    def values(a) -> tuple:
        return () if a is None else tuple(np.asarray(a, dtype=float).ravel().tolist())

    return values(tree.gravity), tuple(
        (b.name, b.parent, values(b.pos), values(b.quat), float(b.mass), values(b.com), values(b.inertia),
         tuple((j.name, j.type, values(j.pos), values(j.axis), float(j.ref), values(j.armature)) for j in b.joints))
        for b in tree.bodies)


def _changed(known, robot):
    """``robot`` with a known difference of its engine's algorithms applied, or None where it does not apply."""
    if not known.applies(robot):
        return None
    try:
        return known.change(robot)
    except (ModelError, EngineError):
        return None


def findings_as_read(reading, robot):
    """``reading`` with each body of a finding (not physical) given the mass properties ``robot``'s engine read for it
    (its link's mass, mass centre and inertia, turned into the body's frame at the reference configuration): what a
    finding must reproduce before it is named as a dynamics row's cause (a body elsewhere being non-physical explains
    nothing). None where a finding body is not a link of its own in both readings, or the engine lacks it."""
    from relacc.core.tree import tree_kinematics
    from relacc.core.tree.coordinates import reference_q
    from relacc.engines.known import with_bodies

    tree = reading.tree
    theirs = {link.name: link for link in robot.structure.links}
    ours = {link.name: link for link in structure(reading).links}
    names = {f.body for f in reading.findings}
    if any(n not in theirs or n not in ours or ours[n].bodies != (n,) or theirs[n].bodies != (n,) for n in names):
        return None
    k = tree_kinematics(tree, 2, reference_q(tree, 2), np.zeros(tree.nv), backend=BACKEND)
    at = {body.name: b for b, body in enumerate(tree.bodies)}

    def as_engine(body):
        if body.name not in names:
            return None
        b, link = at[body.name], theirs[body.name]
        R = k.rotation[b]
        origin = k.position[b] - R @ body.com
        inertia = R.T @ link.inertia @ R
        return replace(body, mass=float(link.mass), com=R.T @ (link.com - origin), inertia=0.5 * (inertia + inertia.T),
                       physical=False)

    return with_bodies(reading, as_engine)


def _geometry(structure_) -> dict:
    """Plain data of a :class:`relacc.engines.base.Structure`'s joints and links (``RobotComparison.geometry``)."""
    listed = lambda x: None if x is None else [float(c) for c in x]  # noqa: E731
    return {"joints": [{"name": j.name, "type": j.type, "anchor": listed(j.anchor), "axis": listed(j.axis)}
                       for j in structure_.joints],
            "links": [{"name": link.name, "mass": float(link.mass), "com": listed(link.com)}
                      for link in structure_.links]}
