"""The model audit: what an engine made of a model file, against MuJoCo's reading of it, with causes.

Differences (:func:`differences`) are found element by element at the reference configuration:
degrees of freedom; joints missing or of another type, their axes and positions, armature and
damping; links (a moving body and the bodies welded to it) missing, their masses, centres of mass
and inertias (world components); the total mass; gravity. A value differs when it is off by more
than :func:`relacc.core.tolerances.robot_tolerance` times its scale (:class:`Scales`, from the
reference model: its total mass, its size, its largest inertia).

Causes are not guessed but reproduced (:func:`explain`): each engine module lists how its parser
reads MJCF differently from MuJoCo (``MJCF_READINGS``: e.g. Pinocchio ignores ``settotalmass``),
each as a change to the file's spec. MuJoCo recompiles the model with the changes that apply, one
at a time and cumulatively, and a change is the cause of the differences it makes disappear.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from relacc.core.tolerances import robot_tolerance
from relacc.errors import ModelError


@dataclass(frozen=True)
class Item:
    """One audit difference: ``item`` (what), ``where`` (the element), each engine's value, its cause."""

    item: str
    where: str
    values: dict = field(default_factory=dict)
    cause: str = ""

    @property
    def key(self) -> tuple[str, str]:
        return self.item, self.where

    def as_json(self) -> dict:
        return {"item": self.item, "where": self.where, **self.values, "cause": self.cause}


@dataclass(frozen=True)
class Scales:
    """The reference model's own scales: ``mass`` (kg, total), ``length`` (m, largest distance of a link's
    centre of mass or a joint from the world origin), ``inertia`` (kg m^2), ``tolerance`` (relative)."""

    mass: float
    length: float
    inertia: float
    tolerance: float

    @classmethod
    def of(cls, structure) -> "Scales":
        points = [np.linalg.norm(link.com) for link in structure.links]
        points += [np.linalg.norm(j.anchor) for j in structure.joints if j.anchor is not None]
        length = max(points + [1e-3])
        mass = max(structure.total_mass, 1e-12)
        inertia = max([np.abs(link.inertia).max() for link in structure.links] + [mass * length**2])
        return cls(mass, length, inertia, robot_tolerance(len(structure.links)))

    def larger(self, other: "Scales") -> "Scales":
        """Each scale the larger of two models' (the terms' magnitude is the larger of the two readings', so that a
        value one engine rounds on its own scale is judged on it); the tolerance stays this one's."""
        return Scales(max(self.mass, other.mass), max(self.length, other.length), max(self.inertia, other.inertia),
                      self.tolerance)


def _value(x):
    """JSON-ready: floats as they are (nothing rounded), arrays as lists."""
    if x is None:
        return None
    arr = np.asarray(x, dtype=float)
    return float(arr) if arr.ndim == 0 else arr.tolist()


def differences(ref, other, engine: str, sc: Scales) -> list[Item]:
    """Every difference between the reference's structure ``ref`` and an engine's ``other`` (causes empty)."""
    items = []

    def differ(a, b, scale):
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        return a.shape != b.shape or bool(np.max(np.abs(a - b), initial=0.0) > sc.tolerance * scale)

    def add(item, where, a, b):
        items.append(Item(item, where, {"mujoco": _value(a), engine: _value(b)}))

    if ref.nv != other.nv:
        add("degrees of freedom", "model", ref.nv, other.nv)
    theirs = {j.name: j for j in other.joints}
    for j in ref.joints:
        where = f"joint {j.name} ({j.type}, body {j.body})"
        o = theirs.get(j.name)
        if o is None:
            items.append(Item("joint missing", where, {"mujoco": j.type, engine: "absent"}))
            continue
        if o.type != j.type:
            items.append(Item("joint type", where, {"mujoco": j.type, engine: o.type}))
            continue
        if j.axis is not None and differ(j.axis, o.axis, 1.0):
            add("joint axis (world, at the reference configuration)", where, j.axis, o.axis)
        elif j.anchor is not None and differ(j.anchor, o.anchor, sc.length):  # a hinge's: on its axis, so with it
            add("joint position (world, m)", where, j.anchor, o.anchor)
        if differ(j.armature, o.armature, max(np.abs(j.armature).max(initial=0), np.abs(o.armature).max(initial=0),
                                                1e-300)):
            add("armature", where, j.armature, o.armature)
        if differ(j.damping, o.damping, max(np.abs(j.damping).max(initial=0), np.abs(o.damping).max(initial=0),
                                              1e-300)):
            add("damping", where, j.damping, o.damping)
    links = {link.name: link for link in other.links}
    for link in ref.links:
        where = f"link {link.name}" + (f" (bodies {', '.join(link.bodies)})" if len(link.bodies) > 1 else "")
        o = links.get(link.name)
        if o is None:
            items.append(Item("body missing", where, {"mujoco": link.mass, engine: "absent"}))
            continue
        if differ(link.mass, o.mass, sc.mass):
            add("mass (kg)", where, link.mass, o.mass)
        if min(link.mass, o.mass) <= sc.tolerance * sc.mass:
            continue  # a massless link has no centre of mass to compare; its mass is reported above
        if differ(link.com, o.com, sc.length):
            add("centre of mass (world, m)", where, link.com, o.com)
        if differ(link.inertia, o.inertia, sc.inertia):
            add("inertia about the centre of mass (world, kg m^2)", where, link.inertia, o.inertia)
    if differ(ref.total_mass, other.total_mass, sc.mass):
        add("total mass (kg)", "model", ref.total_mass, other.total_mass)
    if differ(ref.gravity, other.gravity, max(np.linalg.norm(ref.gravity), np.linalg.norm(other.gravity), 1e-300)):
        add("gravity (m/s^2)", "model", ref.gravity, other.gravity)
    return items


def explain(reference, robot, readings, sc: Scales, unexplained: str | None = None) -> tuple[list[Item], object,
                                                                                           list[str]]:
    """The audit of ``robot`` against ``reference`` with causes; ``(items, explained reference, applied keys)``.

    ``readings``: the engine's ``MJCF_READINGS``. The explained reference is MuJoCo recompiled with every
    reading that made a difference disappear, the model the dynamics are then compared against to see
    whether the readings explain them too. ``unexplained``: the cause to give what no reading explains
    (default: that no known difference of the engine's parser explains it).
    """
    engine = robot.engine
    sc = sc.larger(Scales.of(robot.structure))
    left = differences(reference.structure, robot.structure, engine, sc)
    causes: dict = {}
    current, applied = reference, []
    for key, text, applies, change in readings:
        if not left or not applies(current.spec):
            continue
        try:
            candidate = current.recompiled(change)
        except ModelError:
            continue
        after = differences(candidate.structure, robot.structure, engine, sc)
        gone = {i.key for i in left} - {i.key for i in after}
        if gone:
            for k in gone:
                causes[k] = text
            current, applied = candidate, applied + [key]
            left = after
    still = {i.key for i in left}
    items = [Item(i.item, i.where, i.values, causes.get(i.key, "")) for i in
             differences(reference.structure, robot.structure, engine, sc)]
    return [i if i.key not in still else Item(i.item, i.where, i.values, unexplained or _unknown(i, engine))
            for i in items], current, applied


def _unknown(item: Item, engine: str) -> str:
    if item.item == "joint type":
        return f"{engine} maps this joint to another type"
    return f"not explained by a known difference between {engine}'s reading of the file and MuJoCo's"


def merge(per_engine: list[list[Item]]) -> list[Item]:
    """One row per (item, where) over the engines: every engine's value, their causes joined."""
    rows: dict = {}
    for items in per_engine:
        for i in items:
            row = rows.setdefault(i.key, {"values": {}, "causes": []})
            row["values"].update(i.values)
            engine = next(k for k in i.values if k != "mujoco")
            row["causes"].append(f"{engine}: {i.cause}")
    return [Item(item, where, r["values"], "; ".join(r["causes"])) for (item, where), r in rows.items()]
