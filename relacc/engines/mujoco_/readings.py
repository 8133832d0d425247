"""The differences in MuJoCo's algorithms relacc knows as readings to re-run: none (MuJoCo's known bugs in reading a
file, relacc's reader reproduces itself: :data:`relacc.validation.robots.causes.READINGS`; its known algorithmic
differences are explained by :func:`relacc.validation.robots.routines.routine_cause`)."""

from __future__ import annotations

from relacc.engines.base import KnownBehaviour
from relacc.engines.known import (
    drop_massless_inertia,
    massless_with_inertia,
    mjcf,
    reread,
    unturned_inertials,
    urdf_inertial_turned,
)

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
        "urdf_inertial_rotation",
        "MuJoCo's URDF reader up to 3.13 drops the rotation of an <inertial>'s <origin "
        "rpy> (google-deepmind/mujoco#3559, fixed in 3.14): it takes the inertia as if written in the link's axes",
        urdf_inertial_turned,
        unturned_inertials,
    ),
)
"""How mujoco's parsers read a file differently, as changes to relacc's reading (:mod:`relacc.engines.known`):
the audit applies those that apply, whichever engine reads the file."""
