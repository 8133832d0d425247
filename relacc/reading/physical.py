"""Is this a physical robot? Each body of a reading against what a rigid body's mass properties must be.

For mass ``m`` and the inertia ``I`` about the mass centre (principal moments ``A <= B <= C``):

* ``m >= 0``;
* ``I`` positive semidefinite: ``A >= 0`` (to ``c eps`` of ``C``: the moments come from an eigen-decomposition);
* the triangle inequality ``A + B >= C``, to the same tolerance (:func:`relacc.core.tolerances.triangle_violation`):
  ``C = sum m r^2`` over the axes of the other two, so no distribution of mass breaks it;
* ``m = 0`` with ``I != 0``: no body has inertia without mass. The engines each read it differently (MuJoCo drops
  the inertia of a massless body, Pinocchio keeps it, Drake's parsers refuse a zero mass or give it another), so it
  is named as a finding whatever they do.

A body that breaks one is a finding about the file, named with the condition and the numbers; the reading keeps the
body as written (``Body(physical=False)``) so that the engines can still be compared on it.
"""

from __future__ import annotations

import numpy as np

from relacc.core.tolerances import EPS, ROUNDING_FACTOR, triangle_violation
from relacc.reading.model import Finding


def check(name: str, mass: float, inertia, place: str = "") -> list[Finding]:
    """The findings of one body's mass properties (kg; kg m^2 about the mass centre, any frame's components)."""
    out = []
    inertia = np.asarray(inertia, dtype=float)
    moments = np.linalg.eigvalsh(0.5 * (inertia + inertia.T))
    big = float(np.abs(moments).max(initial=0.0))
    if mass < 0:
        out.append(Finding(name, "a negative mass", f"mass {mass:.6g} kg", place))
    if moments[0] < -ROUNDING_FACTOR * EPS * big:
        out.append(Finding(name, "an inertia that is not positive semidefinite",
                           f"principal moments {_moments(moments)} kg m^2", place))
    else:
        broken = triangle_violation(moments)
        if broken:
            out.append(Finding(name, "principal moments that break the triangle inequality",
                               f"{broken} (moments {_moments(moments)} kg m^2)", place))
    if mass == 0 and big > 0:
        out.append(Finding(name, "no mass but an inertia", f"mass 0 kg, principal moments {_moments(moments)} kg m^2",
                           place))
    return out


def is_physical(findings) -> bool:
    return not findings


def _moments(m) -> str:
    return "[" + ", ".join(f"{x:.6g}" for x in m) + "]"
