"""How Drake's parsers read a model differently from MuJoCo, as changes to MuJoCo's ``MjSpec``.

Each reading is ``(key, text, applies(spec), change(spec))``: the audit
(:func:`relacc.validation.robots.audit.explain`) recompiles MuJoCo's model with ``change`` and takes
``text`` as the cause of the differences that disappear. These functions touch only the spec (no
``pydrake``, no ``mujoco`` import); :class:`relacc.engines.drake_.DrakeAdapter` binds the armature
reading to the joints its plant has an actuator on.
"""

from __future__ import annotations

import warnings

import numpy as np

from relacc.core.rotations import matrix_from_quaternion
from relacc.errors import ModelError


def _loose_roots(spec):
    """Bodies on the world with no joint: MuJoCo welds them; Drake's URDF parser leaves such a root link free."""
    return [b for b in spec.worldbody.bodies if len(b.joints) == 0]


def _free_roots(spec):
    for body in _loose_roots(spec):
        body.add_freejoint()
    spec.compiler.boundmass = spec.compiler.boundinertia = 1e-14  # MuJoCo refuses massless moving bodies


def unactuated(spec, driven=None):
    """Joints with armature and no actuator Drake reads on them (Drake drops their armature).

    ``driven``: the joints Drake made an actuator for (it reads ``<motor>`` and ``<position>``, not
    ``<velocity>``, ``<intvelocity>`` or ``<general>``); default: every actuator's joint in the spec.
    """
    driven = {a.target for a in spec.actuators} if driven is None else driven
    return [j for j in spec.joints if j.armature > 0 and j.name not in driven]


def drop_armature(spec, driven=None):
    for j in unactuated(spec, driven):
        j.armature = 0.0


def _is_stacked(body) -> bool:
    """A body with several joints and a position offset from its parent."""
    return len(body.joints) > 1 and bool(np.any(np.asarray(body.pos) != 0))


def _stacked(spec):
    return [b for b in spec.bodies if _is_stacked(b)]


def _orientations(spec) -> dict[int, np.ndarray]:
    """``{index in spec.bodies: unit quaternion}`` as MuJoCo's compiler resolves each body's orientation.

    A body oriented by ``euler``, ``axisangle``, ``xyaxes`` or ``zaxis`` keeps ``quat = [1, 0, 0, 0]`` in the
    spec until compiled, so the spec's ``quat`` alone is not the body's orientation.
    """
    copy = spec.copy()
    try:
        with warnings.catch_warnings():  # the reference's own compilation already reported MuJoCo's warnings
            warnings.simplefilter("ignore")
            model = copy.compile()
    except Exception as exc:  # mujoco raises ValueError with the compiler's message
        raise ModelError(f"MuJoCo cannot compile the model to resolve body orientations: {exc}") from None
    return {k: np.array(model.body_quat[b.id]) for k, b in enumerate(copy.bodies) if b.id >= 0}


def _joints_at_parent(spec):
    """Every joint but the last of such a body: its ``pos`` and ``axis`` read in the parent's frame."""
    quats = _orientations(spec)
    for k, body in enumerate(spec.bodies):  # by position: the bindings give new wrapper objects at every access
        if not _is_stacked(body):
            continue
        R = matrix_from_quaternion(quats[k])
        for joint in list(body.joints)[:-1]:
            joint.pos = R.T @ (np.asarray(joint.pos, dtype=float) - np.asarray(body.pos, dtype=float))
            joint.axis = R.T @ np.asarray(joint.axis, dtype=float)


def _damped_free(spec):
    """Free joints with damping: Drake's MJCF parser drops it (it warns "not supported for free bodies"). MuJoCo's
    joint type 0 is the free joint."""
    return [j for j in spec.joints if int(j.type) == 0 and np.any(np.asarray(j.damping) != 0)]


def _undamp_free(spec):
    for j in _damped_free(spec):
        j.damping = np.zeros_like(np.asarray(j.damping, dtype=float))


MJCF_READINGS = (
    ("stacked_joints", "Drake's MJCF parser reads the position and axis of every joint but the last of a body with "
     "several joints in the parent body's frame instead of the body's",
     lambda spec: bool(_stacked(spec)), _joints_at_parent),
    ("armature", "Drake's MJCF parser keeps a joint's armature only as the reflected inertia of an actuator it "
     "reads on that joint (<motor> or <position>); joints without one lose it",
     lambda spec: bool(unactuated(spec)), drop_armature),
    ("free_damping", "Drake's MJCF parser drops a free joint's damping (it warns that damping is not supported for "
     "free bodies)", lambda spec: bool(_damped_free(spec)), _undamp_free),
    ("settotalmass", "Drake ignores <compiler settotalmass> (it warns so), which makes MuJoCo scale every mass",
     lambda spec: spec.compiler.settotalmass > 0, lambda spec: setattr(spec.compiler, "settotalmass", -1.0)),
    ("free_root", "Drake's URDF parser leaves a root link that no joint attaches to the world free (a floating "
     "body, 6 more degrees of freedom); MuJoCo and Pinocchio weld it to the world",
     lambda spec: bool(_loose_roots(spec)), _free_roots),
)
"""How Drake's parsers read a file differently from MuJoCo (as in :mod:`relacc.engines.pinocchio_.readings`); each
is applied only where recompiling MuJoCo with it makes a difference disappear."""

ENGINE_READINGS = ()
"""No known difference in Drake's algorithms."""
