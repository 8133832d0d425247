"""Drake's :class:`relacc.engines.traits.Traits` and integration schemes (imports nothing of Drake)."""

from relacc.core.conventions import Route
from relacc.engines.traits import Traits

DRAKE_SCHEMES = ("semi_explicit_euler", "explicit_euler", "runge_kutta2", "runge_kutta3", "runge_kutta5",
                 "bogacki_shampine3", "implicit_euler", "radau1", "radau3", "velocity_implicit_euler")
"""Drake's integration schemes (``ResetIntegratorFromFlags``) that relacc offers; Drake has no RK4."""

TRAITS = Traits(
    name="drake", label="Drake", order=3, package="pydrake", pip="drake", color="#17becf", marker="+",
    marker_size=8, integrators=("euler",) + DRAKE_SCHEMES,
    speeds="a free joint's v = [omega, p_dot], both in the parent's components (case 1's, reordered); a ball is a "
           "BallRpyJoint (roll-pitch-yaw q, omega in the parent's components); several joints on one body a chain "
           "of massless bodies",
    chain_routes={
        Route.QUATERNION: (
            "plant built from the TOML: two QuaternionFloatingJoints (world->B1, B1 at q2'->B2); q = [quat_B1"
            " (w first), s1, quat_B2/B1 (w first), s2']; v = [omega_B1 (fixed), s1_dot (fixed), omega_hat_B2 "
            "(B1), s2'_dot (B1)] = Case 1 speeds reordered; G2: CalcJacobianTranslationalVelocity, J_dot by "
            'AutoDiffXd along q_dot = N(q) v, acceleration from CalcSpatialAccelerationsFromVdot shifted to '
            'G2'
        ),
        Route.EULER: (
            "two_body_euler.urdf through Drake's URDF parser; q = case-3 q, v = case-3 u; no map"
        ),
    },
    chain_files={Route.QUATERNION: ("two_body.xml", {"build": True}), Route.EULER: ("two_body_euler.urdf", {})},
    capabilities=frozenset({"PointLoop"}), adaptive=("runge_kutta3", "runge_kutta5"),
    error_controlled=True, own_steppers=True)


def chain_export() -> dict:
    """The note's chain in Drake, as ``relacc fixtures --out`` writes it in ``conventions.json``
    (:func:`relacc.fixtures.export.conventions`): each route's model, coordinates and speeds, and every case's
    map to them."""
    from relacc.fixtures.export import Q12, Q14, U, route_maps

    return {
        "quaternion_route": {"model": "built from the TOML: QuaternionFloatingJoint world -> B1, "
                                      "QuaternionFloatingJoint (frame Q2 on B1 at q2') -> B2, frame G2 on B2 "
                                      "at r2'",
                             "q": [Q14[i] for i in (3, 4, 5, 6, 0, 1, 2, 10, 11, 12, 13, 7, 8, 9)],
                             "q_from_quaternion_coordinates": [3, 4, 5, 6, 0, 1, 2, 10, 11, 12, 13, 7, 8, 9],
                             "v": [U[1][i] for i in (3, 4, 5, 0, 1, 2, 9, 10, 11, 6, 7, 8)],
                             "v_from_case_1_speeds": [3, 4, 5, 0, 1, 2, 9, 10, 11, 6, 7, 8],
                             "maps": route_maps("q = [quat_B1, s1, quat_B2B1, s2'] (quaternion first, then "
                                                "translation, per joint)",
                                           "v = [omega_B1 (fixed), s1_dot, omega_hat_B2 (B1), s2'_dot]: "
                                           "case-1 speeds reordered")},
        "euler_route": {"model": "two_body_euler.urdf (Drake's URDF parser)", "q": Q12, "v": U[3],
                        "frame": "G2", "maps": {"3": "q = q, v = u (case 3 only)"}},
    }
