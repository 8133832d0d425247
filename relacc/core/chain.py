"""The two-body chain's constant geometry and inertia."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from relacc.errors import InputError


def _real(name, value, what) -> np.ndarray:
    """``value`` as a new float64 array; InputError unless it holds real numbers."""
    try:
        arr = np.array(value)
    except (TypeError, ValueError) as exc:
        raise InputError(f"TwoBodyChain.{name}: expected {what}, {exc}") from None
    if arr.dtype.kind not in "iuf":
        raise InputError(f"TwoBodyChain.{name}: expected {what} (real numbers), got dtype {arr.dtype}")
    return arr.astype(np.float64)


def _vector(name, value) -> np.ndarray:
    arr = _real(name, value, "3 finite numbers (m)")
    if arr.shape != (3,):
        raise InputError(f"TwoBodyChain.{name}: expected 3 numbers (m), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"TwoBodyChain.{name}: every entry must be finite, got {arr.tolist()}")
    arr.setflags(write=False)
    return arr


def _mass(name, value) -> float:
    if isinstance(value, (bool, complex, np.complexfloating)) or not isinstance(value, (int, float, np.number)):
        raise InputError(f"TwoBodyChain.{name}: expected a positive mass in kg, got {value!r}")
    m = float(value)
    if not np.isfinite(m) or m <= 0:
        raise InputError(f"TwoBodyChain.{name}: expected a finite positive mass in kg, got {m}")
    return m


def _inertia(name, value) -> np.ndarray:
    arr = _real(name, value, "a 3x3 inertia tensor (kg m^2)")
    if arr.shape != (3, 3):
        raise InputError(f"TwoBodyChain.{name}: expected a 3x3 tensor (kg m^2), got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"TwoBodyChain.{name}: every entry must be finite")
    scale = np.abs(arr).max()
    if not np.allclose(arr, arr.T, rtol=0, atol=1e-12 * scale):
        raise InputError(f"TwoBodyChain.{name}: inertia tensor must be symmetric, got {arr.tolist()}")
    moments = np.linalg.eigvalsh(arr)
    a, b, c = moments
    # Physically realizable: positive principal moments obeying the triangle inequality.
    if a <= 0 or a + b < c * (1 - 1e-12):
        raise InputError(
            f"TwoBodyChain.{name}: principal moments {moments.tolist()} are not physically "
            "realizable (need all > 0 and each <= the sum of the other two)"
        )
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class TwoBodyChain:
    """Constant geometry and inertia of the two-body chain.

    Args:
        q2: ``q2'``, B2's joint point from B1's origin when ``s2' = 0``,
            B1 components, shape ``(3,)``, m.
        r2: ``r2'``, G2 (B2's mass center) from B2's joint point, B2
            components, shape ``(3,)``, m.
        r1: ``r1'``, G1 (B1's mass center) from B1's origin, B1 components,
            shape ``(3,)``, m. Default ``0``.
        m1, m2: masses of B1 and B2, kg. Default 1.
        I1: inertia tensor of B1 about G1, B1 components, ``(3, 3)``, kg m^2.
        I2: inertia tensor of B2 about G2, B2 components, ``(3, 3)``, kg m^2.

    The kinematics of G2 uses only ``q2`` and ``r2``; the inertia fields serve
    the model fixtures and the equations of motion.

    Raises:
        InputError: non-finite or mis-shaped geometry, non-positive mass,
            asymmetric or unrealizable inertia.
    """

    q2: np.ndarray
    r2: np.ndarray
    r1: np.ndarray = field(default_factory=lambda: np.zeros(3))
    m1: float = 1.0
    m2: float = 1.0
    I1: np.ndarray = field(default_factory=lambda: np.eye(3))
    I2: np.ndarray = field(default_factory=lambda: np.eye(3))

    def __post_init__(self):
        for name in ("q2", "r2", "r1"):
            object.__setattr__(self, name, _vector(name, getattr(self, name)))
        for name in ("m1", "m2"):
            object.__setattr__(self, name, _mass(name, getattr(self, name)))
        for name in ("I1", "I2"):
            object.__setattr__(self, name, _inertia(name, getattr(self, name)))

    def __repr__(self) -> str:
        return (
            f"TwoBodyChain(q2={self.q2.tolist()}, r2={self.r2.tolist()}, r1={self.r1.tolist()}, "
            f"m1={self.m1}, m2={self.m2}, I1={self.I1.tolist()}, I2={self.I2.tolist()})"
        )
