"""The model audit: what an engine made of a model file, against a reference reading of it (relacc's own in
``relacc compare``; MuJoCo's model where a parser's reading is reproduced), with causes.

Differences (:func:`differences`) are found element by element at the reference configuration:
degrees of freedom; joints missing or of another type, their axes and positions, armature and
damping; links (a moving body and the bodies welded to it) missing, their masses, centres of mass
and inertias (world components); the total mass; gravity. A value differs when it is off by more
than :func:`relacc.core.tolerances.robot_tolerance` times its scale (:class:`Scales`, from the
reference model: its total mass, its size, its largest inertia); a damping derived from the mass matrix
(MJCF ``springdamper``) by more than that times ``1 +`` its sensitivity
(:attr:`relacc.reading.Reading.sensitivity`): the mass matrix's rounding, amplified by its inverse.

Causes are not guessed but reproduced (:mod:`relacc.validation.robots.causes`): relacc's reader reads the file
the engine's way (e.g. Pinocchio ignoring ``settotalmass``), and a reading is the cause of the differences it makes
disappear.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from relacc.core.tolerances import robot_tolerance


@dataclass(frozen=True)
class Item:
    """One audit difference: ``item`` (what), ``where`` (the element), each reading's value (``values``: the
    reference's first), its cause (``cause``, ``kind``: :mod:`relacc.validation.robots.causes`), the element's place
    in the file (``file:line``) and ``subject``: ``("joint" | "link" | "model", name)``."""

    item: str
    where: str
    values: dict = field(default_factory=dict)
    cause: str = ""
    kind: str = ""
    place: str = ""
    subject: tuple = ("model", "")

    @property
    def key(self) -> tuple[str, str]:
        return self.item, self.where

    def as_json(self) -> dict:
        return {"item": self.item, "where": self.where, **self.values, "cause": self.cause, "cause_kind": self.kind,
                "place": self.place}


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
        return cls(mass, float(length), float(inertia), robot_tolerance(len(structure.links)))

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


def inertia_slack(evaluator, reading) -> float:
    """kg m^2: what an evaluator's own documented numerical tolerance allows each body inertia of ``reading`` beyond
    rounding (:meth:`relacc.engines.base.Adapter.inertia_allowance`; 0 for relacc's own tree, which has none)."""
    allowance = getattr(evaluator, "inertia_allowance", None)
    return float(allowance(reading)) if allowance is not None else 0.0


def differences(ref, other, ref_name: str, engine: str, sc: Scales, inertia_slack: float = 0.0) -> list[Item]:
    """Every difference between the structure ``ref`` of reading ``ref_name`` and an engine's ``other`` (causes
    empty). ``inertia_slack`` (kg m^2): what the engine's own numerical tolerance allows each body inertia beyond
    rounding (:meth:`relacc.engines.base.Adapter.inertia_allowance`)."""
    items = []

    def differ(a, b, scale, slack=0.0):
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        return a.shape != b.shape or bool(np.max(np.abs(a - b), initial=0.0) > sc.tolerance * scale + slack)

    subject = ("model", "")

    def add(item, where, a, b):
        items.append(Item(item, where, {ref_name: _value(a), engine: _value(b)}, subject=subject))

    if ref.nv != other.nv:
        add("degrees of freedom", "model", ref.nv, other.nv)
    theirs = {j.name: j for j in other.joints}
    for j in ref.joints:
        where = f"joint {j.name} ({j.type}, body {j.body})"
        subject = ("joint", j.name)
        o = theirs.get(j.name)
        if o is None:
            items.append(Item("joint missing", where, {ref_name: j.type, engine: "absent"}, subject=subject))
            continue
        if o.type != j.type:
            items.append(Item("joint type", where, {ref_name: j.type, engine: o.type}, subject=subject))
            continue
        if j.axis is not None and differ(j.axis, o.axis, 1.0):
            add("joint axis (world, at the reference configuration)", where, j.axis, o.axis)
        elif j.anchor is not None and differ(j.anchor, o.anchor, sc.length):  # a hinge's: on its axis, so with it
            add("joint position (world, m)", where, j.anchor, o.anchor)
        if differ(j.armature, o.armature, max(np.abs(j.armature).max(initial=0), np.abs(o.armature).max(initial=0),
                                                1e-300)):
            add("armature", where, j.armature, o.armature)
        derived = 1.0 + max(j.sensitivity, o.sensitivity)  # springdamper's: the mass matrix's rounding, amplified
        if differ(j.damping, o.damping, derived * max(np.abs(j.damping).max(initial=0),
                                                      np.abs(o.damping).max(initial=0), 1e-300)):
            add("damping", where, j.damping, o.damping)
    links = {link.name: link for link in other.links}
    for link in ref.links:
        where = f"link {link.name}" + (f" (bodies {', '.join(link.bodies)})" if len(link.bodies) > 1 else "")
        subject = ("link", link.name)
        o = links.get(link.name)
        if o is None:
            items.append(Item("body missing", where, {ref_name: link.mass, engine: "absent"}, subject=subject))
            continue
        if differ(link.mass, o.mass, sc.mass):
            add("mass (kg)", where, link.mass, o.mass)
        if min(link.mass, o.mass) <= sc.tolerance * sc.mass:
            continue  # a massless link has no centre of mass to compare; its mass is reported above
        if differ(link.com, o.com, sc.length):
            add("centre of mass (world, m)", where, link.com, o.com)
        if differ(link.inertia, o.inertia, sc.inertia, inertia_slack):
            add("inertia about the centre of mass (world, kg m^2)", where, link.inertia, o.inertia)
    subject = ("model", "")
    if differ(ref.total_mass, other.total_mass, sc.mass):
        add("total mass (kg)", "model", ref.total_mass, other.total_mass)
    if differ(ref.gravity, other.gravity, max(np.linalg.norm(ref.gravity), np.linalg.norm(other.gravity), 1e-300)):
        add("gravity (m/s^2)", "model", ref.gravity, other.gravity)
    return items


def merge(per_engine: list[list[Item]]) -> list[Item]:
    """One row per (item, where) over the engines: every reading's value (the reference's first), the engines' causes
    joined, the row's kind the least explained of theirs."""
    from relacc.validation.robots.causes import KINDS

    rows: dict = {}
    for items in per_engine:
        for i in items:
            row = rows.setdefault(i.key, {"values": {}, "causes": [], "kinds": [], "item": i})
            reference, engine = list(i.values)[:2]
            row["values"].setdefault(reference, i.values[reference])
            row["values"][engine] = i.values[engine]
            row["causes"].append(f"{engine}: {i.cause}")
            row["kinds"].append(i.kind)
    return [replace(r["item"], values=r["values"], cause="; ".join(r["causes"]),
                    kind=max(r["kinds"], key=lambda k: KINDS.index(k) if k in KINDS else -1))
            for r in rows.values()]
