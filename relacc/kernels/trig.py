"""Sine and cosine of one angle together, branch-free, for the compiled kernels.

Case 3 needs the sines and cosines of six angles per state. Called from
numba, libm's ``sin`` and ``cos`` cost about 16 ns each here and are half of
the case-3 kernel's time; no library gives numba a vectorized or inlinable
version (PyPI's llvmlite has no SVML, numpy's float64 ``sin``/``cos`` call
libm too). :func:`sincos` is fdlibm's algorithm (Sun Microsystems, 1993, as
in musl's ``__rem_pio2``, ``__sin`` and ``__cos``), reduced to the part the
kernels need and written without branches so that LLVM inlines and schedules
it with the rest of the kernel (about 1 ns per pair in a vectorized loop):

1. range reduction ``x = n pi/2 + y`` with ``n = round(x 2/pi)`` and ``y``
   carried as ``y0 + y1`` (a double-double), by Cody and Waite's method
   with pi/2 split into 33-bit pieces, so that ``n`` times a piece is exact
   for ``|n| < 2^20``; all three of fdlibm's reduction rounds run every time
   (fdlibm skips the second and third when ``y0`` kept enough bits, and
   running them is never less accurate);
2. fdlibm's minimax polynomials for ``sin`` and ``cos`` on ``[-pi/4, pi/4]``
   (error below 2^-58 relative to the function), with the ``y1`` correction;
3. the quadrant ``n mod 4`` picks and signs the pair by exact blends with
   weights 0 and 1, not jumps, so that the same source also runs on numpy
   arrays (the numpy backend gives bit-identical results). The one
   difference from libm this makes: ``sin(-0.0)`` is ``+0.0``.

Accuracy: within 1 ulp of a correctly rounded result, which is fdlibm's
bound; ``tests/test_trig.py`` checks it against libm over 5 million angles,
those next to multiples of pi/2 included (:data:`relacc.core.tolerances.TRIG_ULPS`).
It is valid for ``|x| <= LIMIT`` (``2^20 pi/2``, about 1.6e6 rad): beyond,
``n`` times the first piece of pi/2 is no longer exact, and the kernels use
libm for such states instead (:func:`relacc.kernels.perstate._trig`).
"""

from __future__ import annotations

import numpy as np

from relacc.kernels.jit import HAVE_NUMBA, jitable, numba

LIMIT = 1048576.0 * 1.5707963267948966
"""Largest ``|x|`` (rad) :func:`sincos` accepts: ``2^20 pi/2``, where ``n * PIO2_1`` stops being exact."""

INVPIO2 = 6.36619772367581382433e-01  # 2/pi, 53 bits
PIO2_1 = 1.57079632673412561417e00  # first 33 bits of pi/2
PIO2_1T = 6.07710050650619224932e-11  # pi/2 - PIO2_1
PIO2_2 = 6.07710050630396597660e-11  # second 33 bits of pi/2
PIO2_2T = 2.02226624879595063154e-21  # pi/2 - (PIO2_1 + PIO2_2)
PIO2_3 = 2.02226624871116645580e-21  # third 33 bits of pi/2
PIO2_3T = 8.47842766036889956997e-32  # pi/2 - (PIO2_1 + PIO2_2 + PIO2_3)

# fdlibm k_sin.c: sin(y) ~ y + S1 y^3 + ... + S6 y^13 on [-pi/4, pi/4]
S1 = -1.66666666666666324348e-01
S2 = 8.33333333332248946124e-03
S3 = -1.98412698298579493134e-04
S4 = 2.75573137070700676789e-06
S5 = -2.50507602534068634195e-08
S6 = 1.58969099521155010221e-10
# fdlibm k_cos.c: cos(y) ~ 1 - y^2/2 + C1 y^4 + ... + C6 y^14 on [-pi/4, pi/4]
C1 = 4.16666666666666019037e-02
C2 = -1.38888888888741095749e-03
C3 = 2.48015872894767294178e-05
C4 = -2.75573143513906633035e-07
C5 = 2.08757232129817482790e-09
C6 = -1.13596475577881948265e-11


@jitable
def _reduce(x):
    """``(n, y0, y1)`` with ``x = n pi/2 + y0 + y1``, ``|y0 + y1| <= pi/4`` (about), for ``|x| <= LIMIT``."""
    n = np.floor(x * INVPIO2 + 0.5)
    r = x - n * PIO2_1  # exact: n * PIO2_1 has at most 53 bits and r at most 52
    t = r  # second round, good to 118 bits (fdlibm)
    w = n * PIO2_2
    r = t - w
    w = n * PIO2_2T - ((t - r) - w)
    t = r  # third round, 151 bits
    w = n * PIO2_3
    r = t - w
    w = n * PIO2_3T - ((t - r) - w)
    y0 = r - w
    return n, y0, (r - y0) - w


@jitable
def sincos(x):
    """``(sin x, cos x)`` for a float ``x`` (rad) with ``|x| <= LIMIT``, each within 1 ulp.

    Args:
        x: the angle, rad; a scalar (compiled into the kernels) or a float64 array (numpy backend).

    Returns:
        ``(sin x, cos x)``, dimensionless. For ``|x| > LIMIT`` the result is
        not accurate (NaN and inf give NaN); callers check the range.
    """
    n, y0, y1 = _reduce(x)
    z = y0 * y0
    w = z * z
    r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6)  # fdlibm __kernel_sin(y0, y1, 1)
    v = z * y0
    s = y0 - ((z * (0.5 * y1 - v * r) - y1) - v * S1)
    r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6))  # fdlibm __kernel_cos(y0, y1)
    hz = 0.5 * z
    w = 1.0 - hz
    c = w + (((1.0 - w) - hz) + (z * r - y0 * y1))
    k = n - 4.0 * np.floor(n * 0.25)  # quadrant 0, 1, 2, 3
    o = 1.0 * ((k == 1.0) | (k == 3.0))  # 1 in odd quadrants, where sine and cosine swap
    e = 1.0 - o
    sign_s = 1.0 - 2.0 * (k >= 2.0)
    sign_c = 1.0 - 2.0 * ((k == 1.0) | (k == 2.0))
    return (s * e + c * o) * sign_s, (c * e + s * o) * sign_c  # exact blends: one weight is 0, the other 1

if HAVE_NUMBA:

    @numba.njit(cache=True)
    def _sincos_array(x, s, c):  # pragma: no cover - compiled
        for i in range(x.shape[0]):
            s[i], c[i] = sincos(x[i])


def sincos_array(x):
    """:func:`sincos` on a 1-D float64 array (compiled; for tests and benchmarks).

    Args:
        x: ``(n,)`` angles, rad, each within ``[-LIMIT, LIMIT]``.

    Returns:
        ``(sin, cos)``, two ``(n,)`` arrays, dimensionless.
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    s, c = np.empty_like(x), np.empty_like(x)
    _sincos_array(x, s, c)
    return s, c
