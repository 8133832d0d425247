"""PyBullet's adapter class and its loader (the package's docstring states the conventions)."""

from __future__ import annotations

import contextlib
import re
from importlib.metadata import version as distribution_version
from pathlib import Path

import numpy as np

from relacc.core.tolerances import BULLET_JACOBI_THRESHOLD
from relacc.core.tree.coordinates import reference_q
from relacc.engines.base import BuiltJoint, Link, Points, Structure, combine, moving_mass
from relacc.engines.fixed_base import GRAVITY, FixedBaseAdapter
from relacc.engines.pybullet_.client import disconnect, pb
from relacc.engines.pybullet_.files import placed_copy
from relacc.engines.urdf import is_urdf
from relacc.errors import EngineError, ModelError
from relacc.isolate import captured_output

__all__ = ["PyBulletAdapter", "load", "version"]

KINDS = {pb.JOINT_REVOLUTE: "hinge", pb.JOINT_PRISMATIC: "slide", pb.JOINT_FIXED: None}
"""PyBullet's joint types relacc matches (a URDF's continuous joint is PyBullet's revolute one)."""


def version() -> str:
    return distribution_version("pybullet")


class PyBulletAdapter(FixedBaseAdapter):
    """A URDF in PyBullet, its root fixed, in a client of its own; ``inertia_from_file``: loaded with
    ``URDF_USE_INERTIA_FROM_FILE`` (else as users call ``loadURDF``, inertias from the collision shapes)."""

    engine = "pybullet"
    point_rates = False
    global_coordinates = frozenset({"velocity", "V", "Vdot"})

    def __init__(self, path, reference, inertia_from_file: bool = False):
        if not is_urdf(path):
            raise ModelError(f"{path}: relacc offers PyBullet URDF files only (its loadMJCF is a partial reader: it "
                             "skips <freejoint> and ball joints and keeps inertias in single precision)")
        self.inertia_from_file = inertia_from_file
        self.engine = "pybullet_file" if inertia_from_file else "pybullet"
        self.client = pb.connect(pb.DIRECT)
        flags = pb.URDF_USE_INERTIA_FROM_FILE if inertia_from_file else 0
        with captured_output(stdout=True) as printed:
            try:
                if Path(path).suffix.lower() == ".urdf":
                    self.body = pb.loadURDF(str(Path(path).resolve()), useFixedBase=True, flags=flags,
                                            physicsClientId=self.client)
                else:  # a xacro: its expansion, from a temporary copy
                    with placed_copy(Path(path)) as copy:
                        self.body = pb.loadURDF(copy, useFixedBase=True, flags=flags, physicsClientId=self.client)
            except pb.error as exc:
                failure = exc
            else:
                failure = None
        if failure is not None:
            disconnect(self.client)
            said = "; ".join(m.removeprefix("PyBullet: ") for m in _messages(printed)
                             if "No inertial data" not in m)  # why it failed, without its notes on the links
            raise ModelError(f"{path}: PyBullet cannot load it: {failure}" + (f" ({said})" if said else ""))
        self._inertial_frames: dict[int, tuple[np.ndarray, np.ndarray]] = {}  # (p, R) of each link, read once
        self.links, joints = self._joints(path)
        movable = [j for j in joints if j["kind"] is not None]
        self.order = [j["index"] for j in movable]  # PyBullet's joint index of each of its speeds, in uIndex order
        matches = self._fixed_base("PyBullet", path, reference, "PyBullet's URDF importer reads a floating joint as a "
                                   "fixed one (measured on pybullet 3.2.7)",
                                   [(j["name"], j["kind"], k, k) for k, j in enumerate(movable)])
        super().__init__(reference, matches, len(movable), len(movable), Path(path), _messages(printed))
        pb.setGravity(*GRAVITY, physicsClientId=self.client)
        self.gravity0 = GRAVITY.copy()
        with self._quiet():  # the first evaluation builds Bullet's inverse-dynamics tree, which prints its warnings
            try:
                self.structure = self._structure()
            except pb.error as exc:  # tiago_dual (129 joints): the actual-state request fails on every link
                disconnect(self.client)
                raise ModelError(f"{path}: PyBullet loads it but answers no link state ({exc}) for its "
                                 f"{len(joints)} "
                                 "joints: relacc cannot read what it built") from None

    def __del__(self):
        try:
            disconnect(self.client)
        except Exception:  # noqa: BLE001 - a client already gone at interpreter exit
            pass

    @property
    def version(self) -> str:
        return version()

    def inertia_allowance(self, reading) -> float:
        """kg m^2: with ``URDF_USE_INERTIA_FROM_FILE``, a file inertia with products of inertia comes back
        diagonalized by Bullet's Jacobi iteration, exact to :data:`relacc.core.tolerances.BULLET_JACOBI_THRESHOLD`
        times its trace (the largest such trace here); the default loading computes its own inertias (no allowance:
        its known reading reproduces them exactly)."""
        if reading is None or not self.inertia_from_file:
            return 0.0
        traces = [np.trace(b.inertia) for b in reading.tree.bodies
                  if np.any(np.abs(b.inertia - np.diag(np.diag(b.inertia))) > 0)]
        return BULLET_JACOBI_THRESHOLD * float(max(traces, default=0.0))

    # --- the model ------------------------------------------------------------------------------------------

    @contextlib.contextmanager
    def _quiet(self):
        """Bullet's C++ prints its warnings on standard output (``b3Warning``: "axis of motion not a unit axis", from
        its inverse-dynamics tree), which would land in a ``--json`` document: captured, and each new one kept in
        :attr:`warnings`."""
        with captured_output(stdout=True) as printed:
            yield
        for message in _messages(printed):
            if message not in self.warnings:
                self.warnings.append(message)

    def _joints(self, path) -> tuple[dict, list[dict]]:
        """``({link name: PyBullet link index}, [each joint's name, kind, index, child link]`` in index order).

        Raises:
            ModelError: a joint relacc does not match (PyBullet's spherical or planar joints).
        """
        links, joints = {}, []
        for j in range(pb.getNumJoints(self.body, physicsClientId=self.client)):
            info = pb.getJointInfo(self.body, j, physicsClientId=self.client)
            name, kind, child = info[1].decode(), info[2], info[12].decode()
            if kind not in KINDS:
                disconnect(self.client)
                raise ModelError(f"{path}: PyBullet's joint {name} "
                                 f"is of its type {kind}, which relacc does not match (revolute, prismatic, fixed)")
            links[child] = j
            joints.append({"name": name, "kind": KINDS[kind], "index": j, "child": child, "damping": info[6]})
        self._joint_info = joints
        return links, joints

    def _set(self, qe, ve=None) -> None:
        ve = np.zeros(len(self.order)) if ve is None else ve
        for k, j in enumerate(self.order):
            pb.resetJointState(self.body, j, float(qe[k]), float(ve[k]), physicsClientId=self.client)

    def _frame(self, link: int) -> tuple[np.ndarray, np.ndarray]:
        """``(c (3,), R (3, 3))``: a link's mass centre in world (m) and its inertial frame's orientation."""
        state = pb.getLinkState(self.body, link, computeForwardKinematics=True, physicsClientId=self.client)
        return np.array(state[0]), np.array(pb.getMatrixFromQuaternion(state[1])).reshape(3, 3)

    def _inertia(self, link: int) -> tuple[float, np.ndarray, np.ndarray]:
        """``(mass, com (3,), inertia about it (3, 3))`` of one PyBullet link at the state set, world components."""
        info = pb.getDynamicsInfo(self.body, link, physicsClientId=self.client)
        c, R = self._frame(link)
        return float(info[0]), c, R @ np.diag(info[2]) @ R.T

    def _link_index(self, name: str) -> int:
        if name not in self.links:
            raise EngineError(f"{self.source}: PyBullet has no link named {name!r} that a joint moves")
        return self.links[name]

    def _structure(self) -> Structure:
        tree = self.reference
        self._set(self.engine_q(reference_q(tree, 2))[0])
        joints = []
        info = {j["index"]: j for j in self._joint_info}
        for mt in self.matches:
            b, jt = tree.joints[mt.joints[0]]
            j = info[self.order[mt.v[0]]]
            link = j["index"]
            c, _ = self._link_frame(link)
            lin, ang = self._jacobian(link, np.zeros(3), self.engine_q(reference_q(tree, 2))[0])
            w, v_c = ang[:, mt.v[0]], lin[:, mt.v[0]]
            axis = anchor = None
            if mt.kind == "hinge":  # the axis, and its point nearest the world origin (v_O = v_c - w x c)
                v_O = v_c - np.cross(w, c)
                axis, anchor = w / np.linalg.norm(w), np.cross(w, v_O) / (w @ w)
            else:
                axis = v_c / np.linalg.norm(v_c)
            joints.append(BuiltJoint(jt.name, mt.kind, tree.bodies[b].name, axis, anchor, np.zeros(1),
                                     np.array([j["damping"]], dtype=float)))
        links = []
        for name, members in self.heads.items():
            parts = [self._inertia(self.links[m]) for m in members if m in self.links]
            mass, com, inertia = combine(parts)
            links.append(Link(name, tuple(m for m in members if m in self.links), mass, com, inertia))
        base = pb.getBodyInfo(self.body, physicsClientId=self.client)[0].decode()
        return Structure(self.nq_e, self.nv_e, tuple(joints), tuple(links), self.gravity0.copy(), moving_mass(links),
                         (base, *self.links))

    def _link_frame(self, link: int) -> tuple[np.ndarray, np.ndarray]:
        """``(o (3,), R (3, 3))``: a link's URDF frame (its joint's frame) in world at the state set, from its inertial
        frame and the inertial frame's place in the link (``getDynamicsInfo``): ``getLinkState``'s own
        ``worldLinkFramePosition`` is rounded to single precision (measured: 0.20000001788139343 for 0.2)."""
        c, R_c = self._frame(link)
        if link not in self._inertial_frames:  # the inertial frame's place in the link does not move
            info = pb.getDynamicsInfo(self.body, link, physicsClientId=self.client)
            turned = np.array(pb.getMatrixFromQuaternion(info[4])).reshape(3, 3)
            self._inertial_frames[link] = (np.array(info[3]), turned)
        p_in, R_in = self._inertial_frames[link]
        R = R_c @ R_in.T
        return c - R @ p_in, R

    def _local(self, link: int, p_W: np.ndarray) -> np.ndarray:
        """A world point fixed on ``link`` as :meth:`_jacobian` takes it, at the state set."""
        o, _ = self._link_frame(link)
        _, R_c = self._frame(link)
        return R_c.T @ (p_W - o)

    def _jacobian(self, link: int, local: np.ndarray, qe: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(linear (3, nv), angular (3, nv))``: ``calculateJacobian`` of the point ``local`` at positions ``qe``.
        ``local`` (m) is the point's offset from the link's URDF frame origin in the link's *inertial* frame's axes:
        PyBullet's documentation says "in link local coordinates around its center of mass", but its numbers take
        the link frame's origin as the point of reference and the inertial frame's axes as the components (measured
        on pybullet 3.2.7: a point 0.1 m off a hinge's axis given as ``[0, 0, 0]`` has a zero Jacobian when the link
        frame sits on the axis; with the Panda's turned inertial frames, the offset in the link frame's axes is
        1.3e-3 to 3.2e-2 m/rad off and in the inertial frame's agrees to 4e-16): :meth:`_local`. Its rows are in the
        base's *inertial* frame's axes, not the world's (measured on pybullet 3.2.7: the rtb-data Trossen arms, whose
        base inertial frame is turned 90 deg, read with every joint axis turned 90 deg and their COM Jacobian "not
        explained"): turned to the world's here."""
        zeros = [0.0] * self.nv_e
        lin, ang = pb.calculateJacobian(self.body, link, [float(x) for x in local], [float(x) for x in qe], zeros,
                                        zeros, physicsClientId=self.client)
        _, base = pb.getBasePositionAndOrientation(self.body, physicsClientId=self.client)
        R = np.array(pb.getMatrixFromQuaternion(base)).reshape(3, 3)  # its components are the base's inertial frame's
        return R @ np.array(lin).reshape(3, self.nv_e), R @ np.array(ang).reshape(3, self.nv_e)


    # --- evaluations ----------------------------------------------------------------------------------------

    def _gravity(self, effects) -> None:
        g = self.gravity0 if effects is None or effects.gravity is None else effects.gravity
        pb.setGravity(*(float(x) for x in g), physicsClientId=self.client)

    def _where(self, spec) -> tuple[int, np.ndarray]:
        """``(link, p_W)``: the PyBullet link a point spec is fixed on and the point in world at the state set."""
        kind, name = spec
        if kind == "com":
            members = [m for m in self.heads[name] if m in self.links]
            return self.links[name], combine(self._inertia(self.links[m]) for m in members)[1]
        if kind == "body":
            link = self._link_index(name)
            o, R = self._link_frame(link)
            body = self.reference.bodies[self.reference.body(name)]
            return link, o + R @ np.asarray(body.com, dtype=float)
        link = self._link_index(name)  # a named point: a link's URDF frame
        return link, self._link_frame(link)[0]

    def load_forces(self, qe, effects, t=0.0) -> np.ndarray:
        """Body loads through ``calculateJacobian`` at each body's mass centre: ``J^T F + J_w^T T``."""
        with self._quiet():
            return self._load_forces(qe, effects, t)

    def _load_forces(self, qe, effects, t) -> np.ndarray:
        tau = np.zeros((len(qe), self.nv_e))
        for i in range(len(qe)):
            self._set(qe[i])
            for name, load in effects.bodies.items():
                link, p_W = self._where(("body", name))
                lin, ang = self._jacobian(link, self._local(link, p_W), qe[i])
                tau[i] += float(load.factor(t[i] if np.ndim(t) else t)) * (lin.T @ load.force + ang.T @ load.torque)
        return tau

    def equations(self, qe, ve, effects=None, t=0.0):
        with self._quiet():
            return self._equations(qe, ve, effects, t)

    def _equations(self, qe, ve, effects, t):
        n = len(qe)
        tau = self.generalized_forces(qe, ve, effects, t)
        M, f = np.empty((n, self.nv_e, self.nv_e)), np.empty((n, self.nv_e))
        zeros = [0.0] * self.nv_e
        self._gravity(effects)
        try:
            for i in range(n):
                q = [float(x) for x in qe[i]]
                M[i] = np.array(pb.calculateMassMatrix(self.body, q, physicsClientId=self.client)).reshape(
                    self.nv_e, self.nv_e)
                bias = pb.calculateInverseDynamics(self.body, q, [float(x) for x in ve[i]], zeros,
                                                   physicsClientId=self.client)
                f[i] = tau[i] - np.array(bias)
        finally:
            self._gravity(None)
        return M, f

    def points(self, qe, ve, ae, specs, *, jdot=False):
        """Positions and Jacobians of ``specs``; PyBullet offers neither ``J_dot v`` nor a classical acceleration,
        so those are NaN (and the comparison leaves them out for it: :attr:`Adapter.point_rates`)."""
        with self._quiet():
            return self._points(qe, ve, ae, specs)

    def _points(self, qe, ve, ae, specs):
        n, P = len(qe), len(specs)
        pos, J = np.empty((n, P, 3)), np.empty((n, P, 3, self.nv_e))
        self._set(self.engine_q(reference_q(self.reference, 2))[0])
        fixed = []
        for spec in specs:  # each point as calculateJacobian takes it, from the reference configuration
            link, p_W = self._where(spec)
            fixed.append((link, self._local(link, p_W)))
        for i in range(n):
            self._set(qe[i])
            for k, (link, local) in enumerate(fixed):
                o, _ = self._link_frame(link)
                _, R_c = self._frame(link)
                pos[i, k] = o + R_c @ local
                J[i, k] = self._jacobian(link, local, qe[i])[0]
        nan = np.full((n, P, 3), np.nan)
        return Points(pos, J, None, nan, None if ae is None else nan.copy())

    def stepper(self, effects, dt, integrator, accuracy=None):
        """PyBullet's ``stepSimulation`` under exactly ``effects`` (:mod:`relacc.engines.pybullet_.run`)."""
        from relacc.engines.pybullet_ import run

        return run.stepper(self, effects, dt, integrator, accuracy)


def _messages(printed: list[str]) -> list[str]:
    """PyBullet's importer's lines, one message each, on one line: it prints ``b3Warning[file,line]:`` or
    ``b3Error[file,line]:`` before each part, and some messages without a newline, the link they are about as a part
    of its own ("No inertial data for link, ..." then "base")."""
    parts = [" ".join(p.split()) for p in re.split(r"b3(?:Warning|Error)\[[^\]]*\]:", "\n".join(printed))]
    out: list[str] = []
    for part in filter(None, parts):
        if out and " " not in part:  # the link the previous message was about
            out[-1] += f" {part}" if out[-1].endswith(":") else f" (link {part})"
        else:
            out.append(f"PyBullet: {part}")
    return list(dict.fromkeys(out))


def load(path, reference=None, *, inertia_from_file: bool = False, **options) -> PyBulletAdapter:
    """The one loader signature: the URDF ``path`` read by PyBullet's ``loadURDF`` (``inertia_from_file``: with
    ``URDF_USE_INERTIA_FROM_FILE``), matched to ``reference`` (None: relacc's own reading of the file).

    Raises:
        ModelError: not a URDF, or PyBullet cannot load it or has a joint relacc does not match.
    """
    if reference is None:
        from relacc.reading import read_tree

        reference = read_tree(path)
    return PyBulletAdapter(path, reference, inertia_from_file=inertia_from_file)
