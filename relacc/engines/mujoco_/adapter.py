"""MuJoCo's adapter class and its loader (the package's docstring states the conventions)."""

from __future__ import annotations

import contextlib
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from relacc.engines.base import (
    Adapter,
    BuiltJoint,
    Link,
    Loop,
    Match,
    Points,
    Structure,
    by_order,
    combine,
    moving_mass,
)
from relacc.engines.capabilities import AccelerationRoutine, BodyMotion, KinematicsLoops, PointLoop, Rollout
from relacc.engines.mujoco_ import run
from relacc.engines.mujoco_.spec import (
    TYPES,
    VERSION,
    body_name,
    captured_warnings,
    compile_spec,
    joint_name,
    load_spec,
    read_tree,
    rigid_groups,
    tree_from,
)
from relacc.errors import EngineError

__all__ = ["MujocoAdapter", "captured_warnings", "load", "read_tree", "version"]


def version() -> str:
    return mujoco.__version__


FULLM_TAKES_DATA = (3, 10, 0)
"""From MuJoCo 3.10.0 ``mj_fullM`` takes ``(m, d, dst)``; before, ``(m, dst, d.qM)`` (3.10 still has ``d.qM``, so an
attribute test picks the wrong form there)."""


def full_inertia(m, d, dst):
    """Dense joint-space inertia into ``dst`` (``mj_fullM``'s call form by version: :data:`FULLM_TAKES_DATA`)."""
    if VERSION >= FULLM_TAKES_DATA:
        mujoco.mj_fullM(m, d, dst)
    else:
        mujoco.mj_fullM(m, dst, d.qM)


MUJOCO_JACDOT = ("MuJoCo's mj_jacDot takes a ball joint's columns from the velocity of its whole body, so a slide "
                 "after a ball on the same body adds v_slide x omega_ball to J_dot v (relacc's finding): MuJoCo's own "
                 "acceleration routine (mj_rnePostConstraint) agrees with relacc")
MUJOCO_JACDOT_OTHER = ("MuJoCo's mj_jacDot differs from its own acceleration routine (mj_rnePostConstraint), which "
                       "agrees with relacc")


def ball_then_slide(tree) -> bool:
    """Whether a body of the tree has a slide after a ball."""
    for body in tree.bodies:
        kinds = [j.type for j in body.joints]
        if "ball" in kinds and "slide" in kinds[kinds.index("ball") + 1:]:
            return True
    return False


class MujocoAdapter(PointLoop, KinematicsLoops, Rollout, BodyMotion, AccelerationRoutine, Adapter):
    """A model file in MuJoCo, the reference of every other adapter (see the module docstring)."""

    engine = "mujoco"
    LOOPS_ON_BODIES = True
    global_coordinates = frozenset({"velocity", "acceleration", "V", "Vdot"})
    absolute_velocities = frozenset({"acceleration", "Vdot"})  # measured: tests/test_hardcases.py

    def __init__(self, path, spec=None, reference=None):
        path = Path(path)
        self.spec = load_spec(path) if spec is None else spec
        # a copy is compiled: compiling edits a spec in place where it fuses static bodies (compiler fusestatic,
        # the default for URDF), and the readings are applied to the spec as the file has it
        self.model, warnings = compile_spec(self.spec.copy(), path)
        self.data = mujoco.MjData(self.model)
        self.original = run.Original(self.model)
        m = self.model
        self.joint_names = [joint_name(m, j) for j in range(m.njnt)]
        self.own = tree_from(self.spec, m, path)
        """MuJoCo's reading of the file as a :class:`relacc.Tree` (its compiled model's numbers)."""
        tree = self.own if reference is None else reference
        super().__init__(tree, self._match(tree), m.nq, m.nv, path, warnings)
        self.path = path
        self.groups = rigid_groups(m)
        self.structure = self._structure()

    def _match(self, tree) -> list[Match]:
        """Each joint of ``tree`` MuJoCo has, of the same type: by name, else by the body it moves and its place among
        that body's joints (MuJoCo's own reading: every joint, in order)."""
        m, out, taken = self.model, [], set()
        ids = {name: j for j, name in enumerate(self.joint_names)}
        on_body: dict[str, list[int]] = {}
        for j in range(m.njnt):
            on_body.setdefault(body_name(m, int(m.jnt_bodyid[j])), []).append(j)
        for k, ((b, joint), qa, da) in enumerate(zip(tree.joints, tree.qadr(2), tree.dofadr)):
            found = ids.get(joint.name)
            if found is None:
                place = tree.body_joints[b].index(k)
                mine = on_body.get(tree.bodies[b].name, [])
                found = mine[place] if place < len(mine) else None
            if found is None or found in taken or TYPES[int(m.jnt_type[found])] != joint.type:
                continue  # the audit reports a missing joint or another type
            j = found
            taken.add(j)
            qe, ve = int(m.jnt_qposadr[j]), int(m.jnt_dofadr[j])
            nq, nv = {"free": (7, 6), "ball": (4, 3)}.get(joint.type, (1, 1))
            out.append(Match(joint.type, (k,), tuple(range(qa, qa + nq)), tuple(range(da, da + nv)),
                             tuple(range(qe, qe + nq)), tuple(range(ve, ve + nv))))
        spans = [(j, TYPES[int(m.jnt_type[j])], int(m.jnt_qposadr[j]), int(m.jnt_dofadr[j])) for j in range(m.njnt)]
        return by_order(tree, out, [(j, kind, tuple(range(qa, qa + {"free": 7, "ball": 4}.get(kind, 1))),
                                     tuple(range(da, da + {"free": 6, "ball": 3}.get(kind, 1))))
                                    for j, kind, qa, da in spans])

    def joint_id(self, name: str) -> int:
        """MuJoCo's index of the reference's joint ``name``.

        Raises:
            EngineError: MuJoCo has no such joint.
        """
        k = self.reference.joint(name)
        for match in self.matches:
            if k in match.joints:
                return int(self.model.dof_jntid[match.v[0]])
        raise EngineError(f"MuJoCo has no joint {name!r} of the reference")

    def body_id(self, name: str) -> int:
        """MuJoCo's index of the body ``name``.

        Raises:
            EngineError: MuJoCo has no such body (its compiler fused it into another: ``fusestatic``).
        """
        b = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, name)
        if b < 0 and name.startswith("body ") and name[5:].isdigit() and int(name[5:]) < self.model.nbody \
                and not self.model.body(int(name[5:])).name:
            b = int(name[5:])  # an unnamed body, named by its place as relacc's reading and tree_of name it
        if b < 0:
            raise EngineError(f"MuJoCo has no body {name!r}: its compiler fused it into another (fusestatic)")
        return int(b)

    @property
    def version(self) -> str:
        return version()

    def inertia_allowance(self, reading: Any) -> float:
        """MuJoCo's compiler diagonalizes each mesh's inertia per unit density (m^5) with a Jacobi iteration
        (``mjuu_eig3``) that stops at an absolute off-diagonal of :data:`relacc.core.tolerances.MUJOCO_EIG_EPS`, or
        when a rotation's cosine is within that of 1 (a rotation below sqrt(2 eps_eig) = 1.4e-6 rad, which leaves an
        off-diagonal up to that times twice the largest entry), and keeps the diagonal: each mesh geom's inertia is
        off by up to ``2 eps_eig rho + 2 sqrt(2 eps_eig) |I|`` (kg m^2; ``facts["mesh_density"]`` and
        ``facts["mesh_inertia"]``, summed over the model's mesh geoms). Measured on 25 mesh files of the pinned
        wheels in every mode: within it (tests/test_mesh.py)."""
        import math

        from relacc.core.tolerances import MUJOCO_EIG_EPS

        if reading is None:
            return 0.0
        densities = reading.facts.get("mesh_density", {})
        inertias = reading.facts.get("mesh_inertia", {})
        return (2.0 * MUJOCO_EIG_EPS * float(sum(densities.values()))
                + 2.0 * math.sqrt(2.0 * MUJOCO_EIG_EPS) * float(sum(inertias.values())))

    def default_q(self) -> np.ndarray:
        return self.model.qpos0.copy()

    def body_name(self, b) -> str:
        return body_name(self.model, b)

    # --- the reading ----------------------------------------------------------------------------------------

    def _at(self, q, v=None):
        d = self.data
        d.qpos[:] = q
        d.qvel[:] = 0.0 if v is None else v
        mujoco.mj_kinematics(self.model, d)
        mujoco.mj_comPos(self.model, d)
        mujoco.mj_comVel(self.model, d)
        return d

    def _link(self, b, d) -> Link:
        m = self.model
        parts = [(float(m.body_mass[c]), d.xipos[c].copy(),
                  d.ximat[c].reshape(3, 3) @ np.diag(m.body_inertia[c]) @ d.ximat[c].reshape(3, 3).T)
                 for c in self.groups[b]]
        mass, com, inertia = combine(parts)
        return Link(self.body_name(b), tuple(self.body_name(c) for c in self.groups[b]), mass, com, inertia)

    def _structure(self) -> Structure:
        m = self.model
        d = self._at(m.qpos0)
        joints = []
        for j in range(m.njnt):
            kind, a = TYPES[int(m.jnt_type[j])], int(m.jnt_dofadr[j])
            n = {"free": 6, "ball": 3}.get(kind, 1)
            axis = d.xaxis[j].copy() if kind in ("hinge", "slide") else None
            anchor = d.xanchor[j].copy()
            if kind == "hinge":  # the point of the axis nearest the world origin
                anchor = anchor - (anchor @ axis) * axis
            joints.append(BuiltJoint(self.joint_names[j], kind, self.body_name(m.jnt_bodyid[j]), axis,
                                None if kind == "slide" else anchor,
                                m.dof_armature[a:a + n].copy(), m.dof_damping[a:a + n].copy()))
        links = tuple(self._link(b, d) for b in self.groups)
        gravity = np.zeros(3) if m.opt.disableflags & mujoco.mjtDisableBit.mjDSBL_GRAVITY else m.opt.gravity.copy()
        return Structure(m.nq, m.nv, tuple(joints), links, gravity, moving_mass(links),
                         tuple(self.body_name(b) for b in range(1, m.nbody)))

    def lost_offset(self, name: str) -> float:
        s = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_SITE, name)
        if s >= 0 and self.model.site_sameframe[s] == 1:  # mjSAMEFRAME_BODY: site_pos is ignored
            return float(np.linalg.norm(self.model.site_pos[s]))
        return 0.0

    # --- evaluations ----------------------------------------------------------------------------------------

    def _forward(self, qe, ve, effects, t):
        """``mj_forward`` at each state under exactly ``effects`` at time ``t`` (a scalar, or one per state)."""
        times = np.broadcast_to(np.asarray(t, dtype=float), (len(qe),))
        run.configure(self, effects, float(times[0]) if len(qe) else 0.0)
        m, d = self.model, self.data
        for i in range(len(qe)):
            d.qpos[:], d.qvel[:], d.time = qe[i], ve[i], times[i]
            run.set_loads(self, effects, times[i], d)
            with run.timed_loads(self, effects):
                mujoco.mj_forward(m, d)
            yield i, m, d

    def equations(self, qe, ve, effects=None, t=0.0):
        n, nv = len(qe), self.model.nv
        M, f = np.empty((n, nv, nv)), np.empty((n, nv))
        for i, m, d in self._forward(qe, ve, effects, t):
            full_inertia(m, d, M[i])
            f[i] = d.qfrc_smooth  # passive - bias + applied (xfrc_applied included)
        return M, f

    def forward(self, qe, ve, effects=None, t=0.0):
        out = np.empty((len(qe), self.model.nv))
        for i, _, d in self._forward(qe, ve, effects, t):
            out[i] = d.qacc
        return out

    def _where(self, spec):
        """``(body, [(body, weight)], site or -1, fused point or None)`` of a point spec."""
        kind, name = spec
        m = self.model
        if kind == "body":
            b = self.body_id(name)
            return b, [(b, 1.0)], -1, None
        if kind == "com":
            b = next(b for b in self.groups if self.body_name(b) == name)
            total = sum(m.body_mass[c] for c in self.groups[b])
            return b, [(c, m.body_mass[c] / total) for c in self.groups[b]], -1, None
        s = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, name)
        if s >= 0:
            return int(m.site_bodyid[s]), [], s, None
        own = self.own
        if name in own.point_names:  # a body the compiler fused, at its place on the body that took it
            p = own.points[own.point_names.index(name)]
            return p.body + 1, [], -1, p.pos
        p = self.reference.points[self.reference.point_names.index(name)]
        return self.body_id(self.reference.bodies[p.body].name), [], -1, p.pos

    def points(self, qe, ve, ae, specs, *, jdot=False):
        m, d = self.model, self.data
        n, P, nv = len(qe), len(specs), m.nv
        where = [self._where(s) for s in specs]
        pos, J = np.empty((n, P, 3)), np.empty((n, P, 3, nv))
        Jd = np.empty((n, P, 3, nv))
        acc = np.empty((n, P, 3))  # returned only with ae
        with _zero_gravity(m):  # MuJoCo's accelerations are proper ones: at zero gravity, classical
            for i in range(n):
                self._at(qe[i], ve[i])
                if ae is not None:
                    d.qacc[:] = ae[i]
                    mujoco.mj_rnePostConstraint(m, d)
                for k, (b, weights, site, at) in enumerate(where):
                    if weights:
                        pos[i, k] = sum(w * d.xipos[c] for c, w in weights)
                    elif site >= 0:
                        pos[i, k] = d.site_xpos[site]
                    else:
                        pos[i, k] = d.xpos[b] + d.xmat[b].reshape(3, 3) @ at
                    mujoco.mj_jac(m, d, J[i, k], None, pos[i, k], b)
                    mujoco.mj_jacDot(m, d, Jd[i, k], None, pos[i, k], b)
                    if ae is not None:
                        acc[i, k] = _classical(m, d, b, pos[i, k])
        return Points(pos, J, Jd if jdot else None, np.einsum("npij,nj->npi", Jd, ve), None if ae is None else acc)

    def stepper(self, effects, dt, integrator, accuracy=None):
        return run.stepper(self, effects, dt, integrator, accuracy)

    def rollout(self, qpos, qvel, ends, work):
        """:func:`relacc.engines.mujoco_.run.rollout` on this model, as :meth:`stepper` configured it."""
        return run.rollout(self, qpos, qvel, ends, work)

    def work_data(self, threads: int) -> list:
        """``threads`` fresh ``MjData`` of the model, for :meth:`rollout`'s threads."""
        return [mujoco.MjData(self.model) for _ in range(max(1, int(threads)))]

    def applied(self, effects) -> dict:
        """The disable flags :func:`relacc.engines.mujoco_.run.configure` sets for ``effects``."""
        return {"disabled": run.configure(self, effects)}

    def jdot_cause(self, tree) -> str:
        return MUJOCO_JACDOT if ball_then_slide(tree) else MUJOCO_JACDOT_OTHER

    def body_motion(self, q, u, udot) -> dict:
        """MuJoCo's own numbers for every body at states ``q (n, nq)``, ``u``, ``udot (n, nv)`` (its coordinates):
        ``position`` (``xipos``), ``velocity``, ``omega`` (``mj_jac`` at the mass centre times ``u``), ``V``,
        ``Omega`` (``mj_jac``), ``acceleration``, ``alpha`` (its acceleration routine ``mj_rnePostConstraint`` at zero
        gravity, made classical at the mass centre); fixed-frame components, ``(n, nb, 3)`` and ``(n, nb, 3, nv)``."""
        m, d = self.model, self.data
        n, nb = len(q), m.nbody - 1
        out = {k: np.zeros((n, nb, 3)) for k in ("position", "velocity", "omega", "acceleration", "alpha")}
        out.update({k: np.zeros((n, nb, 3, m.nv)) for k in ("V", "Omega")})
        with _zero_gravity(m):
            for i in range(n):
                self._at(q[i], u[i])
                d.qacc[:] = udot[i]
                mujoco.mj_rnePostConstraint(m, d)
                for b in range(1, m.nbody):
                    J, Jr = out["V"][i, b - 1], out["Omega"][i, b - 1]
                    mujoco.mj_jac(m, d, J, Jr, d.xipos[b], b)
                    out["position"][i, b - 1] = d.xipos[b]
                    out["velocity"][i, b - 1], out["omega"][i, b - 1] = J @ u[i], Jr @ u[i]
                    out["alpha"][i, b - 1] = d.cacc[b, :3]
                    out["acceleration"][i, b - 1] = _classical(m, d, b, d.xipos[b])
        return out

    def point_loop(self, qe, ve, ae, spec, full: bool = False):
        """The throughput anchor: a closure looping over the states as a user would for a site's classical
        acceleration (``mj_kinematics``, ``mj_comPos``, ``mj_comVel``, ``mj_rnePostConstraint``,
        ``mj_objectAcceleration``; gravity must be off: it reports proper accelerations) and, with ``full``, its
        position, ``mj_jac`` and ``mj_jacDot``; results in its ``acc`` attribute ``(n, 3)``."""
        return _point_loop(self, qe, ve, ae, spec, full)

    def step_loop(self, qpos, qvel, n_steps: int):
        """The benchmarks' anchor for one run: a closure stepping ``mj_step`` ``n_steps`` times from Python from the
        state ``(nq,)``, ``(nv,)``, under the model as :meth:`stepper` configured it."""
        m, d = self.model, self.data

        def loop():
            d.qpos[:], d.qvel[:], d.time = qpos, qvel, 0.0
            for _ in range(n_steps):
                mujoco.mj_step(m, d)

        return loop

    def rollout_loop(self, qpos, qvel, n_steps: int, threads: int):
        """The benchmarks' anchor for ensembles: a closure running ``mujoco.rollout`` of every state ``(n, nq)``,
        ``(n, nv)`` for ``n_steps`` with a persistent thread pool, ``skip_checks`` and preallocated output (its
        fastest use), under the model as :meth:`stepper` configured it; call ``loop.close()`` when done."""
        from mujoco import rollout as mj_rollout

        m = self.model
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        state = np.zeros((len(qpos), mujoco.mj_stateSize(m, spec)))
        state[:, 1:1 + m.nq], state[:, 1 + m.nq:1 + m.nq + m.nv] = qpos, qvel
        out = np.empty((len(qpos), n_steps, state.shape[1]))
        datas, models = [mujoco.MjData(m) for _ in range(threads)], [m] * len(qpos)
        pool = mj_rollout.Rollout(nthread=threads)

        def loop():
            pool.rollout(models, datas, state, nstep=n_steps, skip_checks=True, state=out)

        return Loop(loop, close=pool.close)

    def motion_loop(self, qe, ve, ae, specs):
        """The benchmarks' anchor for kinematics without Jacobians (:func:`_motion_loop`), at the bodies of
        ``specs``."""
        return _motion_loop(self, qe, ve, ae, specs)

    def jacobian_loop(self, qe, ve, specs):
        """The benchmarks' anchor: a closure looping over the states with ``mj_kinematics``, ``mj_comPos``,
        ``mj_comVel``, then ``mj_jac`` and ``mj_jacDot`` (translational and rotational) at every point of ``specs``,
        stored into ``(n, P, 3, nv)`` arrays, as a user collecting every body's would."""
        m, d = self.model, self.data
        where = [self._where(s) for s in specs]
        n, P = len(qe), len(specs)
        J, Jr, Jd, Jrd = (np.empty((n, P, 3, m.nv)) for _ in range(4))

        def loop():
            for i in range(n):
                self._at(qe[i], ve[i])
                for k, (b, weights, site, at) in enumerate(where):
                    p = sum(w * d.xipos[c] for c, w in weights) if weights else (
                        d.site_xpos[site] if site >= 0 else d.xpos[b] + d.xmat[b].reshape(3, 3) @ at)
                    mujoco.mj_jac(m, d, J[i, k], Jr[i, k], p, b)
                    mujoco.mj_jacDot(m, d, Jd[i, k], Jrd[i, k], p, b)

        return loop


@contextlib.contextmanager
def _zero_gravity(m):
    """MuJoCo's model at zero gravity inside the block (then its own again): its acceleration routine starts ``cacc``
    from ``-gravity`` (proper accelerations), so that at zero gravity ``cacc`` gives classical ones."""
    gravity = m.opt.gravity.copy()
    m.opt.gravity[:] = 0.0
    try:
        yield m
    finally:
        m.opt.gravity[:] = gravity


def _motion_loop(adapter, qe, ve, ae, specs):
    """:meth:`MujocoAdapter.motion_loop`: per state ``mj_kinematics``, ``mj_comPos``, ``mj_comVel`` and
    ``mj_rnePostConstraint`` (with ``qacc``), then per body its mass centre's position, ``mj_objectVelocity`` and
    ``mj_objectAcceleration`` (world components, classical), stored into ``(n, B, 3)`` arrays; the results in the
    closure's ``pos``, ``vel``, ``acc`` attributes."""
    m, d = adapter.model, adapter.data
    bodies = [adapter._where(s)[0] for s in specs]
    n, B = len(qe), len(bodies)
    pos, vel, acc, om, al = (np.empty((n, B, 3)) for _ in range(5))
    res = np.empty(6)
    body = mujoco.mjtObj.mjOBJ_BODY  # at the body's mass centre

    def loop():
        with _zero_gravity(m):
            for i in range(n):
                adapter._at(qe[i], ve[i])
                d.qacc[:] = ae[i]
                mujoco.mj_rnePostConstraint(m, d)
                for k, b in enumerate(bodies):
                    pos[i, k] = d.xipos[b]
                    mujoco.mj_objectVelocity(m, d, body, b, res, 0)
                    om[i, k], vel[i, k] = res[:3], res[3:]
                    mujoco.mj_objectAcceleration(m, d, body, b, res, 0)
                    al[i, k], acc[i, k] = res[:3], res[3:]

    return Loop(loop, pos=pos, vel=vel, acc=acc)


def _point_loop(adapter, qe, ve, ae, spec, full):
    """:meth:`MujocoAdapter.point_loop` (a site's acceleration by ``mj_objectAcceleration``, gravity off)."""
    m, d = adapter.model, adapter.data
    b, _, site, _ = adapter._where(spec)
    n = len(qe)
    acc, res = np.empty((n, 3)), np.empty(6)
    pos, J, Jd = np.empty((n, 3)), np.empty((n, 3, m.nv)), np.empty((n, 3, m.nv))

    def loop():
        for i in range(n):
            d.qpos[:], d.qvel[:], d.qacc[:] = qe[i], ve[i], ae[i]
            mujoco.mj_kinematics(m, d)
            mujoco.mj_comPos(m, d)
            mujoco.mj_comVel(m, d)
            mujoco.mj_rnePostConstraint(m, d)
            mujoco.mj_objectAcceleration(m, d, mujoco.mjtObj.mjOBJ_SITE, site, res, 0)
            acc[i] = res[3:]
            if full:
                pos[i] = d.site_xpos[site]
                mujoco.mj_jac(m, d, J[i], None, pos[i], b)
                mujoco.mj_jacDot(m, d, Jd[i], None, pos[i], b)

    return Loop(loop, acc=acc)


def _classical(m, d, b, p) -> np.ndarray:
    """The classical acceleration of the point ``p`` (world) fixed on body ``b``, from ``cacc`` and ``cvel`` (spatial,
    about the subtree's centre of mass ``c``): ``a = cacc_lin - r x alpha + omega x (cvel_lin - r x omega)``,
    ``r = p - c``."""
    r = p - d.subtree_com[m.body_rootid[b]]
    w, alpha = d.cvel[b, :3], d.cacc[b, :3]
    return d.cacc[b, 3:] - np.cross(r, alpha) + np.cross(w, d.cvel[b, 3:] - np.cross(r, w))


def load(path, reference=None, **options) -> MujocoAdapter:
    """The one loader signature: a model file in MuJoCo, matched to ``reference`` (a :class:`relacc.Tree`; None:
    MuJoCo's own reading, every joint matched to itself).

    Raises:
        ModelError: MuJoCo cannot read or compile the file.
    """
    return MujocoAdapter(path, reference=reference)
