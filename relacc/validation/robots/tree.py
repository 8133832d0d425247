"""relacc's own reading of a model as an evaluator in ``relacc compare``: the note's method on relacc's tree.

relacc reads the file itself (:mod:`relacc.reading`), so its *structure* (:func:`relacc.validation.robots.reading.
structure`) is a fourth, independent opinion of what the file describes, and its *evaluation*: positions, partial
velocities, their rates and Kane's equations by :mod:`relacc.core.tree` and :mod:`relacc.dynamics.tree`, shares no
code with any engine. Its case-2 coordinates are the comparison's common coordinates (MuJoCo's ``qpos``/``qvel``
layout for an MJCF: the joints in the file's order).

:class:`TreeRobot` answers in those (case 2) coordinates for any of the three cases: the state goes to the case's
coordinates (:func:`relacc.core.tree.convert`), relacc evaluates there, and the answer comes back through the case's
speed map ``u_c = T u_2`` (``T`` per ball or free joint from :func:`relacc.core.tree.walk.angular_map`):
``M = T^T M_c T``, ``bias = T^T (b_c + M_c T_dot u_2)``, ``J = J_c T``, ``J_dot u_2 = Vdot_c u_c + J_c T_dot u_2``,
exactly as the engines' adapters map theirs.
"""

from __future__ import annotations

import warnings

import numpy as np

from relacc.core.cases import Case
from relacc.core.states import States
from relacc.core.tree import convert, tree_kinematics
from relacc.core.tree.coordinates import reference_q, rotations
from relacc.dynamics.tree import solve, tree_accelerations, tree_dynamics
from relacc.engines.base import Answering, Answers, Dynamics, Points, mapped_dynamics
from relacc.errors import AccuracyWarning, RelaccError
from relacc.validation.robots.reading import BACKEND, groups, structure


class TreeRobot(Answering):
    """relacc's reading of a file (a :class:`relacc.reading.Reading`), evaluated in ``case`` and answered in its
    case-2 coordinates (the interface of :class:`relacc.engines.base.Adapter` that a comparison uses:
    ``structure``, ``dynamics``, ``kinematics``, ``default_q``). ``backend``: how its kinematics and forward
    dynamics are evaluated (:data:`relacc.validation.robots.reading.BACKEND`, plain numpy, for a comparison;
    ``"auto"``, relacc's compiled kernels, for ``relacc check --model``, which holds them to the engines)."""

    def __init__(self, reading, case: int = 2, matched_to=None, *, backend: str = BACKEND):
        self.case = int(case)
        self.backend = backend
        self.engine = "relacc" if self.case == Case.BODY_FRAME else f"relacc (case {self.case})"
        self.reading = reading
        self.tree = reading.tree
        self.reference = self.tree if matched_to is None else matched_to
        self.path = reading.source
        self.structure = structure(reading)
        self.dofs, self.qdofs = self._match(self.reference)
        self.extra_dofs = 0
        self.warnings: list[str] = list(reading.notes)
        self.links = {self.tree.bodies[b].name: members for b, members in groups(self.tree).items()}
        self._mapped: tuple | None = None  # the last states' map: dynamics and kinematics take the same states
        self.answers = Answers()  # a comparison asks the reference the same states once per engine and case

    def _match(self, reference) -> tuple[np.ndarray, np.ndarray]:
        """``(dofs, qdofs)``: the reference's speeds and positions of this tree's joints (by name, in order): a reading
        of the file an engine's way (:data:`relacc.validation.robots.causes.READINGS`) may have fewer joints.

        Raises:
            ModelError: a joint the reference lacks, or the joints in another order.
        """
        if reference is self.tree:
            return np.arange(self.tree.nv), np.arange(self.tree.nq_in(2))
        dofs, qdofs = [], []
        for _, joint in self.tree.joints:
            k = reference.joint(joint.name)
            kind = reference.joints[k][1]
            a, d = reference.qadr(2)[k], reference.dofadr[k]
            qdofs += range(a, a + {"free": 7, "ball": 4}.get(kind.type, 1))
            dofs += range(d, d + kind.nv)
        if dofs != sorted(dofs):
            from relacc.errors import ModelError

            raise ModelError(f"{self.path}: an engine's reading orders the joints otherwise")
        return np.array(dofs, dtype=int), np.array(qdofs, dtype=int)

    def _own(self, q, v):
        """States of the reference ``(n, nq_ref)``, ``(n, nv_ref)`` in this tree's coordinates."""
        if self.reference is self.tree:
            return q, v
        return q[:, self.qdofs], v[:, self.dofs]

    def default_q(self) -> np.ndarray:
        """``(nq,)`` the reference configuration (hinges and slides at ``ref``, balls at identity, free bodies as
        placed: MuJoCo's ``qpos0``)."""
        return reference_q(self.tree, 2)

    def states(self, n: int, seed: int) -> States:
        """The reference configuration at rest, then ``n`` random states of this reading's tree in case 2: ``n + 1``
        states, ``q (n + 1, nq)`` (m, rad, unit quaternions), ``u`` and ``udot (n + 1, nv)`` (m/s, rad/s and their
        rates; zero at rest), the states every comparison of the file evaluates: the tree's draw
        (:func:`relacc.core.tree.random_states`, ``numpy.random.default_rng(seed)``) with each limited hinge or slide
        uniform in the range the file gives it, and the model's size the largest distance of a link's mass centre from
        its frame (at least 1 m)."""
        from relacc.core.tree.coordinates import random_states

        size = float(max([np.linalg.norm(link.com) for link in self.structure.links] + [1.0]))
        drawn = random_states(self.tree, 2, n, seed, size=size, ranges=self.reading.ranges)
        nv = self.tree.nv
        rest = States(Case.BODY_FRAME, self.default_q()[None], np.zeros((1, nv)), np.zeros((1, nv)), seed, self.tree)
        return rest.and_then(drawn, seed)

    def _map(self, q, v):
        """``(q_c, u_c, T (n, nv, nv), T_dot v (n, nv))``: states ``(n, nq)``, ``(n, nv)`` in the case's coordinates
        and their speed maps."""
        key = (q.shape, v.shape, q.tobytes(), v.tobytes())
        if self._mapped is not None and self._mapped[0] == key:
            return self._mapped[1]
        nv, c, n = self.tree.nv, self.case, len(q)
        # u_c = T u_2 and, at zero u_2 rates, udot_c = T_dot u_2
        q_c, u_c, Tdv = convert(self.tree, q, v, np.zeros_like(v), source=2, target=c)
        if c == Case.BODY_FRAME:
            T = np.broadcast_to(np.eye(nv), (n, nv, nv))
            Tdv = np.zeros((n, nv))
        else:
            # T is the identity but for each ball's and free joint's 3 x 3 block of angular speeds (convert maps a
            # joint's own speeds alone): column i of every block, from unit speed i in every block, the three
            # columns' states converted in one batch
            T = np.repeat(np.eye(nv)[None], n, axis=0)
            starts = [d for _, _, _, d in rotations(self.tree, c)]
            if starts:
                unit = np.zeros((3, n, nv))
                for i in range(3):
                    unit[i][:, [d + i for d in starts]] = 1.0
                _, cols, _ = convert(self.tree, np.concatenate([q] * 3), unit.reshape(3 * n, nv), source=2, target=c)
                cols = cols.reshape(3, n, nv)
                for i in range(3):
                    for d in starts:
                        T[:, d:d + 3, d + i] = cols[i][:, d:d + 3]
        for a in (q_c, u_c, T, Tdv):
            a.flags.writeable = False  # kept for the next call on the same states
        self._mapped = (key, (q_c, u_c, T, Tdv))
        return q_c, u_c, T, Tdv

    def _dynamics(self, q, v) -> Dynamics:
        """:class:`Dynamics` at states ``q (n, nq)``, ``v (n, nv)`` of the reference (case 2), evaluated in this case
        (:meth:`relacc.engines.base.Answering.dynamics` answers them once)."""
        q_c, u_c, T, Tdv = self._map(*self._own(q, v))
        n = len(q_c)
        # the states and the same states at rest (the gravity terms) in one evaluation
        d = tree_dynamics(self.tree, self.case, np.concatenate([q_c, q_c]), np.concatenate([u_c, np.zeros_like(u_c)]))
        try:
            with warnings.catch_warnings():  # an ill-conditioned M is in the row's scale already (||M^-1||, module
                warnings.simplefilter("ignore", AccuracyWarning)  # relacc.validation.robots.agreement), not on stderr
                if self.backend == "reference" and self.case != Case.ANGLE_RATES:  # the M and f above, solved as
                    forward = solve(self.tree, d.M[:n], d.f[:n])  # tree_accelerations' reference path solves them
                else:  # case 3's rates are solved in case-2 speeds (tree_accelerations), or the compiled kernels
                    forward = tree_accelerations(self.tree, self.case, q_c, u_c, backend=self.backend)
        except RelaccError:  # a singular M: the comparison solves the shared speeds itself and says so
            forward = np.full(u_c.shape, np.nan)
        return mapped_dynamics(d.M[:n], d.f[:n], d.f[n:], forward, T, Tdv)

    def _kinematics(self, q, v, a, links) -> Points:
        """:class:`Points` ``(n, L, ...)`` of the named links' mass centres at states ``(n, ...)`` of the reference
        (:meth:`relacc.engines.base.Answering.kinematics` answers them once)."""
        q, v = self._own(q, v)
        a = a if self.reference is self.tree else a[:, self.dofs]
        q_c, u_c, T, Tdv = self._map(q, v)
        k = tree_kinematics(self.tree, self.case, q_c, u_c, np.einsum("nij,nj->ni", T, a) + Tdv,
                           backend=self.backend)
        mass = np.array([b.mass for b in self.tree.bodies])
        n, L = len(q), len(links)
        pos, J = np.zeros((n, L, 3)), np.zeros((n, L, 3, self.tree.nv))
        Jdv, acc = np.zeros((n, L, 3)), np.zeros((n, L, 3))
        for i, name in enumerate(links):
            bodies = self.links[name]
            w = mass[bodies] / mass[bodies].sum()
            pos[:, i] = np.einsum("b,nbk->nk", w, k.position[:, bodies])
            Vc = np.einsum("b,nbkj->nkj", w, k.required("V")[:, bodies])
            J[:, i] = Vc @ T
            Jdv[:, i] = (np.einsum("nkj,nj->nk", np.einsum("b,nbkj->nkj", w, k.required("Vdot")[:, bodies]), u_c)
                         + np.einsum("nkj,nj->nk", Vc, Tdv))
            acc[:, i] = np.einsum("b,nbk->nk", w, k.required("acceleration")[:, bodies])
        return Points(pos, J, None, Jdv, acc)
