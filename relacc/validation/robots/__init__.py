"""``relacc compare``: does each engine see the same robot as MuJoCo, and do their dynamics agree?

MuJoCo reads the MJCF natively and is the reference; Pinocchio (its MJCF parser, or a URDF of the
same robot) and Drake (its MJCF parser) are compared with it:

1. the **audit** (:mod:`relacc.validation.robots.audit`): structure, inertias, armature, damping,
   gravity, each difference with the element it comes from and its cause, reproduced by recompiling
   the model in MuJoCo the engine's way;
2. the **dynamics** (:mod:`relacc.validation.robots.agreement`) at the reference configuration and at
   random states, over the speeds both engines have, in MuJoCo's coordinates through each engine's
   speed map (a free joint's speeds: the note's case 2 in MuJoCo, case 1 in Drake, neither in Pinocchio). A
   disagreement gets a cause when the audit's causes, or a known difference in the engine's
   algorithms, make it disappear.

:func:`compare` returns a :class:`RobotComparison`; ``as_json()`` is the command's JSON summary.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from relacc.core.tolerances import robot_tolerance
from relacc.engines import adapter_module, installed, readings
from relacc.engines import load as load_adapter
from relacc.engines.contain import survives
from relacc.errors import EngineError, ModelError
from relacc.validation.robots.agreement import QUANTITIES, random_states
from relacc.validation.robots.agreement import compare as compare_dynamics
from relacc.validation.robots.audit import Item, Scales, explain, merge
from relacc.validation.robots.tree import TreeRobot

URDF_CAUSE = "the URDF (Pinocchio's input) and the MJCF (MuJoCo's) describe this element differently"

OTHERS = ("pinocchio", "drake")
"""Engines compared with MuJoCo, in report order."""


@dataclass(frozen=True)
class EngineReport:
    """What one engine made of the file: loaded or not (``error``), its sizes, its parser's warnings."""

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
        model, urdf: the files. engines: ``{name: EngineReport}``, MuJoCo first.
        audit: :class:`relacc.validation.robots.audit.Item` rows, one per difference over the engines.
        dynamics: ``{quantity: {engine: {"max_error", "tolerance", "ok", "state", "cause"}}}``; relacc's own tree
            appears as the evaluators ``relacc (case 1)``, ``relacc (case 2)``, ``relacc (case 3)``.
        n_states, seed: the random states (plus the reference configuration, state 0).
        referee: one :class:`Verdict` per quantity with a disagreement: who is the odd one out.
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
    """``{engine: {"joints": [{"name", "type", "anchor", "axis"}], "links": [{"name", "mass", "com"}]}}``: what each
    engine that took part made of the model at the reference configuration (MuJoCo's ``qpos0``): joint anchors,
    unit axes (hinge, slide; None otherwise) and link mass centres in world components (m), masses (kg)."""

    @property
    def agree(self) -> bool:
        """No audit difference and every dynamics quantity within tolerance for every engine."""
        return not self.audit and all(r.passed for rows in self.dynamics.values() for r in rows.values())

    @property
    def compared(self) -> list[str]:
        """The engines that took part: MuJoCo and each other engine that read the file, shares at least one of
        MuJoCo's speeds and evaluated it (at least two, or :func:`compare` raises)."""
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
        return {"model": self.model, "urdf": self.urdf, "compared": self.compared,
                "engines": {k: e.as_json() for k, e in self.engines.items()},
                "audit": [i.as_json() for i in self.audit], "dynamics": dynamics, "states": self.n_states,
                "seed": self.seed, "referee": [v.as_json() for v in self.referee], "agree": self.agree,
                "geometry": self.geometry}


def _one_line(engine: str, what: str, exc: BaseException) -> str:
    """An engine's failure as one line: the engine, what failed, the exception's type and message."""
    return f"{engine} {what}: {type(exc).__name__}: {' '.join(str(exc).split())}"


def _finite(x: float) -> float | None:
    """JSON has no infinity: an undefined or infinite error or difference is written ``null`` (the row's cause
    says why)."""
    return x if np.isfinite(x) else None


def _readings(engine: str, attribute: str):
    """An engine's readings table (``MJCF_READINGS`` or ``ENGINE_READINGS``, :func:`relacc.engines.readings`)."""
    mjcf, algorithms = readings(engine)
    return mjcf if attribute == "MJCF_READINGS" else algorithms


def load_robot(engine, path, reference, urdf=None):
    """``path`` in one engine, matched to MuJoCo's reading ``reference`` (an adapter; Pinocchio: from ``urdf`` when
    given).

    Raises:
        ModelError: the engine cannot read the file. EngineError: an unknown or missing engine.
    """
    options = {"urdf": urdf} if engine == "pinocchio" and urdf is not None else {}
    return load_adapter(engine, path, reference.reference, **options)


def compare(model, *, urdf=None, engines=None, n_states: int = 20, seed: int = 0) -> RobotComparison:
    """Compare every engine's reading of ``model`` (MJCF, or a URDF MuJoCo reads) with MuJoCo's.

    Args:
        urdf: a URDF of the same robot for Pinocchio (links named as the MJCF's bodies, joints as its joints);
            when ``model`` itself is a URDF, Pinocchio reads it by its URDF parser.
        engines: among :data:`OTHERS` (default: those installed).
        n_states: random states besides the reference configuration; seed: their seed.

    Raises:
        ModelError: MuJoCo cannot read or compile the file, or no other engine can (messages name the
            file and the element). EngineError: an unknown or missing engine.
    """
    names = [e for e in OTHERS if installed(e)] if engines is None else list(engines)
    for name in names:
        if name not in OTHERS:
            raise EngineError(f"unknown engine {name!r} for compare: accepted are {', '.join(OTHERS)}")
    if urdf is not None and not Path(urdf).is_file():
        raise ModelError(f"{urdf}: no such file")
    reference = load_adapter("mujoco", model)
    if reference.model.nv == 0:
        raise ModelError(f"{model}: MuJoCo reads no joint in it: nothing moves, so there are no dynamics to compare")
    if urdf is None and Path(model).suffix.lower() == ".urdf":  # MuJoCo reads URDF too: Pinocchio by its URDF parser
        urdf = model
    reports = {"mujoco": EngineReport("mujoco", True, reference.model.nq, reference.model.nv,
                                      warnings=tuple(reference.warnings))}
    robots, unshared = [], []
    for name in names:
        try:
            adapter_module(name)  # imported here once, not in the probe
            survives(f"{model}: {name} cannot load it", lambda: load_robot(name, model, reference, urdf))  # noqa: B023
            robot = load_robot(name, model, reference, urdf)
        except ModelError as exc:
            reports[name] = EngineReport(name, False, error=str(exc))
            continue
        except (Exception, SystemExit) as exc:  # whatever an engine raises is that engine not loading
            reports[name] = EngineReport(name, False, error=_one_line(name, "cannot load it", exc))
            continue
        if not len(robot.dofs):  # read, but none of its joints is one of MuJoCo's (MuJoCo has some: checked above)
            reports[name] = EngineReport(name, False, robot.structure.nq, robot.structure.nv,
                                         error=f"{name} shares no speed with MuJoCo: it read nq "
                                               f"{robot.structure.nq}, nv {robot.structure.nv} and none of its "
                                               "joints is one of MuJoCo's", warnings=tuple(robot.warnings))
            if name == "pinocchio" and urdf is not None and Path(urdf).resolve() != Path(model).resolve():
                unshared.append(robot)  # the user's URDF describes another robot: that is a finding, audited
            continue
        robots.append(robot)
        reports[name] = EngineReport(name, True, robot.structure.nq, robot.structure.nv,
                                     warnings=tuple(robot.warnings))
    _at_least_two(model, reports, robots)
    scales = Scales.of(reference.structure)
    states = random_states(reference, n_states, seed)
    audits, dynamics = [], {q: {} for q in QUANTITIES}
    for robot in unshared:  # what differs, element by element, though no dynamics can be compared
        audits.append(explain(reference, robot, (), scales, URDF_CAUSE)[0])
    for robot in robots:
        from_urdf = robot.engine == "pinocchio" and urdf is not None
        other_file = from_urdf and Path(urdf).resolve() != Path(model).resolve()  # a URDF beside an MJCF
        readings = () if from_urdf else getattr(robot, "mjcf_readings", _readings(robot.engine, "MJCF_READINGS"))
        try:
            items, explained, applied = explain(reference, robot, readings, scales,
                                                URDF_CAUSE if other_file else None)
            rows = compare_dynamics(reference, robot, states)
        except (Exception, SystemExit) as exc:  # an engine that fails to evaluate takes no part, and says why
            reports[robot.engine] = EngineReport(robot.engine, False, robot.structure.nq, robot.structure.nv,
                                                 error=_one_line(robot.engine, "fails to evaluate it", exc),
                                                 warnings=tuple(robot.warnings))
            continue
        audits.append(items)
        for quantity, row in rows.items():
            cause = "" if row.passed else _dynamics_cause(quantity, row, reference, robot, explained, applied,
                                                          readings, n_states, seed)
            if other_file and items and cause.startswith("not explained"):
                cause = "the URDF and the MJCF describe the robot differently (see the audit)"
            dynamics[quantity][robot.engine] = replace(row, cause=cause)
    tree_rows = {}
    for case in (1, 2, 3) if reference.model.nbody > 1 else ():  # relacc's own evaluation, in each case
        evaluator = TreeRobot(reference, case)
        for quantity, row in compare_dynamics(reference, evaluator, states).items():
            row = replace(row, case=case, cause="" if row.passed else _mujoco_cause(quantity, reference, evaluator,
                                                                                     states))
            dynamics[quantity][evaluator.engine] = row
            tree_rows.setdefault(quantity, {})[case] = row
    verdicts = []
    robots = [r for r in robots if reports[r.engine].loaded]
    _at_least_two(model, reports, robots)
    if reference.model.nbody > 1:
        voters = _voters(robots, reference, states)
        verdicts = _referee(reference, voters, states, dynamics)
        _mujoco_side_causes(dynamics, voters, tree_rows)
    geometry = {r.engine: _geometry(r.structure) for r in [reference, *robots]}
    return RobotComparison(str(model), None if urdf is None or urdf == model else str(urdf), reports, merge(audits),
                           {q: r for q, r in dynamics.items() if r}, n_states, seed, verdicts, geometry)


def _geometry(structure) -> dict:
    """Plain data of a :class:`relacc.engines.base.Structure`'s joints and links (see ``RobotComparison.geometry``)."""
    listed = lambda x: None if x is None else [float(c) for c in x]  # noqa: E731
    return {"joints": [{"name": j.name, "type": j.type, "anchor": listed(j.anchor), "axis": listed(j.axis)}
                       for j in structure.joints],
            "links": [{"name": link.name, "mass": float(link.mass), "com": listed(link.com)}
                      for link in structure.links]}


def _at_least_two(model, reports, robots) -> None:
    """A comparison needs MuJoCo and at least one other engine over at least one shared speed.

    Raises:
        ModelError: no other engine took part; the message says, engine by engine, why.
    """
    if not robots:
        why = "; ".join(f"{r.error}" for r in reports.values() if r.error) or "no other engine is installed"
        raise ModelError(f"{model}: nothing to compare MuJoCo with: {why}")


@dataclass(frozen=True)
class Verdict:
    """The referee on one quantity: MuJoCo and relacc's tree are two independent evaluations of the same reading;
    each other engine stands with one, both or neither.

    ``odd_ones_out``: the evaluators a majority disagrees with (empty on an even split); ``agreeing``: the side
    that agrees; ``split``: the two sides when they are equally many; ``pairs``: ``"a|b"`` to the worst normalized
    error over the tolerance (a pair agrees at <= 1)."""

    quantity: str
    odd_ones_out: tuple
    agreeing: tuple
    split: tuple
    pairs: dict
    voted_as: dict = field(default_factory=dict)
    """``{engine: why}``: engines that voted with a known difference of their algorithms removed."""

    def sentence(self) -> str:
        join = lambda names: ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else names[0]  # noqa: E731
        if self.split:
            return f"{self.quantity}: an even split, {join(self.split[0])} against {join(self.split[1])}"
        if not self.odd_ones_out:
            known = f" once {join(sorted(self.voted_as))}'s known difference is removed" if self.voted_as else ""
            return f"{self.quantity}: no odd one out: {join(self.agreeing)} agree{known}"
        odd = ", ".join(self.odd_ones_out)
        return f"{self.quantity}: the odd one{'s' if len(self.odd_ones_out) > 1 else ''} out: {odd}; " \
               f"{join(self.agreeing)} agree"

    def as_json(self) -> dict:
        return {"quantity": self.quantity, "odd_ones_out": list(self.odd_ones_out), "agreeing": list(self.agreeing),
                "split": [list(side) for side in self.split], "pairs": {k: _finite(v) for k, v in self.pairs.items()},
                "voted_as": dict(self.voted_as), "verdict": self.sentence()}


@dataclass
class _Voter:
    """An engine as the referee counts it: its rows against MuJoCo and against relacc's tree, and, when a known
    difference of its algorithms applies (its ``ENGINE_READINGS``), the engine rebuilt without it and why."""

    engine: str
    against_mujoco: dict
    against_tree: dict
    why: str = ""


def _voters(robots, reference, states) -> list:
    """Each engine's vote: rebuilt without a known difference of its algorithms where one applies (a Pinocchio
    composite joint's J_dot v), so that a known bug does not vote."""
    tree = TreeRobot(reference, 2)
    out = []
    for robot in robots:
        why, voter = "", robot
        for key, text, applies, rebuild in _readings(robot.engine, "ENGINE_READINGS"):
            if applies(robot):
                try:
                    voter, why = rebuild(robot), text
                except (ModelError, EngineError):
                    continue
        out.append(_Voter(robot.engine, compare_dynamics(reference, voter, states),
                          compare_dynamics(tree, voter, states), why))
    return out


def _mujoco_side_causes(dynamics, voters, tree_rows) -> None:
    """An engine row that differs from MuJoCo where relacc's tree does too, for a reproduced MuJoCo cause, and where
    the engine agrees with relacc's tree: the row's cause is MuJoCo's."""
    for quantity, rows in dynamics.items():
        mujoco = tree_rows.get(quantity, {}).get(2)
        if mujoco is None or mujoco.passed or mujoco.cause.startswith("not explained"):
            continue
        for v in voters:
            row, theirs = rows.get(v.engine), v.against_tree.get(quantity)
            if row is not None and not row.passed and theirs is not None and theirs.passed:
                rows[v.engine] = replace(row, cause=f"{mujoco.cause}; {v.engine} agrees with relacc's tree")


def _referee(reference, voters, states, dynamics) -> list:
    """A :class:`Verdict` for each quantity on which evaluators disagree.

    Each engine (a :class:`_Voter`) is compared with MuJoCo and with relacc's tree. If MuJoCo and relacc agree, the
    engines that disagree with them are the odd ones out. If they differ, the engines take sides: the side with more
    evaluators agrees, the other is odd; equal sides are a split.
    """
    tree = TreeRobot(reference, 2)
    verdicts = []
    for quantity, rows in dynamics.items():
        if all(r.passed for r in rows.values()) or tree.engine not in rows:
            continue
        ratio = lambda row: row.max_ratio  # noqa: E731
        pairs = {f"mujoco|{tree.engine}": ratio(rows[tree.engine])}
        sides = {"mujoco": ["mujoco"], "relacc": [tree.engine]}
        others, voted = [], {}
        present = [v for v in voters if v.engine in rows and quantity in v.against_tree]
        for v in present:
            if v.why:
                voted[v.engine] = v.why
            mine, theirs = v.against_mujoco[quantity], v.against_tree[quantity]
            pairs[f"mujoco|{v.engine}"], pairs[f"{v.engine}|{tree.engine}"] = ratio(mine), ratio(theirs)
            with_mujoco, with_tree = mine.passed, theirs.passed
            if with_mujoco and not with_tree:
                sides["mujoco"].append(v.engine)
            elif with_tree and not with_mujoco:
                sides["relacc"].append(v.engine)
            elif not (with_mujoco or with_tree):
                others.append(v.engine)
        if rows[tree.engine].passed:  # MuJoCo and relacc agree: every engine that does not is odd
            odd = tuple(v.engine for v in present if not v.against_mujoco[quantity].passed)
            agreeing = tuple(n for n in ["mujoco", *(v.engine for v in present), tree.engine] if n not in odd)
            verdicts.append(Verdict(quantity, odd, agreeing, (), pairs, voted))
            continue
        m, t = sides["mujoco"], sides["relacc"]
        if len(m) == len(t):
            verdicts.append(Verdict(quantity, tuple(others), (), (tuple(m), tuple(t)), pairs, voted))
        else:
            win, lose = (m, t) if len(m) > len(t) else (t, m)
            verdicts.append(Verdict(quantity, tuple(lose) + tuple(others), tuple(win), (), pairs, voted))
    return verdicts


MUJOCO_JACDOT = ("MuJoCo's mj_jacDot takes a ball joint's columns from the velocity of its whole body, so a slide "
                 "after a ball on the same body adds v_slide x omega_ball to J_dot v (relacc's finding): MuJoCo's own "
                 "acceleration routine (mj_rnePostConstraint) agrees with relacc's tree")


def _mujoco_cause(quantity, reference, evaluator, states) -> str:
    """Why relacc's tree and MuJoCo differ, reproduced: MuJoCo's other reading of the quantity (``J_dot v`` from its
    acceleration routine, ``mj_rnePostConstraint`` at zero rates, rather than ``mj_jacDot``) agrees with relacc."""
    if quantity in ("J_dot v", "classical acceleration"):
        from relacc.engines.base import com
        from relacc.validation.robots.agreement import CHUNK, point_terms, shared_links

        links = shared_links(reference.structure, evaluator.structure, 0.0)
        tol = robot_tolerance(len(reference.structure.links))
        worst = 0.0
        for start in range(0, len(states.q), CHUNK):  # batched, a chunk of states at a time (as compare_dynamics)
            q, u, udot = (x[start:start + CHUNK] for x in (states.q, states.u, states.udot))
            mine = evaluator.kinematics(q, u, udot, links)
            theirs = reference.points(q, u, np.zeros_like(u), [com(name) for name in links])
            for i, (v, a) in enumerate(zip(u, udot)):
                scale, _ = point_terms(mine.J[i], mine.position[i], v, a)  # J_dot v: MuJoCo's acceleration, zero rates
                x, y = mine.Jdot_v[i], theirs.acceleration[i]
                worst = max(worst, float((np.abs(x - y).max(axis=1) / np.maximum(scale, np.finfo(float).tiny)).max()))
        if worst <= tol:
            return MUJOCO_JACDOT if _ball_then_slide(reference.model) else (
                "MuJoCo's mj_jacDot differs from its own acceleration routine (mj_rnePostConstraint), which agrees "
                "with relacc's tree")
    return "not explained: relacc's tree and MuJoCo differ on MuJoCo's own reading of the model"


def _ball_then_slide(model) -> bool:
    """Whether a body of the model has a slide after a ball (MuJoCo's joint types 1 ball, 2 slide)."""
    for b in range(1, model.nbody):
        first = int(model.body_jntadr[b])
        kinds = [int(model.jnt_type[j]) for j in range(first, first + int(model.body_jntnum[b]))]
        if 1 in kinds and 2 in kinds[kinds.index(1) + 1:]:
            return True
    return False


EXPLAINED = 1e-6
"""A cause explains a dynamics disagreement when, applied, it leaves the quantity within tolerance or its largest
absolute difference at most this fraction of what it was (the residue of readings that need MuJoCo's minimum
body mass, 1e-14 kg, against an engine's zero)."""


def _explained(again: dict, quantity: str, before: dict) -> bool:
    row = again.get(quantity)
    if row is None:
        return False
    return row.passed or (np.isfinite(before.max_difference)
                          and row.max_difference <= EXPLAINED * before.max_difference)


def _dynamics_cause(quantity, before, reference, robot, explained, applied, readings, n_states, seed) -> str:
    """Why ``quantity`` disagrees: the audit's causes, or a known difference in the engine's algorithms."""
    texts = [text for key, text, _, _ in readings if key in applied]
    if applied:
        again = compare_dynamics(explained, robot, random_states(explained, n_states, seed))
        if _explained(again, quantity, before):
            return "explained by the audit: " + "; ".join(texts)
    for key, text, applies, rebuild in _readings(robot.engine, "ENGINE_READINGS"):
        if applies(robot):
            try:
                fixed = rebuild(robot)
            except (ModelError, EngineError):
                continue
            alone = compare_dynamics(reference, fixed, random_states(reference, n_states, seed))
            if _explained(alone, quantity, before):
                return text
            again = compare_dynamics(explained, fixed, random_states(explained, n_states, seed))
            if texts and _explained(again, quantity, before):
                return text + "; and the audit's causes: " + "; ".join(texts)
    if before.singular:
        return "forward dynamics undefined: " + "; ".join(
            f"{'MuJoCo' if engine == 'mujoco' else engine}'s mass matrix over the shared speeds is singular "
            f"(no inertia moves with {', '.join(joints) or 'a combination of speeds'})"
            for engine, joints in before.singular.items())
    return f"not explained by a known difference of {robot.engine}" + (
        f" (the audit's causes were applied: {'; '.join(texts)})" if texts else "")


__all__ = ["OTHERS", "EngineReport", "Item", "RobotComparison", "Verdict", "compare", "load_robot"]
