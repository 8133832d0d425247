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
    capabilities=frozenset({"PointLoop"}), adaptive=("runge_kutta3", "runge_kutta5"),
    error_controlled=True, own_steppers=True)
