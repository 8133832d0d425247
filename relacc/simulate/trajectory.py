"""What one engine's run of a scene records, block by block, and what it keeps.

A :class:`Track` receives the run a block of records at a time (states and
what is observed at them) and keeps only running summaries: the first and
last records, the energy's drift and scale, the momenta's drift; with
``keep=True`` it also keeps every record and ends as a :class:`Trajectory`.
So a long run's memory is set by the block, not by the number of steps.

Energy drift is ``max_t |E(t) - E(0)| / S`` with ``S = max_t (T + |V_g| + V_s)``,
the largest magnitude of the energy's terms along the run (kinetic, gravity's
and the spring's potential): the scale the error model uses for any sum, and
never zero unless nothing moves at all (the drift is then 0).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

OBSERVED = ("position", "velocity", "acceleration", "energy", "energy_scale", "momentum", "angular_momentum")
"""What is observed at every record (see :class:`Trajectory`)."""


def drift(values, origin, scale) -> float:
    """``max |values - origin| / scale`` (0 when nothing changed, whatever the scale)."""
    change = float(np.max(np.abs(values - origin))) if np.size(values) else 0.0
    return 0.0 if change == 0.0 else change / max(float(scale), np.finfo(float).tiny)


@dataclass(frozen=True, eq=False)
class Trajectory:
    """One engine's run, every record. Arrays share the leading time axis.

    Attributes:
        engine: ``relacc`` or an engine's name.
        t: ``(m,)`` s; the first record is ``t = 0``, the last ``t = duration``.
        q, u: ``(m, .)`` the engine's own coordinates (relacc: the scene's case
            coordinates and speeds).
        columns: names of the ``q`` and ``u`` columns.
        position, velocity, acceleration: ``(m, 3)`` G2 in R, fixed components
            (m, m/s, m/s^2; classical acceleration).
        energy: ``(m,)`` J (kinetic + potential of the conservative effects).
        energy_scale: ``(m,)`` J, ``T + |V_g| + V_s``, the magnitude of the energy's terms.
        momentum, angular_momentum: ``(m, 3)`` kg m/s and kg m^2/s about R's origin, fixed components.
        seconds: wall time of the integration alone. applied: what the engine was told to apply.
    """

    engine: str
    t: np.ndarray
    q: np.ndarray
    u: np.ndarray
    columns: tuple[list, list]
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    energy: np.ndarray
    energy_scale: np.ndarray
    momentum: np.ndarray
    angular_momentum: np.ndarray
    seconds: float
    applied: dict = field(default_factory=dict)

    def energy_drift(self) -> float:
        """``max |E(t) - E(0)| / max_t (T + |V_g| + V_s)``: relative drift of the energy (module docstring)."""
        return drift(self.energy, self.energy[0], np.max(self.energy_scale))

    def momentum_drift(self) -> tuple[float, float]:
        """Largest change of the linear (kg m/s) and angular (kg m^2/s) momenta over the run."""
        return (float(np.max(np.linalg.norm(self.momentum - self.momentum[0], axis=1))),
                float(np.max(np.linalg.norm(self.angular_momentum - self.angular_momentum[0], axis=1))))


class Track:
    """One engine's run in progress: running summaries, and every record when ``keep``."""

    def __init__(self, engine: str, columns, applied: dict, keep: bool):
        self.engine, self.columns, self.applied, self.keep = engine, columns, applied, keep
        self.blocks: list[dict] = []
        self.first: dict | None = None
        self.last: dict | None = None
        self.seconds = 0.0
        self.max_energy_change = self.energy_scale = 0.0
        self.max_momentum_change = self.max_angular_change = 0.0

    def add(self, block: dict) -> None:
        """One block of records: ``t``, ``q``, ``u`` and every :data:`OBSERVED` quantity, ``(b, ...)`` each."""
        if self.first is None:
            self.first = {k: v[0].copy() for k, v in block.items()}
        f = self.first
        self.max_energy_change = max(self.max_energy_change, float(np.max(np.abs(block["energy"] - f["energy"]))))
        self.energy_scale = max(self.energy_scale, float(np.max(block["energy_scale"])))
        self.max_momentum_change = max(self.max_momentum_change, float(np.max(np.linalg.norm(
            block["momentum"] - f["momentum"], axis=1))))
        self.max_angular_change = max(self.max_angular_change, float(np.max(np.linalg.norm(
            block["angular_momentum"] - f["angular_momentum"], axis=1))))
        self.last = {k: v[-1].copy() for k, v in block.items()}
        if self.keep:
            self.blocks.append(block)

    def energy_drift(self) -> float:
        """As :meth:`Trajectory.energy_drift`, from the running summaries."""
        return 0.0 if self.max_energy_change == 0.0 else self.max_energy_change / max(self.energy_scale,
                                                                                         np.finfo(float).tiny)

    def momentum_drift(self) -> tuple[float, float]:
        """As :meth:`Trajectory.momentum_drift`, from the running summaries."""
        return self.max_momentum_change, self.max_angular_change

    def trajectory(self) -> Trajectory | None:
        """Every record as a :class:`Trajectory` (None unless ``keep``)."""
        if not self.keep:
            return None
        cat = {k: np.concatenate([b[k] for b in self.blocks]) for k in self.blocks[0]}
        return Trajectory(self.engine, cat["t"], cat["q"], cat["u"], self.columns,
                          **{k: cat[k] for k in OBSERVED}, seconds=self.seconds, applied=self.applied)
