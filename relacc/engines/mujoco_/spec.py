"""Reading a model file through MuJoCo's compiler: the spec, the compiled model, its warnings, relacc's tree of it.

Imports only ``mujoco``. The file is parsed into an ``MjSpec`` (includes and default classes resolved) and a copy is
compiled (compiling edits a spec in place where it fuses static bodies). MuJoCo's warnings are collected (never
printed, never appended to ``MUJOCO_LOG.TXT``): :func:`captured_warnings`.

relacc's tree of a compiled model (:func:`tree_of`) takes MuJoCo's numbers: bodies in MuJoCo's order, their
placement ``body_pos``/``body_quat``, joints' ``jnt_pos``/``jnt_axis``, ``qpos0`` as hinges' and slides' ``ref``,
``dof_armature``, the inertia ``body_ipos``, ``body_mass`` and ``body_inertia`` turned by ``body_iquat`` into body
components, and the gravity of ``<option>`` (zero when the model disables gravity). Named points: every site, and
every body the compiler fused into another (``fusestatic``, the default for URDF: a URDF's fixed links), at its
place in the body it was fused into.
"""

from __future__ import annotations

import contextlib
import os
import warnings as warnings_module
from pathlib import Path

import mujoco
import numpy as np

from relacc.core.rotations import matrix_from_quaternion
from relacc.core.tree.model import Body, Joint, Point, Tree
from relacc.engines.urdf import dynamics_text, is_urdf
from relacc.errors import ModelError
from relacc.files import regular_file

VERSION = tuple(int("".join(c for c in part if c.isdigit()) or 0) for part in mujoco.__version__.split(".")[:3])
"""MuJoCo's version as numbers: its API differences are handled by version, not guessed from attributes."""

TYPES = {int(mujoco.mjtJoint.mjJNT_FREE): "free", int(mujoco.mjtJoint.mjJNT_BALL): "ball",
         int(mujoco.mjtJoint.mjJNT_SLIDE): "slide", int(mujoco.mjtJoint.mjJNT_HINGE): "hinge"}

WARNINGS_KEPT = 1000
"""MuJoCo's warnings are kept in memory, the newest this many, for the command that caused them."""

_WARNINGS: list[str] = []


def _warning(message: str) -> None:
    """MuJoCo's warning handler: keep the message (one line) for relacc's output, never the terminal or a file."""
    _WARNINGS.append(" ".join(str(message).split()))
    del _WARNINGS[:-WARNINGS_KEPT]


# Without a handler MuJoCo prints its warnings and appends them to MUJOCO_LOG.TXT in the working
# directory; relacc reports them in its own output instead (captured_warnings).
mujoco.set_mju_user_warning(_warning)


@contextlib.contextmanager
def captured_warnings():
    """Inside the block, MuJoCo's warnings are collected into the list it yields (one line each)."""
    start = len(_WARNINGS)
    got: list[str] = []
    try:
        yield got
    finally:
        got.extend(_WARNINGS[start:])
        del _WARNINGS[start:]


def load_spec(path) -> "mujoco.MjSpec":
    """The file's ``MjSpec`` (MuJoCo's parse: includes and default classes resolved).

    Raises:
        ModelError: a missing file or MuJoCo's parser message (it names the element and line).
    """
    path = regular_file(path, ModelError, "model file")
    text = dynamics_text(path)[0] if is_urdf(path) else None  # a URDF's kinematics and inertials only
    try:
        # the file by its absolute path: given a relative one, MuJoCo (4.0.0) looks for a mesh that an included file in
        # a subfolder names relative to itself under the working directory instead (genesis-world's franka_sim)
        return mujoco.MjSpec.from_file(os.path.abspath(path)) if text is None else mujoco.MjSpec.from_string(text)
    except Exception as exc:  # mujoco raises ValueError with the parser's message
        raise ModelError(f"{path}: MuJoCo cannot read it: {' '.join(str(exc).split())}") from None


def compile_spec(spec, path) -> tuple["mujoco.MjModel", list[str]]:
    """``(model, warnings)``: the compiled spec and MuJoCo's warnings while compiling.

    Raises:
        ModelError: MuJoCo's compiler message (a missing mesh, a massless moving body, ...).
    """
    try:
        with warnings_module.catch_warnings(record=True) as caught, captured_warnings() as own:
            warnings_module.simplefilter("always")  # MuJoCo's Python bindings warn through here
            model = spec.compile()
    except Exception as exc:
        raise ModelError(f"{path}: MuJoCo cannot compile it: {' '.join(str(exc).split())}") from None
    note = dynamics_text(path)[1] if is_urdf(path) else None
    return model, [" ".join(str(w.message).split()) for w in caught] + own + ([note] if note else [])


def rigid_groups(model) -> dict[int, list[int]]:
    """``{moving body: [it and the bodies welded to it]}``; bodies welded to the world are left out."""
    head = {0: 0}
    groups: dict[int, list[int]] = {}
    for b in range(1, model.nbody):
        head[b] = b if model.body_jntnum[b] > 0 else head[int(model.body_parentid[b])]
        if head[b]:
            groups.setdefault(head[b], []).append(b)
    return groups


def body_name(model, b: int) -> str:
    return model.body(b).name or f"body {b}"


def joint_name(model, j: int) -> str:
    return model.joint(j).name or f"joint {j}"


def tree_of(model, name: str = "", source: str = "", fused: tuple = ()) -> Tree:
    """A compiled ``MjModel`` as a :class:`relacc.Tree` (see the module docstring); ``fused``: extra points."""
    m = model
    bodies = []
    for b in range(1, m.nbody):
        joints = []
        for j in range(int(m.body_jntadr[b]), int(m.body_jntadr[b] + m.body_jntnum[b])):
            kind = TYPES[int(m.jnt_type[j])]
            d = int(m.jnt_dofadr[j])
            nv = {"free": 6, "ball": 3}.get(kind, 1)
            joints.append(Joint(joint_name(m, j), kind, pos=m.jnt_pos[j].copy(),
                                axis=m.jnt_axis[j].copy() if kind in ("hinge", "slide") else np.array([0.0, 0.0, 1.0]),
                                ref=float(m.qpos0[m.jnt_qposadr[j]]) if kind in ("hinge", "slide") else 0.0,
                                armature=m.dof_armature[d:d + nv].copy()))
        R = matrix_from_quaternion(m.body_iquat[b])
        inertia = R @ np.diag(m.body_inertia[b]) @ R.T
        bodies.append(Body(body_name(m, b), int(m.body_parentid[b]) - 1, pos=m.body_pos[b].copy(),
                           quat=m.body_quat[b].copy(), joints=tuple(joints), mass=float(m.body_mass[b]),
                           com=m.body_ipos[b].copy(), inertia=0.5 * (inertia + inertia.T)))
    points = [Point(m.site(s).name or f"site {s}", int(m.site_bodyid[s]) - 1, m.site_pos[s].copy())
              for s in range(m.nsite)]
    taken = {p.name for p in points}
    points += [p for p in fused if p.name not in taken]
    gravity = np.zeros(3) if m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY else m.opt.gravity.copy()
    return Tree(name, tuple(bodies), gravity=gravity, points=tuple(points), source=source)


def fused_points(spec, model, path) -> tuple:
    """Bodies the compiler fused away (``fusestatic``), as points of the body that took them."""
    kept = {model.body(b).name for b in range(model.nbody)}
    whole = spec.copy()
    whole.compiler.fusestatic = False
    try:
        full, _ = compile_spec(whole, path)
    except ModelError:  # the fused model compiled; without fusing there is nothing to add
        return ()
    if full.nbody == model.nbody:
        return ()
    data = mujoco.MjData(full)
    mujoco.mj_kinematics(full, data)
    points = []
    names = [model.body(i).name for i in range(1, model.nbody)]
    for b in range(1, full.nbody):
        name = full.body(b).name
        if not name or name in kept:
            continue
        anc = int(full.body_parentid[b])
        while anc and full.body(anc).name not in kept:
            anc = int(full.body_parentid[anc])
        R = data.xmat[anc].reshape(3, 3)
        rel = R.T @ (data.xpos[b] - data.xpos[anc])
        points.append(Point(name, names.index(full.body(anc).name) if anc else -1, rel))
    return tuple(points)


def read_tree(path) -> Tree:
    """Read an MJCF (``.xml``) or URDF (``.urdf``) file into a :class:`relacc.Tree` through MuJoCo's compiler.

    Raises:
        ModelError: MuJoCo cannot read or compile the file (its message names the element), or reads no body.
    """
    path = Path(path)
    spec = load_spec(path)
    model, _ = compile_spec(spec.copy(), path)
    return tree_from(spec, model, path)


def tree_from(spec, model, path) -> Tree:
    """relacc's tree of a compiled ``model`` of ``spec`` (read from ``path``), fused bodies as points."""
    if model.nbody < 2:
        raise ModelError(f"{path}: MuJoCo reads no body besides the world in it: there is nothing to evaluate")
    return tree_of(model, spec.modelname or Path(path).stem, str(path), fused_points(spec, model, path))
