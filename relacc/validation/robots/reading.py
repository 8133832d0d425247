"""relacc's own reading of a file (:mod:`relacc.reading`) as what ``relacc compare`` holds every engine to.

:func:`structure` gives the reading the same shape as an engine's (:class:`relacc.engines.base.Structure`), at the
reference configuration (hinges and slides at their ``ref``, balls at identity, free bodies as placed: MuJoCo's
``qpos0``): joints with their world axis and anchor (a hinge's anchor moved to the point of its axis nearest the
world origin, as every adapter gives it), armature and damping; links, each a moving body and the bodies welded to
it (named by the moving body), with their mass, mass centre and inertia in world components; gravity; the total
mass of the moving links. Bodies welded to the world carry none of the dynamics and are left out, as the engines'.
"""

from __future__ import annotations

import numpy as np

from relacc.core.tree import tree_kinematics
from relacc.core.tree.coordinates import reference_q
from relacc.engines.base import BuiltJoint, Link, Structure, combine, moving_mass

BACKEND = "reference"
"""The backend ``relacc compare`` evaluates its reading with, kinematics and forward dynamics alike (plain numpy:
:func:`relacc.tree_kinematics`'s walk, :func:`relacc.tree_accelerations`' Kane's equations solved by Cholesky; each
agrees with the compiled kernels to rounding). A comparison evaluates one state and a few dozen, where numpy takes
milliseconds, while the compiled kernels cost 0.4 s to load from numba's cache in each process and, on the first
run, 8-9 s to compile (gymnasium's humanoid's kinematics) or 20 s (example-robot-data's romeo, a tree beyond the
lanes kernel: CRBA): a pre-commit hook's fresh environment paid that at every install (benchmarks/history.md)."""


def groups(tree) -> dict[int, list[int]]:
    """``{moving body index: [it and the bodies welded to it]}``; bodies welded to the world left out."""
    head: dict[int, int] = {}
    out: dict[int, list[int]] = {}
    for b, body in enumerate(tree.bodies):
        head[b] = b if body.joints else (head[body.parent] if body.parent >= 0 else -1)
        if head[b] >= 0:
            out.setdefault(head[b], []).append(b)
    return out


def structure(reading) -> Structure:
    """The reading as a :class:`relacc.engines.base.Structure` (module docstring)."""
    tree = reading.tree
    q = reference_q(tree, 2)
    k = tree_kinematics(tree, 2, q, np.zeros(tree.nv), backend=BACKEND)
    R = k.rotation
    origin = k.position - np.einsum("bij,bj->bi", R, np.array([b.com for b in tree.bodies]))
    joints = []
    for b, j in tree.joints:
        body = tree.bodies[b]
        axis = R[b] @ j.axis if j.type in ("hinge", "slide") else None
        anchor = origin[b] + R[b] @ j.pos
        if j.type == "hinge":
            anchor = anchor - (anchor @ axis) * axis
        joints.append(BuiltJoint(j.name, j.type, body.name, axis, None if j.type == "slide" else anchor,
                            np.array(j.armature, dtype=float), reading.joint_damping(j.name, j.nv),
                            reading.sensitivity.get(j.name, 0.0)))
    links = []
    for head, members in groups(tree).items():
        parts = [(tree.bodies[c].mass, k.position[c], R[c] @ tree.bodies[c].inertia @ R[c].T) for c in members]
        mass, com, inertia = combine(parts)
        links.append(Link(tree.bodies[head].name, tuple(tree.bodies[c].name for c in members), mass, com, inertia))
    return Structure(tree.nq_in(2), tree.nv, tuple(joints), tuple(links), np.array(tree.gravity, dtype=float),
                     moving_mass(tuple(links)), tree.body_names)
