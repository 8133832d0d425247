"""Drake's plant of a model: read by Drake's parsers, or built from relacc's tree, and matched to the reference.

Imports only ``pydrake``. Drake's parsers (MJCF and URDF) make a continuous-time ``MultibodyPlant``; their warnings
are collected, never printed (:func:`parse`). A file without a model name is loaded through a model directive naming
it after the file (Drake's MJCF parser refuses it otherwise), and the warnings say so.

:func:`build_plant` makes the plant of a :class:`relacc.Tree` where Drake's MJCF parser would read the model
otherwise (it turns a ball into roll-pitch-yaw angles, singular at pitch +-pi/2, and ignores sites): a free joint
becomes a ``QuaternionFloatingJoint`` from the world; three slides along the parent's axes followed by a ball at
the same point (the note's chain: B2 on B1) become one ``QuaternionFloatingJoint`` from the body's place on its
parent (match kind ``floating``); a body without joints is welded; every named point is a ``FixedOffsetFrame``.
"""

from __future__ import annotations

import json
import logging
import re
from pathlib import Path

import numpy as np
from pydrake.common.eigen_geometry import Quaternion
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import FixedOffsetFrame, QuaternionFloatingJoint, RotationalInertia, SpatialInertia

from relacc.engines.base import NQ, NV, Match, by_order
from relacc.engines.mjcf import has_equality, has_zero_inertial, without_equality, without_meshes
from relacc.engines.urdf import dynamics_text, is_urdf
from relacc.errors import EngineError, ModelError

TYPES = {"quaternion_floating": "free", "ball_rpy": "ball", "revolute": "hinge", "prismatic": "slide"}

OBJ_ONLY = "only supports mesh files in .obj format"
"""Drake's MJCF parser refusing a mesh of another format."""

NO_MODEL_NAME = "must have a name attribute or a model name must be specified"
"""Drake's MJCF parser refuses a ``<mujoco>`` without ``model=`` (MuJoCo itself names it "MuJoCo Model")."""


class _Collect(logging.Handler):
    def __init__(self):
        super().__init__(logging.WARNING)
        self.lines: list[str] = []

    def emit(self, record):
        self.lines.append(" ".join(record.getMessage().split()))


def _directive(path) -> str:
    """A Drake model directive adding ``path`` under its file's stem: how Drake's parser takes a model name."""
    path = Path(path).resolve()
    return ("directives:\n- add_model:\n"
            f"    name: {json.dumps(path.stem)}\n    file: {json.dumps(path.as_uri())}\n")


def _parse(path, named: bool, text: str | None = None):
    """Drake's plant of ``path``: through a model directive when ``named``, from ``text`` (an MJCF) when given."""
    plant = MultibodyPlant(0.0)
    parser = Parser(plant)
    welded = []
    if is_urdf(path):  # its kinematics and inertials only
        text = dynamics_text(path)[0]
        children = set(CHILD.findall(COMMENT.sub("", text)))  # a commented-out joint is no joint
        for instance in parser.AddModelsFromString(text, "urdf"):
            welded += _weld_roots(plant, instance, children)
    elif text is not None:
        parser.AddModelsFromString(text, "xml")
    elif named:
        parser.AddModelsFromString(_directive(path), "dmd.yaml")
    else:
        parser.AddModels(str(path))
    plant.Finalize()
    return plant, welded


def _without_meshes(path, handler, reason: str):
    """Drake's plant of the MJCF's text without its meshes and zero inertials
    (:func:`relacc.engines.mjcf.without_meshes`), its note among the warnings; ``reason``: why the file's own text
    cannot be read."""
    try:
        text, note = without_meshes(path)
    except ModelError as why:
        raise ModelError(f"{path}: Drake cannot read it: {reason}, and "
                         f"{str(why).removeprefix(f'{path}: ')}") from None
    plant, welded = _parse(path, named=False, text=text)
    handler.lines.append(note)
    return plant, welded


CHILD = re.compile(r"""<child\b[^>]*\blink\s*=\s*["']([^"']+)["']""")
"""A URDF joint's child link."""
COMMENT = re.compile(r"<!--.*?-->", re.S)


def _weld_roots(plant, instance, urdf_children=frozenset()) -> list[str]:
    """Weld to the world, where it is, each body of a URDF that no joint carries: URDF's root link, which MuJoCo
    and Pinocchio fix to the world and Drake's parser alone would leave free (six more degrees of freedom). A link
    the file puts on a joint Drake does not build (a ``floating`` joint, which its parser leaves as a free body) is
    the child of that joint, not a root: left free, as the file says (``urdf_children``: the file's child links)."""
    children = {plant.get_joint(j).child_body().index() for j in plant.GetJointIndices(instance)}
    names = []
    for index in plant.GetBodyIndices(instance):
        if index not in children and plant.get_body(index).name() not in urdf_children:
            body = plant.get_body(index)
            plant.WeldFrames(plant.world_frame(), body.body_frame())
            names.append(body.name())
    return names


def parse(path):
    """Drake's plant of ``path`` and its parser's warnings (and, when relacc named the model, a line saying so).

    Raises:
        ModelError: Drake's parser message (file and line).
    """
    log, handler = logging.getLogger("drake"), _Collect()
    before = log.propagate
    log.addHandler(handler)
    log.propagate = False
    try:
        try:
            if not is_urdf(path) and has_zero_inertial(path):  # Drake's parser would abort on the zero mass
                plant, welded = _without_meshes(path, handler, "its parser cannot take a body of zero mass")
            elif not is_urdf(path) and has_equality(path):  # its continuous plant refuses constraints
                text, note = without_equality(path)
                plant, welded = _parse(path, named=False, text=text)
                handler.lines.append(note)
            else:
                plant, welded = _parse(path, named=False)
        except ModelError:
            raise
        except Exception as exc:
            plant, failure = None, exc
            if NO_MODEL_NAME in str(exc):
                handler.lines.clear()
                try:
                    plant, welded = _parse(path, named=True)
                    handler.lines.append(f"the file has no model name, which Drake's parser requires: relacc loaded "
                                         f"it through a model directive naming it {Path(path).stem!r} (the name only)")
                except Exception as again:
                    failure = again
            if plant is None and OBJ_ONLY in str(failure) and not is_urdf(path):
                handler.lines.clear()  # the text without meshes names the model too
                plant, welded = _without_meshes(path, handler, "it reads .obj meshes only")
            elif plant is None:
                raise failure from None
    except ModelError:
        raise
    except Exception as exc:  # Drake raises RuntimeError with its parser's message (file and line)
        raise ModelError(f"{path}: Drake cannot read it: {' '.join(str(exc).split())}") from None
    finally:
        log.removeHandler(handler)
        log.propagate = before
    if is_urdf(path):
        dropped = dynamics_text(path)[1]
        handler.lines = [line.replace("<literal-string>.urdf", str(path)) for line in handler.lines]
        handler.lines += [dropped] if dropped else []
        handler.lines += [f"relacc welded the URDF's root link {name!r} to the world, as MuJoCo and Pinocchio read "
                          "it (Drake's parser alone leaves it free)" for name in welded]
    return plant, handler.lines


def match_parsed(plant, reference) -> tuple[list[Match], dict]:
    """Each reference joint the parsed plant has, of the same type: by name, else by structure (free joints by
    their body; a body's only joint, unnamed in MuJoCo and named ``<parent>-<body>`` by Drake's parser, by the
    body it moves); and each reference body's Drake body (its last joint's child)."""
    joints = [plant.get_joint(j) for j in plant.GetJointIndices() if plant.get_joint(j).num_velocities() > 0]
    by_name = {j.name(): j for j in joints if j.type_name() != "quaternion_floating"}
    floating = {j.child_body().name(): j for j in joints if j.type_name() == "quaternion_floating"}
    by_body = {}
    for j in joints:
        by_body.setdefault(j.child_body().name(), []).append(j)
    count = {}
    for b, _ in reference.joints:
        count[b] = count.get(b, 0) + 1
    matches, heads, taken = [], {}, set()
    for k, ((b, joint), qa, da) in enumerate(zip(reference.joints, reference.qadr(2), reference.dofadr)):
        body = reference.bodies[b].name
        dj = floating.get(body) if joint.type == "free" else by_name.get(joint.name)
        if dj is None and count[b] == 1 and len(by_body.get(body, ())) == 1:
            dj = by_body[body][0]
        if dj is None or TYPES.get(dj.type_name()) != joint.type or dj.index() in taken:
            continue
        taken.add(dj.index())
        matches.append(Match(joint.type, (k,), tuple(range(qa, qa + NQ[joint.type])),
                             tuple(range(da, da + NV[joint.type])),
                             tuple(range(dj.position_start(), dj.position_start() + dj.num_positions())),
                             tuple(range(dj.velocity_start(), dj.velocity_start() + dj.num_velocities()))))
        heads[body] = dj.child_body()  # the last joint of a body wins
    ordered = sorted(joints, key=lambda j: j.velocity_start())
    spans = lambda j: (tuple(range(j.position_start(), j.position_start() + j.num_positions())),  # noqa: E731
                       tuple(range(j.velocity_start(), j.velocity_start() + j.num_velocities())))
    completed = by_order(reference, matches, [(j.index(), TYPES.get(j.type_name()), *spans(j)) for j in ordered])
    for m in completed:
        if m not in matches:  # a body matched by structure: its Drake body is the joint's child
            j = next(j for j in ordered if spans(j)[1] == m.v)
            heads[reference.bodies[reference.joints[m.joints[0]][0]].name] = j.child_body()
    return completed, heads


def _inertia(m, com, inertia) -> SpatialInertia:
    """A body's spatial inertia about its origin from mass (kg), mass centre (m) and central inertia (kg m^2)."""
    I = np.asarray(inertia, dtype=float)
    return SpatialInertia.MakeFromCentralInertia(
        float(m), np.asarray(com, dtype=float), RotationalInertia(I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]))


def _floating_pattern(body) -> bool:
    """Three slides along the body's axes x, y, z in order, then a ball at the body's origin."""
    j = body.joints
    return (len(j) == 4 and [x.type for x in j] == ["slide"] * 3 + ["ball"] and not np.any(j[3].pos)
            and all(np.array_equal(x.axis, np.eye(3)[k]) and x.ref == 0 for k, x in enumerate(j[:3])))


def build_plant(tree):
    """``(plant, matches, heads)``: the finalized plant of ``tree`` (module docstring), gravity the tree's.

    Raises:
        EngineError: a body whose joints are none of the patterns above.
    """
    plant = MultibodyPlant(0.0)
    drake_bodies, matches, heads = [], [], {}
    for b, body in enumerate(tree.bodies):
        drake_bodies.append(plant.AddRigidBody(body.name, _inertia(body.mass, body.com, body.inertia)))
    for b, body in enumerate(tree.bodies):
        parent = plant.world_body() if body.parent < 0 else drake_bodies[body.parent]
        place = RigidTransform(RotationMatrix(Quaternion(np.asarray(body.quat, dtype=float))),
                               np.asarray(body.pos, dtype=float))
        kinds = [j.type for j in body.joints]
        if kinds == ["free"] and body.parent < 0:
            plant.AddJoint(QuaternionFloatingJoint(body.joints[0].name, plant.world_frame(),
                                                   drake_bodies[b].body_frame()))
        elif _floating_pattern(body):
            frame = plant.AddFrame(FixedOffsetFrame(f"{body.name}_on_parent", parent.body_frame(), place))
            plant.AddJoint(QuaternionFloatingJoint(body.name + "_floating", frame, drake_bodies[b].body_frame()))
        elif not kinds:
            plant.WeldFrames(parent.body_frame(), drake_bodies[b].body_frame(), place)
        else:
            raise EngineError(f"tree {tree.name!r}, body {body.name!r}: relacc builds Drake plants of free bodies and "
                              f"of three slides then a ball only (got {', '.join(kinds)}); read the file with Drake's "
                              "parser instead")
        heads[body.name] = drake_bodies[b]
    for p in tree.points:
        owner = plant.world_body() if p.body < 0 else drake_bodies[p.body]
        plant.AddFrame(FixedOffsetFrame(p.name, owner.body_frame(), RigidTransform(np.asarray(p.pos, dtype=float))))
    plant.mutable_gravity_field().set_gravity_vector(np.asarray(tree.gravity, dtype=float))
    plant.Finalize()
    qadr, dofadr = tree.qadr(2), tree.dofadr
    at = 0
    for b, body in enumerate(tree.bodies):
        ks = list(range(at, at + len(body.joints)))
        at += len(body.joints)
        if not ks:
            continue
        joint = plant.GetJointByName(body.joints[0].name if len(ks) == 1 else body.name + "_floating")
        kind = "free" if len(ks) == 1 else "floating"
        qa, da = qadr[ks[0]], dofadr[ks[0]]
        matches.append(Match(kind, tuple(ks), tuple(range(qa, qa + 7)), tuple(range(da, da + 6)),
                             tuple(range(joint.position_start(), joint.position_start() + 7)),
                             tuple(range(joint.velocity_start(), joint.velocity_start() + 6))))
    return plant, matches, heads


def quiet(plant, context) -> None:
    """Nothing from the file acts in ``context``: zero actuation and no joint damping (applied forces stay the
    caller's: exactly a scene's effects)."""
    if plant.num_actuators():
        plant.get_actuation_input_port().FixValue(context, np.zeros(plant.num_actuated_dofs()))
    for j in plant.GetJointIndices():
        joint = plant.get_joint(j)
        if joint.num_velocities():
            joint.SetDampingVector(context, np.zeros(joint.num_velocities()))
