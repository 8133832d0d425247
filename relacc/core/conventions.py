"""What every reported quantity means: point, frame of components, kind, units.

One table, used by the command line, ``relacc check`` and the report, so a
number never travels without its meaning.
"""

from __future__ import annotations

from enum import StrEnum


class Quantity(StrEnum):
    """Every quantity relacc compares between evaluators, one vocabulary for the chain and for models: each member's
    value is its display name (and its key in the JSON). The chain's G2 (:data:`QUANTITIES`, meanings in
    :data:`MEANINGS`) and a model file's (:data:`MODEL_QUANTITIES`, meanings in :data:`MODEL_MEANINGS`)."""

    POSITION = "position"
    VELOCITY = "velocity"
    ACCELERATION = "acceleration"
    V = "V"
    VDOT = "Vdot"
    MASS_MATRIX = "mass matrix"
    BIAS_FORCES = "bias forces"
    GRAVITY_FORCES = "gravity forces"
    FORWARD_DYNAMICS = "forward dynamics"
    COM_POSITION = "COM position"
    COM_JACOBIAN = "COM Jacobian"
    JDOT_V = "J_dot v"
    CLASSICAL_ACCELERATION = "classical acceleration"


class Route(StrEnum):
    """How an engine models the note's chain (each engine's card says what each route is): ``QUATERNION``, cases 1 to
    3 through unit quaternions (``two_body.xml``); ``EULER``, case 3 only, through the 1-2-3 angles as three hinges
    each (``two_body_euler.xml``, ``.urdf``)."""

    QUATERNION = "quaternion"
    EULER = "euler"


QUANTITIES = (Quantity.POSITION, Quantity.VELOCITY, Quantity.ACCELERATION, Quantity.V, Quantity.VDOT)
"""The outputs of :func:`relacc.g2_kinematics` that are cross-validated, in report order."""
MODEL_QUANTITIES = (Quantity.MASS_MATRIX, Quantity.BIAS_FORCES, Quantity.GRAVITY_FORCES, Quantity.FORWARD_DYNAMICS,
                    Quantity.COM_POSITION, Quantity.COM_JACOBIAN, Quantity.JDOT_V, Quantity.CLASSICAL_ACCELERATION)
"""What ``relacc compare`` compares between evaluators of a model file, in report order."""

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


CONVENTIONS: dict[str, str] = {q: _sentence(q) for q in QUANTITIES}
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


MODEL_MEANINGS: dict[str, str] = {
    Quantity.MASS_MATRIX: "M (nv x nv) over the shared speeds, in case c's speeds",
    Quantity.BIAS_FORCES: "Coriolis, centrifugal and gravity generalized forces, M a + bias = tau",
    Quantity.GRAVITY_FORCES: "bias at zero speeds",
    Quantity.FORWARD_DYNAMICS: "a = M^-1 (-bias): no passive force, actuator or contact",
    Quantity.COM_POSITION: "each link's mass centre, fixed components, m",
    Quantity.COM_JACOBIAN: "d v_G / d u per link, fixed components",
    Quantity.JDOT_V: "each link's mass centre, fixed components, m/s^2 (classical: a = J u_dot + J_dot u)",
    Quantity.CLASSICAL_ACCELERATION: "each link's mass centre at random speed rates, fixed components, m/s^2 "
                                     "(classical)",
}
"""What each of a model's compared quantities is: which point, which components, classical or spatial."""
