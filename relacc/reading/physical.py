"""Is this a physical robot? Each body of a reading against what a rigid body's mass properties must be.

For mass ``m`` and the inertia ``I`` about the mass centre (principal moments ``A <= B <= C``):

* ``m >= 0``;
* ``I`` positive semidefinite: ``A >= 0`` (to ``c eps`` of ``C``: the moments come from an eigen-decomposition);
* the triangle inequality ``A + B >= C``, to the same tolerance (:func:`relacc.core.tolerances.triangle_violation`):
  ``C = sum m r^2`` over the axes of the other two, so no distribution of mass breaks it;
* ``m = 0`` with ``I != 0``: no body has inertia without mass. The engines each read it differently (MuJoCo drops
  the inertia of a massless body, Pinocchio keeps it, Drake's parsers refuse a zero mass or give it another), so it
  is named as a finding whatever they do. A subnormal mass (below float64's smallest normal number, 2.2e-308) is
  no mass to any engine's arithmetic, and is named so;
* a radius of gyration ``sqrt(C / m)`` beyond :data:`MAX_GYRATION` (1 km): mass that would have to sit that far from
  the mass centre to give the inertia (a mass of 1e-300 kg with a unit inertia: 1e150 m). No robot is that large.

The conditions hold to the rounding of the eigen-decomposition and of the digits the file writes
(:func:`relacc.core.tolerances.moment_tolerance`): a plate's moments written to 12 digits miss ``A + B >= C`` by a few
units in the 12th digit, which is the file's rounding, not a finding.

A body that breaks one is a finding about the file, named with the condition and the numbers; the reading keeps the
body as written (``Body(physical=False)``) so that the engines can still be compared on it.
"""

from __future__ import annotations

import numpy as np

from relacc.core.tolerances import moment_tolerance, triangle_violation
from relacc.errors import ModelError
from relacc.reading.model import Finding

MAX_GYRATION = 1e3
"""m: the largest radius of gyration ``sqrt(C / m)`` a body may have (module docstring)."""

TINY = float(np.finfo(np.float64).tiny)
"""float64's smallest normal number, 2.2e-308: a positive mass below it is subnormal."""


def check(name: str, mass: float, inertia, place: str = "", written: float = 0.0) -> list[Finding]:
    """The findings of one body's mass properties (kg; kg m^2 about the mass centre, any frame's components).
    ``written``: the Frobenius norm of the rounding the file's digits allow the tensor (kg m^2; 0 for an inertia
    computed, not written)."""
    out = []
    inertia = np.asarray(inertia, dtype=float)
    if not np.all(np.isfinite(inertia)) or not np.isfinite(mass):
        raise ModelError(f"{place}: body {name!r}'s inertia is not finite once its frame is applied (its numbers "
                         "overflow float64); give smaller ones")
    moments = np.linalg.eigvalsh(0.5 * (inertia + inertia.T))
    big = float(np.abs(moments).max(initial=0.0))
    if mass < 0:
        out.append(Finding(name, "a negative mass", f"mass {mass:.6g} kg", place))
    if moments[0] < -moment_tolerance(moments, written):
        out.append(Finding(name, "an inertia that is not positive semidefinite",
                           f"principal moments {_moments(moments)} kg m^2", place))
    else:
        broken = triangle_violation(moments, written)
        if broken:
            out.append(Finding(name, "principal moments that break the triangle inequality",
                               f"{broken} (moments {_moments(moments)} kg m^2)", place))
    if 0 <= mass < TINY and big > 0:
        said = "mass 0 kg" if mass == 0 else f"mass {mass:.3g} kg, subnormal (no mass to the engines' arithmetic)"
        out.append(Finding(name, "no mass but an inertia", f"{said}, principal moments {_moments(moments)} kg m^2",
                           place))
    elif mass > 0 and big > 0 and big > mass * MAX_GYRATION**2:
        out.append(Finding(name, "an inertia too large for its mass",
                           f"mass {mass:.6g} kg, largest principal moment {big:.6g} kg m^2: a radius of gyration of "
                           f"{np.sqrt(big / mass):.3g} m (more than {MAX_GYRATION:g} m)", place))
    return out


def is_physical(findings) -> bool:
    return not findings


def _moments(m) -> str:
    return "[" + ", ".join(f"{x:.6g}" for x in m) + "]"
