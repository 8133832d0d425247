"""The difference in Pinocchio's algorithms relacc knows (how Pinocchio's MJCF parser *reads* a file differently,
relacc's reader reproduces itself: :data:`relacc.validation.robots.causes.READINGS`).

Each entry is a :class:`relacc.engines.base.KnownBehaviour` whose ``change`` gives the adapter without the
difference, so that a known bug does not vote (:mod:`relacc.validation.robots.referee`) and a row that it explains
says so.
"""

from __future__ import annotations

from relacc.engines.base import KnownBehaviour
from relacc.engines.known import (
    element_skipped,
    inertiagrouprange_ignored,
    mjcf,
    mjcf_reading,
    reread,
    settotalmass_ignored,
    springdamper_ignored,
)

ENGINE_READINGS = (
    KnownBehaviour(
        "composite_jdot",
        "Pinocchio's Jacobian time variation (J_dot v) of a JointModelComposite, which its MJCF parser "
        "makes of a body with several joints, is wrong (stack-of-tasks/pinocchio#2519): with the composites split "
        "into simple joints Pinocchio agrees",
        lambda robot: bool(robot.composites()),
        lambda robot: _split(robot),
    ),
    KnownBehaviour(
        "free_armature",
        "Pinocchio adds a free joint's armature in its own speeds (the body-frame velocity of the body's origin), "
        "MuJoCo and relacc in case 2's (the world-frame velocity): for an armature equal on the three translations "
        "the same mass matrix, but bias forces that differ by the armature times omega x v",
        lambda robot: bool(robot.free_armature()),
        lambda robot: _armature_as_case2(robot),
    ),
)
"""Differences in Pinocchio's algorithms rather than its reading of the file."""


def _split(robot):
    from relacc.engines.pinocchio_.adapter import PinocchioAdapter

    path, reference, urdf = robot.args
    return PinocchioAdapter(path, reference, urdf=urdf, split=True, armature_as_case2=robot.armature_as_case2)


def _armature_as_case2(robot):
    from relacc.engines.pinocchio_.adapter import PinocchioAdapter

    path, reference, urdf = robot.args
    return PinocchioAdapter(path, reference, urdf=urdf, split=robot.split, armature_as_case2=True)


FILE_READINGS = (
    KnownBehaviour(
        "first_body",
        "Pinocchio's MJCF parser reads only the first <body> written directly in the main file's "
        "<worldbody> (it expands no <include>); the others are dropped",
        lambda r: mjcf(r) and r.facts["world_children"] > 1,
        reread("first_body_only"),
    ),
    KnownBehaviour(
        "fixed_root",
        "Pinocchio's MJCF parser drops the pos and orientation of a first <body> that has no joint (it "
        "puts that body at the world frame)",
        lambda r: mjcf(r) and r.facts["placed_jointless_first"],
        reread("first_body_unplaced"),
    ),
    settotalmass_ignored("Pinocchio"),
    KnownBehaviour(
        "default_mass",
        "Pinocchio's MJCF parser ignores a geom's mass inherited from a <default> class (it honours "
        "one written on the geom) and takes the geom's density times its volume",
        lambda r: mjcf(r) and r.facts["default_geom_masses"] > 0,
        reread("default_geom_mass_ignored"),
    ),
    KnownBehaviour(
        "visual_geoms",
        "Pinocchio's MJCF parser takes geoms with contype=0 and conaffinity=0 as visual and leaves "
        "them out of the inertia; MuJoCo counts every geom in inertiagrouprange",
        lambda r: mjcf(r) and r.facts["visual_geoms"] > 0,
        reread("visual_geoms_ignored"),
    ),
    KnownBehaviour(
        "mesh_inertia",
        "Pinocchio's MJCF parser gives a mesh geom 1 kg and a unit inertia at the geom's frame (it "
        "reads neither the mesh's volume nor the geom's mass)",
        lambda r: mjcf(r) and r.facts["mesh_bodies"],
        reread("mesh_unit_inertia"),
    ),
    KnownBehaviour(
        "unnamed_bodies",
        "Pinocchio's MJCF parser names an unnamed <body> after its parent (<parent>Bis), so of "
        "several unnamed children of one body only the first is read; the others and their subtrees are dropped",
        lambda r: mjcf(r) and r.facts.get("unnamed_dropped", 0) > 0,
        reread("unnamed_siblings_dropped"),
    ),
    mjcf_reading("bare_bodies", "Pinocchio's MJCF parser drops a <body> written with no attribute at all, with "
                 "everything in it (it takes a body's name, parent and place from the element's attributes)",
                 "bare_bodies", "bare_bodies_dropped"),
    KnownBehaviour(
        "default_joint_pos",
        "Pinocchio's MJCF parser ignores a joint's pos inherited from a <default> (it honours one written on "
        "the joint) and puts the joint at its body's origin",
        lambda r: mjcf(r) and r.facts.get("default_joint_pos", 0) > 0,
        reread("default_joint_pos_ignored"),
    ),
    KnownBehaviour(
        "default_geom_pose",
        "Pinocchio's MJCF parser ignores a geom's pos and orientation inherited from a <default> (it honours "
        "those written on the geom) and puts the geom at its body's frame",
        lambda r: mjcf(r) and r.facts.get("default_geom_pose", 0) > 0,
        reread("default_geom_pose_ignored"),
    ),
    springdamper_ignored("Pinocchio"),
    inertiagrouprange_ignored("Pinocchio"),
    KnownBehaviour(
        "inertial_unit_inertia",
        "Pinocchio's MJCF parser reads an <inertial> with neither diaginertia nor fullinertia as the unit inertia "
        "(1 kg m^2 about each axis); MuJoCo's compiler reads it as zero",
        lambda r: mjcf(r) and r.facts.get("inertia_less", 0) > 0,
        reread("inertial_unit_inertia"),
    ),
    KnownBehaviour(
        "ball_free_damping",
        "Pinocchio's MJCF parser drops the damping of a ball or free joint (it keeps a hinge's and a slide's)",
        lambda r: mjcf(r) and (r.facts.get("damped_free", 0) + r.facts.get("damped_balls", 0)) > 0,
        reread("free_damping_dropped", "ball_damping_dropped"),
    ),
    KnownBehaviour(
        "gravity",
        'Pinocchio\'s MJCF parser ignores <option gravity> and <flag gravity="disable"/> and keeps (0, 0, -9.81)',
        lambda r: mjcf(r) and list(r.tree.gravity) != [0.0, 0.0, -9.81],
        reread("gravity_default"),
    ),
    element_skipped("Pinocchio", "replicate", "replicates", "and everything in it: its copies absent"),
    element_skipped("Pinocchio", "attach", "attaches", "the attached bodies absent"),
)
"""How pinocchio's parsers read a file differently, as changes to relacc's reading (:mod:`relacc.engines.known`):
the audit applies those that apply, whichever engine reads the file."""
