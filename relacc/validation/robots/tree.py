"""relacc's own tree as an evaluator in ``relacc compare``: the note's method on the model MuJoCo compiled.

relacc reads the model through MuJoCo's compiler (the reference adapter's tree,
:attr:`relacc.engines.base.Adapter.reference`), so its *structure* is MuJoCo's by construction and it takes no
part in the audit. What it adds is an independent *evaluation*: positions, partial velocities, their rates and Kane's
equations by :mod:`relacc.core.tree` and :mod:`relacc.dynamics.tree`, sharing no code with any engine.

:class:`TreeRobot` answers in the common (MuJoCo's, case 2) coordinates for any of the three cases: the
state goes to the case's coordinates (:func:`relacc.core.tree.convert`), relacc evaluates there, and the
answer comes back through the case's speed map ``u_c = T u_2`` (``T`` per ball or free joint from
:func:`relacc.core.tree.walk.angular_map`): ``M = T^T M_c T``, ``bias = T^T (b_c + M_c T_dot u_2)``,
``J = J_c T``, ``J_dot u_2 = Vdot_c u_c + J_c T_dot u_2``, exactly as the engines' adapters map theirs.
"""

from __future__ import annotations

import numpy as np

from relacc.core.tree import convert, tree_kinematics
from relacc.dynamics.tree import tree_accelerations, tree_dynamics
from relacc.engines.base import Dynamics, Points


class TreeRobot:
    """relacc's tree of ``reference``'s compiled model, evaluated in ``case`` and answered in MuJoCo's coordinates
    (the interface of :class:`relacc.engines.base.Adapter` that a comparison uses: ``dynamics``, ``kinematics``)."""

    def __init__(self, reference, case: int = 2):
        self.case = int(case)
        self.engine = f"relacc (case {self.case})"
        self.tree = reference.reference
        self.model, self.joint_names, self.path = reference.model, reference.joint_names, reference.path
        self.default_q = reference.default_q  # MuJoCo's qpos0
        self.structure = reference.structure
        self.dofs, self.qdofs = np.arange(self.tree.nv), np.arange(self.tree.nq(2))
        self.extra_dofs = 0
        self.warnings: list[str] = []
        self.links = {reference.body_name(b): [c - 1 for c in bodies] for b, bodies in reference.groups.items()}

    def _map(self, q, v):
        """``(q_c, u_c, T (nv, nv), T_dot v (nv,))``: the state in the case's coordinates and its speed map."""
        nv, c = self.tree.nv, self.case
        # u_c = T u_2 and, at zero u_2 rates, udot_c = T_dot u_2
        q_c, u_c, Tdv = convert(self.tree, q, v, np.zeros(nv), source=2, target=c)
        if c == 2:
            return q_c, u_c, np.eye(nv), np.zeros(nv)
        T = convert(self.tree, np.broadcast_to(q, (nv, len(q))), np.eye(nv), source=2, target=c)[1].T
        return q_c, u_c, T, Tdv

    def dynamics(self, q, v) -> Dynamics:
        q_c, u_c, T, Tdv = self._map(q, v)
        d = tree_dynamics(self.tree, self.case, q_c, u_c)
        rest = tree_dynamics(self.tree, self.case, q_c, np.zeros_like(u_c))
        M = T.T @ d.M @ T
        bias = T.T @ (-d.f + d.M @ Tdv)
        forward = np.linalg.solve(T, tree_accelerations(self.tree, self.case, q_c, u_c) - Tdv)
        return Dynamics(M, bias, T.T @ (-rest.f), forward)

    def kinematics(self, q, v, a, links) -> Points:
        q_c, u_c, T, Tdv = self._map(q, v)
        k = tree_kinematics(self.tree, self.case, q_c, u_c, T @ np.asarray(a, dtype=float) + Tdv)
        mass = np.array([b.mass for b in self.tree.bodies])
        n = len(links)
        pos, J, Jdv, acc = np.zeros((n, 3)), np.zeros((n, 3, self.tree.nv)), np.zeros((n, 3)), np.zeros((n, 3))
        for i, name in enumerate(links):
            bodies = self.links[name]
            w = mass[bodies] / mass[bodies].sum()
            pos[i] = np.einsum("b,bk->k", w, k.position[bodies])
            Vc = np.einsum("b,bkj->kj", w, k.V[bodies])
            J[i] = Vc @ T
            Jdv[i] = np.einsum("b,bkj->kj", w, k.Vdot[bodies]) @ u_c + Vc @ Tdv
            acc[i] = np.einsum("b,bk->k", w, k.acceleration[bodies])
        return Points(pos, J, None, Jdv, acc)
