"""What every reported quantity means: point, frame of components, kind, units.

One table, used by the command line, ``relacc check`` and the report, so a
number never travels without its meaning.
"""

from __future__ import annotations

from enum import StrEnum

QUANTITIES = ("position", "velocity", "acceleration", "V", "Vdot")
"""The outputs of :func:`relacc.g2_kinematics` that are cross-validated."""

SYMBOLS = {
    "position": "r_G2",
    "velocity": "v_G2",
    "acceleration": "a_G2",
    "V": "V",
    "Vdot": "Vdot",
}

MEANINGS = {
    # quantity: (point, what, components, kind, units)
    "position": ("G2", "position from R's origin", "fixed-frame", "", "m"),
    "velocity": ("G2", "velocity in R", "fixed-frame", "", "m/s"),
    "acceleration": ("G2", "acceleration in R", "fixed-frame", "classical (d2r/dt2), not spatial", "m/s^2"),
    "V": ("G2", "partial velocity matrix, v = V u", "fixed-frame", "3x12", "m/s per unit of each speed"),
    "Vdot": ("G2", "dV/dt along the motion, a = V udot + Vdot u", "fixed-frame", "3x12", "V's units per second"),
}
"""Structured meaning of each quantity: point, what, components, kind, units."""


def _sentence(q: str) -> str:
    point, what, comps, kind, units = MEANINGS[q]
    return f"{point} {what}; {comps} components" + (f"; {kind}" if kind else "") + f"; {units}"


CONVENTIONS = {q: _sentence(q) for q in QUANTITIES}
"""One line per quantity, printed beside every number."""

CASE_NAMES = {
    1: "fixed-frame angular velocity components",
    2: "body-frame angular velocity components",
    3: "1-2-3 orientation angle rates",
}

SPEEDS = {
    1: "[s1_dot (fixed), omega_B1 (fixed), s2'_dot (B1), omega_hat_B2 (B1)]",
    2: "[s1_dot (fixed), omega'_B1 (B1), s2'_dot (B1), omega_hat'_B2 (B2)]",
    3: "[s1_dot (fixed), theta_B1_dot, s2'_dot (B1), theta_B2_dot]",
}

COORDINATES = {
    1: "[s1 (fixed), quat_B1 (w,x,y,z), s2' (B1), quat_B2/B1 (w,x,y,z)]",
    2: "[s1 (fixed), quat_B1 (w,x,y,z), s2' (B1), quat_B2/B1 (w,x,y,z)]",
    3: "[s1 (fixed), theta_B1 (1-2-3), s2' (B1), theta_B2 (1-2-3)]",
}

ENGINE_MAPPINGS = {
    ("mujoco", "quaternion"): (
        "two_body.xml; qpos = [s1, quat_B1 (w first), s2', quat_B2/B1 (w first)]; "
        "qvel = [s1_dot (world), omega'_B1 (B1), s2'_dot, omega_hat'_B2 (B2)] = Case 2 speeds; "
        "G2: mj_jac, mj_jacDot (after mj_comVel), mj_objectAcceleration with gravity 0"
    ),
    ("mujoco", "euler"): (
        "two_body_euler.xml; qpos = case-3 q, qvel = case-3 u (slides, hinges x, y, z); no map"
    ),
    ("pinocchio", "quaternion"): (
        "two_body.xml, composite joint split; q = [s1, quat_B1 (x,y,z,w), s2', quat_B2/B1 (x,y,z,w)]; "
        "v = [[R_B1] s1_dot (B1), omega'_B1, s2'_dot, omega_hat'_B2]; "
        "a = [[R_B1] s1_ddot - omega'_B1 x [R_B1] s1_dot, ...]; G2: LOCAL_WORLD_ALIGNED frame "
        "Jacobian, its time variation, getFrameClassicalAcceleration"
    ),
    ("pinocchio", "euler"): (
        "two_body_euler.urdf; q = case-3 q, v = case-3 u (prismatic, revolute x, y, z); no map"
    ),
    ("drake", "quaternion"): (
        "plant built from the TOML: two QuaternionFloatingJoints (world->B1, B1 at q2'->B2); "
        "q = [quat_B1 (w first), s1, quat_B2/B1 (w first), s2']; v = [omega_B1 (fixed), s1_dot (fixed), "
        "omega_hat_B2 (B1), s2'_dot (B1)] = Case 1 speeds reordered; G2: CalcJacobianTranslationalVelocity, "
        "J_dot by AutoDiffXd along q_dot = N(q) v, acceleration from CalcSpatialAccelerationsFromVdot shifted to G2"
    ),
    ("drake", "euler"): (
        "two_body_euler.urdf through Drake's URDF parser; q = case-3 q, v = case-3 u; no map"
    ),
}

ENGINE_LABELS = {"relacc": "relacc", "pinocchio": "Pinocchio", "mujoco": "MuJoCo", "drake": "Drake"}
"""How each engine's name is written in sentences."""

DRAKE_SCHEMES = ("semi_explicit_euler", "explicit_euler", "runge_kutta2", "runge_kutta3", "runge_kutta5",
                 "bogacki_shampine3", "implicit_euler", "radau1", "radau3", "velocity_implicit_euler")
"""Drake's integration schemes (``ResetIntegratorFromFlags``) that relacc offers; Drake has no RK4."""

ENGINE_INTEGRATORS = {
    "relacc": ("rk4", "euler"),
    "pinocchio": ("rk4", "euler"),
    "mujoco": ("rk4", "euler", "implicit", "implicitfast"),
    "drake": ("euler",) + DRAKE_SCHEMES,
}
"""The integrators each engine has, by the names scenes use. ``euler`` is semi-implicit Euler everywhere
(MuJoCo's ``mjINT_EULER``, Drake's ``semi_explicit_euler``: ``v`` first, then ``q`` with the new ``v``)."""


TREE_JOINTS = {
    "free": ("[p, quat] (7)", "[p, theta] (6)", "[p_dot, omega], omega in fixed components",
             "[p_dot, omega'], omega' in body components", "[p_dot, theta_dot]"),
    "ball": ("quat (4)", "theta (3)", "relative angular velocity, parent body's components",
             "relative angular velocity, the body's components", "theta_dot"),
    "hinge": ("angle (rad)", "angle (rad)", "rate (rad/s)", "rate (rad/s)", "rate (rad/s)"),
    "slide": ("displacement (m)", "displacement (m)", "rate (m/s)", "rate (m/s)", "rate (m/s)"),
}
"""A model's coordinates and speeds at each joint type: ``(q cases 1-2, q case 3, u case 1, u case 2, u case 3)``.
``p``: the body frame's origin, fixed components; ``theta``: 1-2-3 body-fixed angles of the same rotation as
``quat`` (``Rx Ry Rz``). Case 2 is MuJoCo's ``qpos``/``qvel`` as they are (``docs/trees.md``)."""

TREE_ENGINE_SPEEDS = {
    "mujoco": "case 2 as it is: a free joint's v = [p_dot (world), omega (body)], a ball's omega in the child's "
              "components; quaternions (w, x, y, z)",
    "pinocchio": "a free joint's v = [R^T p_dot, omega], both in body components (T = diag(R^T, I)); quaternions "
                 "(x, y, z, w); an unbounded revolute q = (cos, sin); ball, hinge and slide speeds as case 2",
    "drake": "a free joint's v = [omega, p_dot], both in the parent's components (case 1's, reordered); a ball is a "
             "BallRpyJoint (roll-pitch-yaw q, omega in the parent's components); several joints on one body a chain "
             "of massless bodies",
}
"""Each engine's own speeds at a model's joints, which its adapter maps to case 2 (``v_e = T(q) v``) once."""

class ModelQuantity(StrEnum):
    """What ``relacc compare`` compares between evaluators of a model file, in report order; each member's value is
    its display name (and its key in the JSON), its meaning in :data:`MODEL_MEANINGS`."""

    MASS_MATRIX = "mass matrix"
    BIAS_FORCES = "bias forces"
    GRAVITY_FORCES = "gravity forces"
    FORWARD_DYNAMICS = "forward dynamics"
    COM_POSITION = "COM position"
    COM_JACOBIAN = "COM Jacobian"
    JDOT_V = "J_dot v"
    CLASSICAL_ACCELERATION = "classical acceleration"


MODEL_MEANINGS = {
    ModelQuantity.MASS_MATRIX: "M (nv x nv) over the shared speeds, in case c's speeds",
    ModelQuantity.BIAS_FORCES: "Coriolis, centrifugal and gravity generalized forces, M a + bias = tau",
    ModelQuantity.GRAVITY_FORCES: "bias at zero speeds",
    ModelQuantity.FORWARD_DYNAMICS: "a = M^-1 (-bias): no passive force, actuator or contact",
    ModelQuantity.COM_POSITION: "each link's mass centre, fixed components, m",
    ModelQuantity.COM_JACOBIAN: "d v_G / d u per link, fixed components",
    ModelQuantity.JDOT_V: "each link's mass centre, fixed components, m/s^2 (classical: a = J u_dot + J_dot u)",
    ModelQuantity.CLASSICAL_ACCELERATION: "each link's mass centre at random speed rates, fixed components, m/s^2 "
                                          "(classical)",
}
"""What each of a model's compared quantities is: which point, which components, classical or spatial."""
