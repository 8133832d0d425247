"""The differences in MuJoCo's algorithms relacc knows as readings to re-run: none (MuJoCo's known bugs in reading a
file, relacc's reader reproduces itself: :data:`relacc.validation.robots.causes.READINGS`; its known algorithmic
differences are explained by :func:`relacc.validation.robots.routines.routine_cause`)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from relacc.engines.base import KnownBehaviour
from relacc.engines.known import (
    drop_massless_inertia,
    massless_with_inertia,
    mjcf,
    reread,
    unturned_inertials,
    urdf_inertial_turned,
    with_bodies,
)

FRAME_EPS = 1e-6
"""MuJoCo's ``kFrameEps`` (``user_model.cc``): an inertial frame whose position (m) and quaternion components are each
within it of the body frame's is the body frame (``body_sameframe``): the kinematics put the mass centre at the
body's origin and the principal axes on the body's axes, whatever the compiled ``body_ipos`` and ``body_iquat``."""


def _snapped(body):
    """The body with its mass centre at its origin where it is within :data:`FRAME_EPS` of it (each coordinate), as
    MuJoCo's kinematics place it when its principal axes are the body's too; None elsewhere. The axes are left as
    relacc reads them: which frame MuJoCo's compiler takes for principal (a mesh's own, an eigen solver's) decides
    the snapping, and where it takes another the snapped mass centre is simply not MuJoCo's (the reading then makes
    no difference disappear and is not kept)."""
    if body.mass <= 0 or not 0 < np.max(np.abs(body.com)) < FRAME_EPS:
        return None
    return replace(body, com=np.zeros(3))


def _near_body_frame(reading) -> bool:
    return mjcf(reading) and any(_snapped(body) is not None for body in reading.tree.bodies)


ENGINE_READINGS = ()
"""No known difference in MuJoCo's algorithms to re-run."""

FILE_READINGS = (
    KnownBehaviour(
        "massless_inertia",
        "the file gives a body no mass but an inertia (a finding); MuJoCo's compiler drops the "
        "inertia of a massless body",
        massless_with_inertia,
        drop_massless_inertia,
    ),
    KnownBehaviour(
        "obj_first_object",
        "MuJoCo reads only the first object (o or g) of an OBJ mesh file of several (google-deepmind/mujoco#911): "
        "its legacy, exact and shell inertias are that object's",
        lambda r: mjcf(r) and bool(r.facts.get("multi_object_meshes")),
        reread("mesh_obj_first_object"),
    ),
    KnownBehaviour(
        "inertial_frame_snapped",
        "MuJoCo's kinematics put an inertial frame within 1e-6 of its body's frame on it (body_sameframe, "
        "kFrameEps): a mass centre within 1e-6 m of the body's origin at the origin",
        _near_body_frame,
        lambda reading: with_bodies(reading, _snapped),
    ),
    KnownBehaviour(
        "urdf_inertial_rotation",
        "MuJoCo's URDF reader up to 3.13 drops the rotation of an <inertial>'s <origin "
        "rpy> (google-deepmind/mujoco#3559, fixed in 3.14): it takes the inertia as if written in the link's axes",
        urdf_inertial_turned,
        unturned_inertials,
    ),
)
"""How mujoco's parsers read a file differently, as changes to relacc's reading (:mod:`relacc.engines.known`):
the audit applies those that apply, whichever engine reads the file."""
