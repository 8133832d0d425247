"""MuJoCo's :class:`relacc.engines.traits.Traits` (imports nothing of MuJoCo)."""

from relacc.core.conventions import Route
from relacc.engines.traits import Traits

TRAITS = Traits(
    name="mujoco", label="MuJoCo", order=2, package="mujoco", pip="mujoco", color="#2ca02c", marker="d",
    marker_size=6, integrators=("rk4", "euler", "implicit", "implicitfast"),
    speeds="case 2 as it is: a free joint's v = [p_dot (world), omega (body)], a ball's omega in the child's "
           "components; quaternions (w, x, y, z)",
    chain_routes={
        Route.QUATERNION: (
            "two_body.xml; qpos = [s1, quat_B1 (w first), s2', quat_B2/B1 (w first)]; qvel = [s1_dot (world),"
            " omega'_B1 (B1), s2'_dot, omega_hat'_B2 (B2)] = Case 2 speeds; G2: mj_jac, mj_jacDot (after "
            'mj_comVel), mj_objectAcceleration with gravity 0'
        ),
        Route.EULER: (
            'two_body_euler.xml; qpos = case-3 q, qvel = case-3 u (slides, hinges x, y, z); no map'
        ),
    },
    chain_files={Route.QUATERNION: ("two_body.xml", {}), Route.EULER: ("two_body_euler.xml", {})},
    capabilities=frozenset({"PointLoop", "KinematicsLoops", "Rollout", "BodyMotion", "AccelerationRoutine"}),
    calls={"rollout": "rollout", "step": "mj_step per call", "jacobians": "mj_jac/mj_jacDot loop",
           "motion": "mj_kinematics/mj_comVel loop"},
    compiled_loops=True, own_steppers=True, mesh_source=True, truth=True, in_scenes=True)


def chain_export() -> dict:
    """The note's chain in MuJoCo, as ``relacc fixtures --out`` writes it in ``conventions.json``
    (:func:`relacc.fixtures.export.conventions`): each route's model, coordinates and speeds, and every case's
    map to them."""
    from relacc.fixtures.export import Q12, Q14, U, route_maps

    return {
        "quaternion_route": {"model": "two_body.xml", "qpos": Q14, "qpos_from_quaternion_coordinates": list(range(14)),
                             "qvel": U[2], "site": "G2",
                             "maps": route_maps("qpos = quaternion coordinates as they are",
                                                "qvel = case-2 body speeds as they are (linear: world; angular: "
                                                "body)")},
        "euler_route": {"model": "two_body_euler.xml", "qpos": Q12, "qvel": U[3], "site": "G2",
                        "maps": {"3": "qpos = q, qvel = u (case 3 only)"}},
    }
