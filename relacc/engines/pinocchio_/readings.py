"""The difference in Pinocchio's algorithms relacc knows (how Pinocchio's MJCF parser *reads* a file differently,
relacc's reader reproduces itself: :data:`relacc.validation.robots.causes.READINGS`).

Each entry is a :class:`relacc.engines.base.KnownBehaviour` whose ``change`` gives the adapter without the
difference, so that a known bug does not vote (:mod:`relacc.validation.robots.referee`) and a row that it explains
says so.
"""

from __future__ import annotations

from relacc.engines.base import KnownBehaviour

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
    from relacc.engines.pinocchio_ import PinocchioAdapter

    path, reference, urdf = robot.args
    return PinocchioAdapter(path, reference, urdf=urdf, split=True, armature_as_case2=robot.armature_as_case2)


def _armature_as_case2(robot):
    from relacc.engines.pinocchio_ import PinocchioAdapter

    path, reference, urdf = robot.args
    return PinocchioAdapter(path, reference, urdf=urdf, split=robot.split, armature_as_case2=True)
