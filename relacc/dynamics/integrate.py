"""Fixed-step integrators on configuration manifolds: RKMK4 and semi-implicit Euler.

A *space* describes a configuration manifold with two operations:

* ``integrate(x, delta)``: move ``x`` by the tangent vector ``delta``;
* ``dexpinv(delta, w)``: the local-coordinate rate ``d(delta)/dt`` whose
  configuration ``integrate(x0, delta)`` has velocity ``w`` (tangent at the
  moved point); for SO(3) in body coordinates this is the inverse right
  Jacobian ``J_r^-1(delta) w``.

The state is a configuration ``x`` and a velocity vector ``v`` in R^n;
``derivs(x, v)`` returns the tangent velocity of ``x`` and ``dv/dt``. RKMK4 (Runge-Kutta-Munthe-Kaas) runs the classical
RK4 tableau on the local coordinates ``delta`` around each step's start, so it
keeps order 4 on the manifold and the quaternions stay unit without
normalization.
"""

from __future__ import annotations

import numpy as np

from relacc.core.rotations import tilde


def so3_dexpinv_body(phi, w):
    """``J_r^-1(phi) w``: rate of ``phi`` for ``R = R0 Exp(phi)`` with body angular velocity ``w``.

    ``J_r^-1 = I + 1/2 [phi~] + beta [phi~]^2``, ``beta = 1/theta^2 - (1 + cos theta) / (2 theta sin theta)``,
    with the series ``beta = 1/12 + theta^2/720 + theta^4/30240`` below theta = 1e-2.

    Args:
        phi: ``(3,)`` rotation vector (rad). w: ``(3,)`` body angular velocity (rad/s).
    """
    theta2 = float(phi @ phi)
    if theta2 < 1e-4:
        beta = 1 / 12 + theta2 / 720 + theta2 * theta2 / 30240
    else:
        th = np.sqrt(theta2)
        beta = 1 / theta2 - (1 + np.cos(th)) / (2 * th * np.sin(th))
    P = tilde(phi)
    return w + 0.5 * (P @ w) + beta * (P @ (P @ w))


class CaseSpace:
    """The configuration space of a case's coordinates.

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

    def dexpinv(self, delta, w):
        """The rate of the local coordinates ``delta`` whose move has velocity ``w`` (identity in case 3)."""
        from relacc.kernels.dynamics import dexp_one

        return dexp_one(int(self.case), np.ascontiguousarray(delta, dtype=float), np.ascontiguousarray(w, dtype=float))


def rkmk4_step(space, x, v, h, derivs):
    """One RKMK4 step of size ``h`` (s). Returns the new ``(x, v)``."""
    w1, a1 = derivs(x, v)
    d2 = 0.5 * h * w1
    x2, v2 = space.integrate(x, d2), v + 0.5 * h * a1
    w2, a2 = derivs(x2, v2)
    k2 = space.dexpinv(d2, w2)
    d3 = 0.5 * h * k2
    x3, v3 = space.integrate(x, d3), v + 0.5 * h * a2
    w3, a3 = derivs(x3, v3)
    k3 = space.dexpinv(d3, w3)
    d4 = h * k3
    x4, v4 = space.integrate(x, d4), v + h * a3
    w4, a4 = derivs(x4, v4)
    k4 = space.dexpinv(d4, w4)
    delta = h / 6 * (w1 + 2 * k2 + 2 * k3 + k4)
    return space.integrate(x, delta), v + h / 6 * (a1 + 2 * a2 + 2 * a3 + a4)


def euler_step(space, x, v, h, derivs):
    """One semi-implicit (symplectic) Euler step: ``v += h a(x, v)``, then ``x`` moves with the new ``v``."""
    _, a = derivs(x, v)
    v_new = v + h * a
    w, _ = derivs(x, v_new)
    return space.integrate(x, h * w), v_new


STEPPERS = {"rk4": rkmk4_step, "euler": euler_step}
"""Integrators for relacc and Pinocchio, by scene name."""

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

    record(np.zeros(14 if c != 3 else 12), np.zeros(12), np.zeros(0, dtype=np.int64))  # load (or compile) it now,
    return Stepper(advance, record)  # so that a run's seconds are its integration's


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
        if hasattr(space, "at"):
            space.at(x)
        base = x

        def rhs(_, y, base=base):
            delta, w = y[:n], y[n:]
            xs = space.integrate(base, delta)
            tangent, a = derivs(xs, w)
            return np.concatenate([space.dexpinv(delta, tangent), a])

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
