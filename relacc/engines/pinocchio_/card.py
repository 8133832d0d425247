"""Pinocchio's :class:`relacc.engines.traits.Traits` (imports nothing of Pinocchio)."""

from relacc.core.conventions import Route
from relacc.engines.traits import Traits

TRAITS = Traits(
    name="pinocchio", label="Pinocchio", order=1, package="pinocchio", pip="pin", color="#1f77b4", marker="x",
    marker_size=6, integrators=("rk4", "euler"),
    speeds="a free joint's v = [R^T p_dot, omega], both in body components (T = diag(R^T, I)); quaternions "
           "(x, y, z, w); an unbounded revolute q = (cos, sin); ball, hinge and slide speeds as case 2",
    chain_routes={
        Route.QUATERNION: (
            "two_body.xml, composite joint split; q = [s1, quat_B1 (x,y,z,w), s2', quat_B2/B1 (x,y,z,w)]; v ="
            " [[R_B1] s1_dot (B1), omega'_B1, s2'_dot, omega_hat'_B2]; a = [[R_B1] s1_ddot - omega'_B1 x "
            '[R_B1] s1_dot, ...]; G2: LOCAL_WORLD_ALIGNED frame Jacobian, its time variation, '
            'getFrameClassicalAcceleration'
        ),
        Route.EULER: (
            'two_body_euler.urdf; q = case-3 q, v = case-3 u (prismatic, revolute x, y, z); no map'
        ),
    },
    chain_files={Route.QUATERNION: ("two_body.xml", {"split": True}),
                 Route.EULER: ("two_body_euler.urdf", {"urdf": "two_body_euler.urdf"})},
    capabilities=frozenset({"PointLoop", "KinematicsLoops", "BatchedForward", "ThreadedStepper", "ManifoldRates"}),
    calls={"batched_forward": "abaInParallel", "jacobians": "jacobians loop", "motion": "forwardKinematics loop"},
    own_urdf=True, compiled_loops=True, in_scenes=True)


def chain_export() -> dict:
    """The note's chain in Pinocchio, as ``relacc fixtures --out`` writes it in ``conventions.json``
    (:func:`relacc.fixtures.export.conventions`): each route's model, coordinates and speeds, and every case's
    map to them."""
    from relacc.fixtures.export import Q12, Q14, R1, U, route_maps

    return {
        "quaternion_route": {"model": "two_body.xml (split the composite joint of B2: Pinocchio 4.1.0's "
                                      "Jacobian time variation of a JointModelComposite is wrong)",
                             "q": [Q14[i] for i in (0, 1, 2, 4, 5, 6, 3, 7, 8, 9, 11, 12, 13, 10)],
                             "q_from_quaternion_coordinates": [0, 1, 2, 4, 5, 6, 3, 7, 8, 9, 11, 12, 13, 10],
                             "v": ["v_B1_local_x", "v_B1_local_y", "v_B1_local_z"] + U[2][3:], "frame": "G2",
                             "maps": route_maps("q = quaternion coordinates with both quaternions scalar last "
                                                "(x, y, z, w)", f"v = case-2 body speeds with the first block "
                                                f"replaced by {R1} s1_dot (free-flyer linear velocity in B1)")},
        "euler_route": {"model": "two_body_euler.urdf", "q": Q12, "v": U[3], "frame": "G2",
                        "maps": {"3": "q = q, v = u (case 3 only)"}},
    }
