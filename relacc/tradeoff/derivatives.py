"""Accuracy against cost for G2's acceleration: analytic, finite differences, complex step, engines.

Reference: the complex-step derivative (``h = 1e-40``) of the velocity of
the note's *reference* implementation (:func:`relacc.g2_kinematics` with
``backend="reference"``) along the motion. Its truncation error is below
1e-40 and it subtracts nothing, so only rounding (a few eps, confirmed by
both engines) remains; it shares no code with the fused analytic kernel or
with the finite-difference methods, which differentiate the fused velocity.
Errors are normalized by the acceleration's term scale (maximum over states).
"""

from __future__ import annotations

import numpy as np

import relacc
from relacc.core.cases import Case
from relacc.core.conventions import Route
from relacc.core.derivatives import advance, along_motion
from relacc.core.scales import term_scales
from relacc.core.states import random_states
from relacc.core.tolerances import EPS, normalized_error
from relacc.engines.chain import G2
from relacc.tradeoff.throughput import wall_times

STEPS = tuple(10.0 ** -k for k in np.arange(1, 14.5, 0.5))
"""Finite-difference steps h (s), 1e-1 down to 3e-15, every half decade."""

COMPLEX_STEPS = (1e-1, 1e-2, 1e-3, 1e-5, 1e-10, 1e-20)

FORMULAS = {
    "forward": ((0, -1), (1, 1)),               # (f(h) - f(0)) / h
    "central": ((-1, -0.5), (1, 0.5)),         # (f(h) - f(-h)) / 2h
    "central4": ((-2, 1 / 12), (-1, -8 / 12), (1, 8 / 12), (2, -1 / 12)),
}
"""Finite-difference stencils: (multiple of h, weight) pairs; the derivative is sum(w f(k h)) / h."""


TIMING_BATCH = 4096
"""States the analytic formulas are timed on (the sampled states repeated): they are batch calls, and a call's fixed
cost (about 10 us of checks and dispatch) spread over a few hundred states would be timed instead of the formulas."""


def _timed(fn, n, repeats):
    """The method's output and its median time per state (s)."""
    out = fn()  # also the warm-up
    return out, wall_times(fn, repeats, warmups=0)[0] / n


def sweep(chain, n_states: int = 200, seed: int = 0, repeats: int = 3, engines=None, cases=(1, 2, 3)) -> list[dict]:
    """Every method's error and time per state, per case. Rows are plain dicts (see module docstring). The analytic
    formulas are timed as batch calls over :data:`TIMING_BATCH` states, everything else on the sampled states."""
    rows = []
    for case in cases:
        s = random_states(case, n_states, [seed, case, 7])
        n = len(s)
        ref = along_motion(case, s.q, s.u, s.udot,
                           lambda q, u: relacc.g2_kinematics(chain, case, q, u, backend="reference").velocity,
                           method="complex", h=1e-40)
        scale = term_scales(chain, case, s.q, s.u, s.udot).acceleration

        def row(method, param, value, seconds):
            err = normalized_error(value, ref, scale)
            rows.append({"case": case, "method": method, "param": param, "error": float(np.max(err)),
                         "error_median": float(np.median(err)), "seconds_per_state": seconds})

        reps = max(1, TIMING_BATCH // n)
        Q, U, Ud = (np.tile(x, (reps, 1)) for x in (s.q, s.u, s.udot))
        _, sec = _timed(lambda: relacc.g2_acceleration(chain, case, Q, U, Ud), n * reps, repeats)
        row("analytic", None, relacc.g2_acceleration(chain, case, s.q, s.u, s.udot), sec)
        _, sec = _timed(lambda: relacc.g2_kinematics(chain, case, Q, U, Ud, backend="reference").acceleration,
                        n * reps, repeats)
        row("analytic-reference", None,
            relacc.g2_kinematics(chain, case, s.q, s.u, s.udot, backend="reference").acceleration, sec)

        def velocity_at(t):
            return relacc.g2_kinematics(chain, case, advance(case, s.q, s.u, t), s.u + t * s.udot).velocity

        for name, stencil in FORMULAS.items():
            for h in STEPS:
                value, sec = _timed(lambda: sum(w * velocity_at(k * h) for k, w in stencil) / h, n, repeats)
                row(name, h, value, sec)
        for h in STEPS:
            def rich(h=h):
                d = lambda hh: (velocity_at(hh) - velocity_at(-hh)) / (2 * hh)  # noqa: E731
                return (4 * d(h / 2) - d(h)) / 3
            value, sec = _timed(rich, n, repeats)
            row("richardson", h, value, sec)
        for h in COMPLEX_STEPS:
            value, sec = _timed(lambda: along_motion(
                case, s.q, s.u, s.udot, lambda q, u: relacc.g2_kinematics(chain, case, q, u).velocity,
                method="complex", h=h), n, repeats)
            row("complex-step", h, value, sec)
        for name, engine in (engines or {}).items():
            route = Route.EULER if case == Case.ANGLE_RATES else Route.QUATERNION
            x = engine.engine_input(route, relacc.Case(case), s.q, s.u, s.udot)
            loop = engine.routes[route].point_loop(x.q, x.v, x.a, G2, False)
            _, sec = _timed(loop, n, repeats)
            row(name, None, loop.acc.copy(), sec)
    return rows


def best_step(rows, method: str, case: int) -> float:
    """The step h with the smallest error for a finite-difference method and case."""
    pts = [r for r in rows if r["method"] == method and r["case"] == case]
    return min(pts, key=lambda r: r["error"])["param"]


THEORY = {"forward": 0.5, "central": 1 / 3, "central4": 0.2, "richardson": 0.2}
"""Optimal step ~ eps^p (time scale 1 s here): truncation h^order against rounding eps/h."""


def theory_step(method: str) -> float:
    return EPS ** THEORY[method]
