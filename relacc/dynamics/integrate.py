"""Fixed-step integrators on configuration manifolds: RKMK4 and semi-implicit Euler, written once.

A *space* describes a configuration manifold with two operations:

* ``integrate(x, delta)``: move ``x`` by the tangent vector ``delta``;
* ``dexpinv(x0, delta, w)``: the local-coordinate rate ``d(delta)/dt`` whose configuration
  ``integrate(x0, delta)`` has velocity ``w`` (tangent at the moved point); for SO(3) in body coordinates this is
  the inverse right Jacobian ``J_r^-1(delta) w`` (:func:`relacc.core.so3.jr_inv`).

The state is a configuration ``x`` and a velocity vector ``v``; ``derivs(x, v, t)`` returns the tangent velocity of
``x`` and ``dv/dt`` at time ``t``. Both may be one state or a batch of rows: :func:`rkmk4_step` and
:func:`euler_step` use only vector arithmetic, so relacc's trees, Pinocchio's single runs and its batched ensembles
(``abaInParallel`` per stage) all step through the same code. RKMK4 (Runge-Kutta-Munthe-Kaas) runs the classical
RK4 tableau on the local coordinates ``delta`` around each step's start, so it keeps order 4 on the manifold and
quaternions stay unit without normalization. relacc's compiled chain integrators
(:mod:`relacc.kernels.dynamics`) run the same tableau in compiled loops.
"""

from __future__ import annotations

import numpy as np

from relacc.core.cases import Case


class CaseSpace:
    """The configuration space of a chain case's coordinates.

    Cases 1-2: ``R^3 x SO(3) x R^3 x SO(3)`` with tangent vectors
    ``[ds1, phi_B1 (body), ds2', phi_B2/B1 (body of B2)]``, quaternions
    updated as ``quat (x) Exp(phi)``; the velocity is the body speeds
    ``[W] u`` of :mod:`relacc.core.speeds`. Case 3: ``R^12``, tangent = ``u``.
    """

    def __init__(self, case):
        from relacc.core.cases import Case, as_case

        self.case = as_case(case)
        self.angles = self.case is Case.ANGLE_RATES

    def integrate(self, q, delta):
        """``q`` moved by the tangent vector ``delta`` (the compiled :func:`relacc.kernels.dynamics.move`)."""
        from relacc.kernels.dynamics import move_one

        return move_one(int(self.case), np.ascontiguousarray(q, dtype=float), np.ascontiguousarray(delta, dtype=float))

    def dexpinv(self, q0, delta, w):
        """The rate of the local coordinates ``delta`` whose move has velocity ``w`` (identity in case 3)."""
        from relacc.kernels.dynamics import dexp_one

        return dexp_one(int(self.case), np.ascontiguousarray(delta, dtype=float), np.ascontiguousarray(w, dtype=float))


class TreeSpace:
    """The configuration space of a tree's case-``c`` coordinates, on one state or a batch of rows.

    Tangent vectors are case-2 speeds (MuJoCo's): hinge and slide rates, a free joint's origin velocity (parent
    components) and, for balls and free joints, body angular velocities. Cases 1-2 move quaternions as
    ``quat (x) Exp(phi)`` (body rotation vector ``phi``, rate :func:`relacc.core.so3.jr_inv`); case 3 moves angles by
    the tangent vector itself (its speeds are the angles' rates).
    """

    def __init__(self, tree, case):
        from relacc.core.tree.coordinates import rotations

        self.tree, self.case = tree, int(case)
        self.quats = [(a, d) for _, kind, a, d in rotations(tree, 2)] if self.case != Case.ANGLE_RATES else []

    def integrate(self, q, delta):
        from relacc.core.so3 import SO3

        out = np.array(q, dtype=float)
        if self.case == Case.ANGLE_RATES:
            return out + delta
        one = out.ndim == 1
        out, delta = np.atleast_2d(out), np.atleast_2d(delta)
        moved = np.zeros(out.shape[1], dtype=bool)
        for a, d in self.quats:
            out[:, a:a + 4] = (SO3(out[:, a:a + 4]) @ SO3.exp(delta[:, d:d + 3])).wxyz
            moved[a:a + 4] = True
        lin = np.flatnonzero(~moved)
        out[:, lin] += delta[:, self._lin_speeds()]
        return out[0] if one else out

    def _lin_speeds(self):
        """The speeds that move the coordinates outside quaternions, in the coordinates' order."""
        ang = {d + i for _, d in self.quats for i in range(3)}
        return [i for i in range(self.tree.nv) if i not in ang]

    def dexpinv(self, q0, delta, w):
        from relacc.core.so3 import jr_inv

        if self.case == Case.ANGLE_RATES:
            return w
        out = np.array(w, dtype=float)
        for _, d in self.quats:
            out[..., d:d + 3] = jr_inv(delta[..., d:d + 3], w[..., d:d + 3])
        return out


def rkmk4_step(space, x, v, h, derivs, t=0.0):
    """One RKMK4 step of size ``h`` (s) from time ``t``. Returns the new ``(x, v)``."""
    w1, a1 = derivs(x, v, t)
    d2 = 0.5 * h * w1
    x2, v2 = space.integrate(x, d2), v + 0.5 * h * a1
    w2, a2 = derivs(x2, v2, t + 0.5 * h)
    k2 = space.dexpinv(x, d2, w2)
    d3 = 0.5 * h * k2
    x3, v3 = space.integrate(x, d3), v + 0.5 * h * a2
    w3, a3 = derivs(x3, v3, t + 0.5 * h)
    k3 = space.dexpinv(x, d3, w3)
    d4 = h * k3
    x4, v4 = space.integrate(x, d4), v + h * a3
    w4, a4 = derivs(x4, v4, t + h)
    k4 = space.dexpinv(x, d4, w4)
    delta = h / 6 * (w1 + 2 * k2 + 2 * k3 + k4)
    return space.integrate(x, delta), v + h / 6 * (a1 + 2 * a2 + 2 * a3 + a4)


def euler_step(space, x, v, h, derivs, t=0.0):
    """One semi-implicit (symplectic) Euler step: ``v += h a(x, v)``, then ``x`` moves with the new ``v``."""
    _, a = derivs(x, v, t)
    v_new = v + h * a
    w, _ = derivs(x, v_new, t)
    return space.integrate(x, h * w), v_new


STEPPERS = {"rk4": rkmk4_step, "euler": euler_step}
"""Integrators for relacc and Pinocchio, by scene name."""


def space_stepper(space, derivs, dt: float, integrator: str):
    """Fixed steps of ``dt`` (s) by ``STEPPERS[integrator]`` on ``space`` with ``derivs(x, v, t)``, as a
    :class:`relacc.dynamics.steps.Stepper`; time runs on from 0 across its calls. The caller checks that
    ``integrator`` is one of :data:`STEPPERS` (and says whose integrators they are)."""
    from relacc.dynamics.steps import Stepper

    step, clock = STEPPERS[integrator], [0.0]

    def advance(x, v, k):
        for _ in range(k):
            x, v = step(space, x, v, dt, derivs, clock[0])
            clock[0] += dt
        return x, v

    return Stepper(advance)


def stepper(chain, case, effects, dt: float, integrator: str):
    """relacc's own fixed-step integrator as a :class:`relacc.dynamics.steps.Stepper`, compiled.

    The forward dynamics of :mod:`relacc.kernels.dynamics` (Newton-Euler, block by block) under exactly
    ``effects``, integrated in the case's own coordinates by ``integrator`` (``rk4``: RKMK4 on SO(3) for
    cases 1-2, RK4 on the angles for case 3; ``euler``: semi-implicit Euler), in compiled loops over
    steps and records: the same algorithms as :func:`rkmk4_step` and :func:`euler_step`. Making the
    stepper loads the compiled loop (compiles it, the first time on a machine), so that what a run then
    times is its integration.

    Raises:
        EngineError: an integrator relacc lacks.
    """
    from relacc.dynamics.steps import Stepper
    from relacc.kernels import dynamics as kernel

    if integrator not in kernel.INTEGRATORS:
        from relacc.errors import EngineError

        raise EngineError(f"relacc integrators: {', '.join(kernel.INTEGRATORS)}; got {integrator!r}")
    c, method = int(case), kernel.INTEGRATORS[integrator]
    cp, ep = kernel.chain_params(chain), kernel.effect_params(effects)

    def advance(q, u, k):
        return kernel.advance(c, method, np.ascontiguousarray(q, dtype=float), np.ascontiguousarray(u, dtype=float),
                              float(dt), int(k), cp, ep)

    def record(q, u, gaps):
        Q, U = np.empty((len(gaps), np.size(q))), np.empty((len(gaps), 12))
        with np.errstate(all="ignore"):  # a diverging run is reported by its record count, not by warnings
            n = kernel.record_run(c, method, np.ascontiguousarray(q, dtype=float), np.ascontiguousarray(u, dtype=float),
                                  float(dt), np.ascontiguousarray(gaps, dtype=np.int64), cp, ep, Q, U)
        return Q, U, n

    # load (or compile) it now, so that a run's seconds are its integration's
    record(np.zeros(14 if c != Case.ANGLE_RATES else 12), np.zeros(12), np.zeros(0, dtype=np.int64))
    return Stepper(advance, record)


def tree_stepper_compiled(tree, effects, dt: float, integrator: str, derivs, case: int = 2):
    """relacc's fixed-step integrator of a tree in any case's coordinates, compiled
    (:mod:`relacc.kernels.tree_step`): the algorithms of :func:`rkmk4_step` and :func:`euler_step` on
    :class:`TreeSpace` with the effects inside the loop, as a :class:`relacc.dynamics.steps.Stepper` (one state or a
    batch of rows; rows in parallel); time runs on from 0. Case 1's tangent is each rotation's ``B u`` from the stage's
    frames (its joint forces act through ``B``); case 3 is solved in case-2 speeds at every stage and mapped to the
    rates (its error is the rate map's condition number times case 2's, as :func:`relacc.tree_accelerations`).

    A state that becomes non-finite ends the run as divergence (the step loop says so). Where a stage's mass matrix is
    singular, a quaternion drifts off unit or a 1-2-3 rate map passes :data:`relacc.core.tolerances.MAX_CONDITION`,
    that stage is evaluated again by ``derivs(x, v, t)`` (the reference path, :func:`relacc.tree_accelerations`),
    which raises its own error naming the speeds or the joint (after ``t = 0`` as :class:`relacc.IntegrationError`:
    a run that diverges reaches such a state); where the reference path finds nothing wrong, it takes those steps
    itself. A case-3 run that comes within :data:`relacc.core.tolerances.CONDITION_WARNING` of the lock warns once
    per call (:class:`relacc.AccuracyWarning`, naming the joint), as the reference path warns at every stage. Making
    the stepper loads the compiled loop (compiles it, the first time on a machine), so that what a run then times is
    its integration; the batch loops are loaded when first asked for (:meth:`relacc.dynamics.steps.Stepper.load`).
    The caller checks ``integrator`` (:data:`relacc.kernels.tree_step.INTEGRATORS`).
    """
    from relacc.core.tolerances import CONDITION_WARNING
    from relacc.dynamics.steps import Stepper
    from relacc.errors import IntegrationError, SingularityError
    from relacc.kernels import tree_step as kernel
    from relacc.kernels.jit import parallel_pays
    from relacc.kernels.tree import arrays_of
    from relacc.kernels.tree_dynamics import US_PER_SPEED, plan

    case = int(case)
    T = arrays_of(tree)
    p = plan(tree)
    chosen = p.method
    anc, depth, mass, com, inertia, arm, free = p.arrays()
    gravity, E = kernel.effect_arrays(tree, effects)
    qadr = T.qadr3 if case == Case.ANGLE_RATES else T.qadr
    fixed = (T, qadr, anc, depth, mass, com, inertia, arm, free, gravity, E)
    method, aba, width = kernel.INTEGRATORS[integrator], chosen == "aba", anc.shape[1]
    nq, nv = tree.nq_in(case), tree.nv
    space, clock = TreeSpace(tree, case), [0]  # clock: steps taken
    cost = (4 if method == kernel.RK4 else 1) * US_PER_SPEED * nv  # us per step of a row, for parallel_pays

    def explain(failed, status):
        """The reference path's error at a failed stage, or False when it finds none (then the steps are taken
        again by the reference path); True for divergence."""
        t, q, u = failed[0], failed[1:1 + nq], failed[1 + nq:]
        if status == kernel.NON_FINITE or not (np.all(np.isfinite(q)) and np.all(np.isfinite(u))):
            return True
        try:
            derivs(q, u, t)  # raises SingularityError or InputError, naming what is wrong
        except SingularityError as exc:
            if t == 0.0:  # the initial state itself
                raise
            raise IntegrationError(f"at t = {t:.6g} s {exc}: the run diverged or reached a singular configuration; "
                                   "reduce the step") from None
        return False

    def warn(near):
        """The reference path's AccuracyWarning, once, where a case-3 stage came near the lock."""
        worst = int(np.argmax(near[:, 0]))
        if near[worst, 0] > CONDITION_WARNING:
            from relacc.core.tree.coordinates import warn_near_lock

            warn_near_lock(tree, near[worst:worst + 1, 1:], "the rates' accelerations of the run's stages carry "
                           "relative errors up to about {err:.2g} times the mass matrix's condition number",
                           stacklevel=4)

    def replay(x, v, k, t0):
        for i in range(k):
            x, v = STEPPERS[integrator](space, x, v, dt, derivs, t0 + i * dt)
        return x, v

    def record(x, v, gaps):
        gaps = np.ascontiguousarray(gaps, dtype=np.int64)
        X, V, failed = np.empty((len(gaps), nq)), np.empty((len(gaps), nv)), np.empty(1 + nq + nv)
        near = np.zeros(1 + nq)
        x, v = np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(v, dtype=float)
        got, status, done = kernel.record(case, method, aba, x, v, clock[0] * dt, float(dt), gaps, *fixed, X, V,
                                          width, failed, near)
        warn(near[None])
        if status and not explain(failed, status):
            done = 0
            for j, k in enumerate(gaps):
                x, v = replay(x, v, int(k), (clock[0] + done) * dt)
                X[j], V[j], done = x, v, done + int(k)
            got = len(gaps)
        clock[0] += done
        return X, V, got

    def load():
        """The batch loops, loaded (compiled the first time on a machine: 15-20 s, the parallel one most) when a
        batch is first asked for rather than with the stepper, which a single trajectory never needs."""
        if not loaded:
            for loop in (kernel.advance_rows, lambda *a: kernel.advance_range(*a, 0, 1)):
                loop(case, method, aba, x0[None].copy(), v0[None].copy(), 0.0, float(dt), 0, *fixed, width,
                     np.zeros(1, dtype=np.int64), np.empty((1, 1 + nq + nv)), np.zeros((1, 1 + nq)))
            loaded.append(True)

    def advance(x, v, k):
        load()
        one = np.ndim(x) == 1
        X, V = np.array(np.atleast_2d(x), dtype=float), np.array(np.atleast_2d(v), dtype=float)
        start_x, start_v = X.copy(), V.copy()
        status, failed = np.zeros(len(X), dtype=np.int64), np.empty((len(X), 1 + nq + nv))
        near = np.zeros((len(X), 1 + nq))
        args = (case, method, aba, X, V, clock[0] * dt, float(dt), int(k), *fixed, width, status, failed, near)
        if parallel_pays(len(X), int(k) * cost, 1):
            kernel.advance_rows(*args)
        else:
            kernel.advance_range(*args, 0, len(X))
        warn(near)
        for i in np.flatnonzero(status):
            if explain(failed[i], status[i]):
                X[i], V[i] = np.nan, np.nan  # diverged: the caller's check names the member and the time
            else:
                X[i], V[i] = replay(start_x[i], start_v[i], int(k), clock[0] * dt)
        clock[0] += int(k)
        return (X[0], V[0]) if one else (X, V)

    x0, v0, loaded = np.zeros(nq), np.zeros(nv), []
    for a, _ in space.quats:
        x0[a] = 1.0
    kernel.record(case, method, aba, x0, v0, 0.0, float(dt), np.zeros(0, dtype=np.int64), *fixed, np.empty((0, nq)),
                  np.empty((0, nv)), width, np.empty(1 + nq + nv), np.zeros(1 + nq))  # load (or compile) the loop
    return Stepper(advance, record, load)


def solve_on_space(space, x0, v0, derivs, duration: float, method: str, rtol: float, atol: float,
                   rotations=(slice(3, 6), slice(9, 12)), max_chart: float = 1.0):
    """Adaptive integration with :func:`scipy.integrate.solve_ivp` in local coordinates.

    The state is ``x = integrate(x_base, delta)``, ``v``; ``solve_ivp`` integrates
    ``d(delta)/dt = dexpinv(delta, w)``, ``dv/dt = a`` from ``delta = 0``. A terminal
    event re-bases the chart before any rotation vector (``rotations``) passes
    ``max_chart`` rad, far from the singularity of ``dexpinv`` at 2 pi, and the
    integration restarts there with the last step size. Quaternions stay unit
    without any normalization.

    Returns:
        ``(x, v, n_evaluations)`` at ``t = duration``.
    """
    from scipy.integrate import solve_ivp

    x, v, t, nfev, first = x0, np.asarray(v0, dtype=float), 0.0, 0, None
    n = np.asarray(v0).size
    while t < duration * (1 - 1e-14):
        base = x

        def rhs(time, y, base=base):
            delta, w = y[:n], y[n:]
            xs = space.integrate(base, delta)
            tangent, a = derivs(xs, w, time)
            return np.concatenate([space.dexpinv(base, delta, tangent), a])

        def chart(_, y):
            return max_chart - max((np.linalg.norm(y[r]) for r in rotations), default=0.0)

        chart.terminal = True
        if first is not None:
            first = min(first, duration - t)
        sol = solve_ivp(rhs, (t, duration), np.concatenate([np.zeros(n), v]), method=method, rtol=rtol,
                        atol=atol, events=chart if rotations else None, first_step=first)
        if sol.status < 0:
            from relacc.errors import IntegrationError

            raise IntegrationError(f"solve_ivp {method} failed at t = {sol.t[-1]:.6g} s: {sol.message}")
        nfev += sol.nfev
        x, v, t = space.integrate(base, sol.y[:n, -1]), sol.y[n:, -1], sol.t[-1]
        first = float(np.diff(sol.t[-2:])[0]) if sol.t.size > 1 and sol.t[-1] > sol.t[-2] else None
    return x, v, nfev
