"""How Pinocchio reads a model differently from MuJoCo, as changes to MuJoCo's ``MjSpec``, and the difference in its
algorithms relacc knows.

Each reading is ``(key, text, applies(spec), change(spec))``: the audit (:func:`relacc.validation.robots.audit.explain`)
recompiles MuJoCo's model with ``change`` and takes ``text`` as the cause of the differences that disappear. These
functions touch only the spec (no ``pinocchio``, no ``mujoco`` import).
"""

from __future__ import annotations

import numpy as np


def _drop_later_world_children(spec):
    for body in list(spec.worldbody.bodies)[1:]:
        spec.delete(body)


MESH = 7
"""MuJoCo's ``mjGEOM_MESH`` (``mjtGeom``), read here without importing mujoco."""


def _solid(geom) -> bool:
    """A geom Pinocchio's MJCF parser counts in the inertia (not ``contype = conaffinity = 0``)."""
    return not (geom.contype == 0 and geom.conaffinity == 0)


def _visual_geoms(spec):
    """Geoms with ``contype = conaffinity = 0`` in bodies whose inertia comes from their geoms."""
    return [g for b in spec.bodies if not b.explicitinertial for g in b.geoms if not _solid(g)]


def _leave_out_of_inertia(spec):
    for g in spec.geoms:
        g.group = min(int(g.group), 4)
    for g in _visual_geoms(spec):
        g.group = 5
    spec.compiler.inertiagrouprange = [0, 4]
    spec.compiler.boundmass = spec.compiler.boundinertia = 1e-14  # MuJoCo refuses massless moving bodies


def _placed_fixed_root(spec):
    """The first body under ``<worldbody>``, when it has no joint and is placed away from the world frame."""
    bodies = list(spec.worldbody.bodies)
    if not bodies or list(bodies[0].joints):
        return None
    b = bodies[0]
    turned = int(b.alt.type) != 0 or list(b.quat) != [1.0, 0.0, 0.0, 0.0]  # 0: a quaternion, MuJoCo's enum
    return b if turned or any(b.pos) else None


def _root_at_world(spec):
    b = _placed_fixed_root(spec)
    b.pos, b.quat = [0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]
    b.alt.type = type(b.alt.type)(0)  # the quaternion, not an alternative orientation


def _mesh_bodies(spec):
    """Bodies whose inertia comes from their geoms and whose every counted geom is a mesh."""
    out = []
    for b in spec.bodies:
        solid = [g for g in b.geoms if _solid(g)]
        if not b.explicitinertial and solid and all(int(g.type) == MESH for g in solid):
            out.append((b, solid))
    return out


def _unit_mesh_inertia(spec):
    from relacc.engines.base import combine

    for body, meshes in _mesh_bodies(spec):
        mass, com, inertia = combine((1.0, list(g.pos), np.eye(3)) for g in meshes)
        body.explicitinertial = True
        body.mass, body.ipos, body.iquat = mass, list(com), [1.0, 0.0, 0.0, 0.0]
        body.fullinertia = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2]]


def _default_gravity(spec):
    spec.option.gravity = [0.0, 0.0, -9.81]


MJCF_READINGS = (
    ("first_body", "Pinocchio's MJCF parser reads only the first <body> under <worldbody>; the others are dropped",
     lambda spec: len(list(spec.worldbody.bodies)) > 1, _drop_later_world_children),
    ("settotalmass", "Pinocchio ignores <compiler settotalmass>, which makes MuJoCo scale every mass",
     lambda spec: spec.compiler.settotalmass > 0, lambda spec: setattr(spec.compiler, "settotalmass", -1.0)),
    ("visual_geoms", "Pinocchio's MJCF parser takes geoms with contype=0 and conaffinity=0 as visual and leaves "
     "them out of the inertia; MuJoCo counts every geom in inertiagrouprange",
     lambda spec: bool(_visual_geoms(spec)), _leave_out_of_inertia),
    ("mesh_inertia", "Pinocchio's MJCF parser gives a mesh geom 1 kg and a unit inertia at the geom's frame (it reads "
     "neither the mesh's volume nor the geom's mass)", lambda spec: bool(_mesh_bodies(spec)), _unit_mesh_inertia),
    ("fixed_root", "Pinocchio's MJCF parser drops the pos and orientation of a first <body> that has no joint (it "
     "puts that body at the world frame)", lambda spec: _placed_fixed_root(spec) is not None, _root_at_world),
    ("gravity", "Pinocchio's MJCF parser ignores <option gravity> and keeps (0, 0, -9.81)",
     lambda spec: list(spec.option.gravity) != [0.0, 0.0, -9.81], _default_gravity),
)
"""How Pinocchio's MJCF parser reads a file differently from MuJoCo, each as ``(key, cause, applies(spec),
change(spec))``: ``change`` makes MuJoCo read the file Pinocchio's way, so that a comparison can check that the
difference is explained (MuJoCo recompiled with the change gives Pinocchio's numbers)."""

ENGINE_READINGS = (
    ("composite_jdot", "Pinocchio's Jacobian time variation (J_dot v) of a JointModelComposite, which its MJCF parser "
     "makes of a body with several joints, is wrong (stack-of-tasks/pinocchio#2519): with the composites split "
     "into simple joints Pinocchio agrees",
     lambda robot: bool(robot.composites()), lambda robot: _split(robot)),
)
"""Differences in Pinocchio's algorithms rather than its reading of the file: ``(key, cause, applies(robot),
rebuild(robot))``, ``rebuild`` giving a robot without the difference."""


def _split(robot):
    from relacc.engines.pinocchio_ import PinocchioAdapter

    path, reference, urdf = robot.args
    return PinocchioAdapter(path, reference, urdf=urdf, split=True)
