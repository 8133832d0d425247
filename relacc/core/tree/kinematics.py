"""Every body's kinematics at its mass centre, by the note's method: :func:`tree_kinematics`."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from relacc.core.cases import as_case, batch_rows
from relacc.core.tree.coordinates import check_q, check_u
from relacc.core.tree.model import Tree
from relacc.core.tree.walk import cross_columns, mv, walk
from relacc.errors import InputError
from relacc.limits import require_memory


class _Evaluated:
    """What an evaluation computed only when asked: :meth:`required` names what was not."""

    def required(self, name: str) -> np.ndarray:
        """The array ``name``, which this evaluation must have computed (the partials need ``partials=True``, the
        accelerations ``udot``).

        Raises:
            InputError: it was not computed (the message says what to pass).
        """
        value = getattr(self, name)
        if value is None:
            raise InputError(f"{name} was not computed: pass udot for accelerations, partials=True for the partial "
                             "velocities")
        return value


@dataclass(frozen=True, eq=False)
class TreeKinematics(_Evaluated):
    """Kinematics of a tree's bodies in the fixed frame R. Immutable unless written into ``out`` buffers.

    Every array is in **fixed-frame components** and starts with the batch shape ``...`` of the
    inputs; ``nb`` is the number of bodies (MuJoCo's order, the world left out), ``nv`` of speeds.

    Attributes:
        position: ``(..., nb, 3)`` each body's mass centre from R's origin, m.
        velocity: ``(..., nb, 3)`` its velocity in R, m/s.
        acceleration: ``(..., nb, 3)`` its classical acceleration in R (second time derivative of
            ``position``, not a spatial acceleration), m/s^2; None without ``udot``.
        omega: ``(..., nb, 3)`` each body's angular velocity in R, rad/s.
        alpha: ``(..., nb, 3)`` its angular acceleration in R, rad/s^2; None without ``udot``.
        rotation: ``(..., nb, 3, 3)`` each body's orientation: body components to fixed components.
        V: ``(..., nb, 3, nv)`` partial velocities of the mass centres, ``velocity = V u`` (1 or m per column).
        Vdot: ``(..., nb, 3, nv)`` their time derivatives, ``acceleration = V udot + Vdot u`` (1/s or m/s).
        Omega: ``(..., nb, 3, nv)`` partial angular velocities, ``omega = Omega u`` (0 or 1 per column, or
            the 1-2-3 map's entries in case 3).
        Omegadot: ``(..., nb, 3, nv)`` their time derivatives, ``alpha = Omega udot + Omegadot u`` (1/s).
            ``V``, ``Vdot``, ``Omega``, ``Omegadot`` are None when computed with ``partials=False``.
        points: :class:`PointKinematics` of the named points asked for, or None.
        case: the choice of speeds. bodies: the bodies' names.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray | None
    omega: np.ndarray
    alpha: np.ndarray | None
    rotation: np.ndarray
    V: np.ndarray | None
    Vdot: np.ndarray | None
    Omega: np.ndarray | None
    Omegadot: np.ndarray | None
    points: "PointKinematics | None"
    case: int
    bodies: tuple = field(repr=False)
    buffers: frozenset = field(default=frozenset(), repr=False)
    """The fields that hold the caller's ``out`` buffers: those stay writable, for reuse."""

    def __post_init__(self):
        for name in ("position", "velocity", "acceleration", "omega", "alpha", "rotation", "V", "Vdot", "Omega",
                     "Omegadot"):
            value = getattr(self, name)
            if isinstance(value, np.ndarray) and name not in self.buffers:
                value.setflags(write=False)


@dataclass(frozen=True, eq=False)
class PointKinematics(_Evaluated):
    """Named points fixed in bodies (MJCF sites, URDF frames), fixed-frame components.

    Attributes:
        names: the points, in the order of the arrays' ``np`` axis.
        position ``(..., np, 3)`` m; velocity ``(..., np, 3)`` m/s; acceleration ``(..., np, 3)`` m/s^2
        (classical; None without ``udot``); V, Vdot ``(..., np, 3, nv)`` as in :class:`TreeKinematics` (None with
        ``partials=False``).
    """

    names: tuple
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray | None
    V: np.ndarray | None
    Vdot: np.ndarray | None


def _point_set(tree, points):
    if points is None:
        return ()
    if points == "all":
        return tuple(range(len(tree.points)))
    if isinstance(points, str):
        points = (points,)
    out = []
    for name in points:
        if name not in tree.point_names:
            known = ", ".join(tree.point_names) or "none"
            raise InputError(f"tree {tree.name!r} has no point {name!r}; points: {known}")
        out.append(tree.point_names.index(name))
    return tuple(out)


def check_tree(tree) -> None:
    """InputError unless ``tree`` is a :class:`relacc.Tree`."""
    if not isinstance(tree, Tree):
        raise InputError(f"tree: expected a relacc.Tree (Tree.from_file, Tree.from_chain), got {type(tree).__name__}")


def inputs(tree, case, q, u, udot=None, *, need_udot=False, values=True, bytes_per_state=0.0, what="evaluating"
           ) -> tuple[int, np.ndarray, np.ndarray, Any, tuple[int, ...]]:
    """The checks every tree entry point shares: ``(case, q, u, udot, batch)``, all checked and broadcast.

    In order, so that nothing large is allocated before it is known to fit: types and shapes; then the batch's
    cost, ``bytes_per_state`` times its states, against the memory available (:func:`relacc.limits.require_memory`,
    refused with the estimate); then, with ``values``, the values (finite, unit quaternions). ``values=False``:
    a compiled kernel checks the values and reports what it finds."""
    check_tree(tree)
    c = int(as_case(case))
    q = check_q(tree, c, q, values=False)
    u = check_u(tree, f"u for case {c}", u, values=False)
    if udot is not None or need_udot:
        udot = check_u(tree, f"udot for case {c}", udot, values=False)
    shapes = [q.shape[:-1], u.shape[:-1]] + ([udot.shape[:-1]] if udot is not None else [])
    try:
        batch = np.broadcast_shapes(*shapes)
    except ValueError:
        raise InputError(f"batch shapes of q, u, udot do not broadcast: {shapes}; give equal leading shapes") from None
    n = float(math.prod(batch))
    # every entry point copies its inputs once, C-contiguous, besides what it computes
    states = f"{int(n)} state{'s' if n != 1 else ''}"
    require_memory(n * (bytes_per_state + 8.0 * (q.shape[-1] + 3 * tree.nv)),
                   f"{what} {states} of {tree.name!r} ({tree.nb} bodies, {tree.nv} speeds)",
                   "pass fewer states at a time" if n > 1 else
                   "even one state is too much for this model (its partial velocities are bodies x 3 x speeds): ask "
                   "for fewer quantities (partials=False) or a smaller model")
    if values:
        check_q(tree, c, q)
        check_u(tree, f"u for case {c}", u)
        if udot is not None:
            check_u(tree, f"udot for case {c}", udot)
    return c, q, u, udot, batch


BACKENDS = ("auto", "fast", "reference")


def tree_kinematics(tree: Tree, case: int, q: ArrayLike, u: ArrayLike, udot: ArrayLike | None = None, *,
                    points: str | Sequence[str] | None = None, backend: str = "auto", out: dict | None = None,
                    partials: bool = True) -> TreeKinematics:
    """Every body's mass-centre kinematics, angular velocity and partial velocities, by the note's method.

    Args:
        tree: :class:`relacc.Tree`.
        case: 1, 2 or 3 (see :mod:`relacc.core.tree.coordinates`: case 2 is MuJoCo's ``qpos``, ``qvel``).
        q: ``(..., nq)`` the case's coordinates. u: ``(..., nv)`` its speeds.
        udot: ``(..., nv)`` their rates, or None to skip accelerations.
        points: None, ``"all"``, or names of the tree's points to evaluate too.
        backend: ``"auto"`` (the fused kernel of :mod:`relacc.kernels.tree` for real inputs, else the reference),
            ``"fast"`` or ``"reference"`` (:mod:`relacc.core.tree.walk`, plain numpy; the two agree to rounding).
        out: numpy's ``out`` convention: a dict of writable C-contiguous float64 arrays to write the body outputs
            into, keyed by the field names of :class:`TreeKinematics` (``position`` ... ``Omegadot``; the batch's
            shapes), fast backend only; the returned arrays are those buffers, still writable.
        partials: False to skip the partial velocities and their rates (``V``, ``Vdot``, ``Omega``, ``Omegadot``
            and the points' ``V``, ``Vdot`` are then None): the fast backend then walks the joints once per state,
            spatial velocities and accelerations root to leaves (:mod:`relacc.kernels.tree_motion`), ``O(nv)``
            work and output instead of ``O(nb nv)``.

    Returns:
        :class:`TreeKinematics`, fixed-frame components throughout.

    Raises:
        InputError: a bad tree, shape, value (non-finite, non-unit quaternion) or point name.
        CaseError: an unknown case.
    """
    check_tree(tree)
    chosen = _point_set(tree, points)
    fast_guess = backend == "fast" or backend == "auto"
    per_state = (tree.nb + len(chosen)) * 3 * tree.nv * 4 + (tree.nb + 4) * 3 * tree.nv * (4 if fast_guess else 12)
    if not partials and fast_guess:
        per_state = (tree.nb + len(chosen)) * 24 + 60 * tree.nb
    c, q, u, udot, batch = inputs(tree, case, q, u, udot, bytes_per_state=8.0 * per_state)
    if backend not in BACKENDS:
        raise InputError(f"unknown backend {backend!r}: accepted are {', '.join(BACKENDS)}")
    real = not any(np.iscomplexobj(a) for a in (q, u, udot) if a is not None)
    if backend == "fast" and not real:
        raise InputError("backend 'fast' evaluates real inputs only; use backend 'reference' for complex ones")
    fast = backend == "fast" or (backend == "auto" and real)
    if out is not None and not fast:
        raise InputError("out= is for the fast backend (real inputs)")
    n = math.prod(batch)
    qf, uf = batch_rows(q, batch, q.shape[-1]), batch_rows(u, batch, tree.nv)
    udf = None if udot is None else batch_rows(udot, batch, tree.nv)
    if not isinstance(partials, (bool, np.bool_)):
        raise InputError(f"partials: expected True or False, got {partials!r:.40}")
    if fast:
        return _fast(tree, c, qf, uf, udf, chosen, points is not None, batch, out, bool(partials))
    if not partials:
        full = tree_kinematics(tree, c, q, u, udot, points=points, backend=backend)
        pk = full.points
        if pk is not None:
            pk = PointKinematics(pk.names, pk.position, pk.velocity, pk.acceleration, None, None)
        return TreeKinematics(full.position, full.velocity, full.acceleration, full.omega, full.alpha, full.rotation,
                              None, None, None, None, pk, c, tree.body_names)
    frames, _ = walk(tree, c, qf, uf)
    out = {k: [] for k in ("position", "V", "Vdot", "Omega", "Omegadot", "rotation")}
    for f, body in zip(frames, tree.bodies):
        r = mv(f.R, np.broadcast_to(body.com, (n, 3)))
        V, Vdot = f.point(r)
        for key, value in (("position", f.o + r), ("V", V), ("Vdot", Vdot), ("Omega", f.Omega),
                           ("Omegadot", f.Omegadot), ("rotation", f.R)):
            out[key].append(value)
    arr = {k: np.stack(v, axis=1) for k, v in out.items()}
    res = _motion(arr["V"], arr["Vdot"], uf, udf)
    ang = _motion(arr["Omega"], arr["Omegadot"], uf, udf)
    shape = lambda a, tail: np.ascontiguousarray(a).reshape(batch + tail)  # noqa: E731
    maybe = lambda a, tail: None if a is None else shape(a, tail)  # noqa: E731
    pk = None
    if points is not None:
        pk = _points(tree, frames, chosen, uf, udf, batch, n)
    nb, nv = tree.nb, tree.nv
    return TreeKinematics(shape(arr["position"], (nb, 3)), shape(res[0], (nb, 3)), maybe(res[1], (nb, 3)),
                          shape(ang[0], (nb, 3)), maybe(ang[1], (nb, 3)), shape(arr["rotation"], (nb, 3, 3)),
                          shape(arr["V"], (nb, 3, nv)), shape(arr["Vdot"], (nb, 3, nv)),
                          shape(arr["Omega"], (nb, 3, nv)), shape(arr["Omegadot"], (nb, 3, nv)), pk, c,
                          tree.body_names)


FIELDS = ("position", "velocity", "acceleration", "omega", "alpha", "rotation", "V", "Vdot", "Omega", "Omegadot")
TAILS = {"position": (3,), "velocity": (3,), "acceleration": (3,), "omega": (3,), "alpha": (3,), "rotation": (3, 3),
         "V": (3, -1), "Vdot": (3, -1), "Omega": (3, -1), "Omegadot": (3, -1)}


def _fast(tree, c, q, u, udot, chosen, want_points, batch, out, partials=True):
    """The fused kernel's answer as a :class:`TreeKinematics` (see :func:`relacc.kernels.tree.kinematics`)."""
    from relacc.core.kinematics import check_finite_result, check_out
    from relacc.kernels import tree as kernel

    nb, nv = tree.nb, tree.nv
    tail = lambda k: tuple(nv if t == -1 else t for t in TAILS[k])  # noqa: E731
    buffers = None
    fields = FIELDS if partials else FIELDS[:6]
    if out is not None:
        if not isinstance(out, dict) or set(out) - set(fields):
            raise InputError(f"out: expected a dict with keys among {', '.join(fields)}"
                             f"{'' if partials else ' (partials=False)'}, got {out!r:.80}")
        buffers = {k: check_out(b, batch + (nb,) + tail(k), f"out {k}") for k, b in out.items()}
        if udot is None and any(buffers.get(k) is not None for k in ("acceleration", "alpha")):
            raise InputError("out: acceleration and alpha buffers need udot")
    flat_out = None if buffers is None else {k: b.reshape((-1, nb) + tail(k)) for k, b in buffers.items()}
    with np.errstate(over="ignore", invalid="ignore"):
        if partials:
            res, bad = kernel.kinematics(tree, c, q, u, udot, want_points, flat_out)
        else:
            from relacc.kernels.tree_motion import motion

            res, bad = motion(tree, c, q, u, udot, want_points, flat_out)
    if bad:
        check_finite_result([res[k] for k in FIELDS if res[k] is not None], q, u, udot)
    shape = lambda a, k: None if a is None else a.reshape(batch + (a.shape[1],) + a.shape[2:])  # noqa: E731
    arrays: dict[str, Any] = {k: (buffers[k] if buffers and k in buffers else shape(res[k], k)) for k in FIELDS}
    pk = None
    if want_points:
        p = res["points"]
        idx = list(chosen)

        def take(a):
            if a is None:
                return None
            a = a.reshape(batch + a.shape[1:])
            return np.ascontiguousarray(a[..., idx, :] if a.ndim == len(batch) + 2 else a[..., idx, :, :])

        pk = PointKinematics(tuple(tree.points[i].name for i in chosen), take(p["position"]), take(p["velocity"]),
                             take(p["acceleration"]), take(p["V"]), take(p["Vdot"]))
    return TreeKinematics(**arrays, points=pk, case=c, bodies=tree.body_names,
                          buffers=frozenset(buffers or ()))


def _motion(P, Pdot, u, udot):
    """``(P u, P udot + Pdot u)`` over bodies: ``(n, m, 3)`` each (the second None without ``udot``)."""
    vel = np.einsum("nbij,nj->nbi", P, u)
    if udot is None:
        return vel, None
    return vel, np.einsum("nbij,nj->nbi", P, udot) + np.einsum("nbij,nj->nbi", Pdot, u)


def _points(tree, frames, chosen, u, udot, batch, n) -> PointKinematics:
    nv = tree.nv
    pos, Vs, Vds = [], [], []
    for i in chosen:
        p = tree.points[i]
        if p.body < 0:  # fixed in the world
            pos.append(np.broadcast_to(p.pos, (n, 3)).astype(float))
            Vs.append(np.zeros((n, 3, nv)))
            Vds.append(np.zeros((n, 3, nv)))
            continue
        f = frames[p.body]
        r = mv(f.R, np.broadcast_to(p.pos, (n, 3)))
        V, Vdot = f.point(r)
        pos.append(f.o + r)
        Vs.append(V)
        Vds.append(Vdot)
    m = len(chosen)
    P = np.stack(Vs, 1) if m else np.zeros((n, 0, 3, nv))
    Pd = np.stack(Vds, 1) if m else np.zeros((n, 0, 3, nv))
    vel, acc = _motion(P, Pd, u, udot)
    shape = lambda a, tail: np.ascontiguousarray(a).reshape(batch + tail)  # noqa: E731
    return PointKinematics(tuple(tree.points[i].name for i in chosen),
                           shape(np.stack(pos, 1) if m else np.zeros((n, 0, 3)), (m, 3)), shape(vel, (m, 3)),
                           None if acc is None else shape(acc, (m, 3)), shape(P, (m, 3, nv)), shape(Pd, (m, 3, nv)))


__all__ = ["PointKinematics", "TreeKinematics", "cross_columns", "tree_kinematics"]
