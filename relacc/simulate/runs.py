"""Run a scene on relacc, Pinocchio and MuJoCo and compare what they do.

* relacc integrates Kane's equations (:mod:`relacc.dynamics`) in the scene's
  own coordinates (quaternions on SO(3) by RKMK4 for cases 1-2, angles for
  case 3); Pinocchio is integrated by the same RKMK4 on its own manifold
  (``pin.aba``, ``pin.integrate``); MuJoCo steps itself (``mj_step``).
* Along every trajectory: G2's position, velocity and classical acceleration
  (fixed components), the energy of the conservative effects and both momenta.
* Along relacc's trajectory the note's acceleration formulas
  (:func:`relacc.g2_kinematics` with Kane's ``udot``) are compared with each
  engine's own acceleration at the same states.
"""

from __future__ import annotations

import csv
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from relacc import dynamics
from relacc.core.cases import as_case
from relacc.core.kinematics import g2_kinematics
from relacc.core.scales import term_scales
from relacc.core.speeds import to_body_speeds
from relacc.core.tolerances import EPS, normalized_error, rounding_tolerance
from relacc.dynamics.integrate import stepper
from relacc.dynamics.steps import collect
from relacc.engines import load_engine
from relacc.errors import RelaccError
from relacc.simulate.scenes import Scene

NOTE_CHECK_STATES = 40
"""States of relacc's trajectory at which the note's accelerations meet the engines'."""


@dataclass(frozen=True, eq=False)
class Trajectory:
    """One engine's run. Arrays share the leading time axis.

    Attributes:
        engine: ``relacc``, ``pinocchio`` or ``mujoco``.
        t: ``(m,)`` s. q, u: ``(m, .)`` the engine's own coordinates (relacc:
            the scene's case coordinates and speeds).
        columns: names of the ``q`` and ``u`` columns.
        position, velocity, acceleration: ``(m, 3)`` G2 in R, fixed components
            (m, m/s, m/s^2; classical acceleration).
        energy: ``(m,)`` J (kinetic + potential of the conservative effects).
        momentum, angular_momentum: ``(m, 3)`` about R's origin, fixed components.
        seconds: wall time of the integration. applied: what the engine was told to apply.
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
    momentum: np.ndarray
    angular_momentum: np.ndarray
    seconds: float
    applied: dict = field(default_factory=dict)

    def energy_drift(self) -> float:
        """``max |E(t) - E(0)| / max(|E(0)|, T(0))``: relative drift of the energy."""
        ref = max(abs(self.energy[0]), 1e-300)
        return float(np.max(np.abs(self.energy - self.energy[0])) / ref)

    def momentum_drift(self) -> tuple[float, float]:
        """Largest change of the linear (kg m/s) and angular (kg m^2/s) momenta over the run."""
        return (float(np.max(np.linalg.norm(self.momentum - self.momentum[0], axis=1))),
                float(np.max(np.linalg.norm(self.angular_momentum - self.angular_momentum[0], axis=1))))


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """All engines' trajectories of one scene, and their comparison."""

    scene: Scene
    trajectories: dict
    note_check: dict

    def differences(self):
        """Largest G2 position and velocity difference over the run, over every pair of engines."""
        names = list(self.trajectories)
        pos = vel = 0.0
        pairs = {}
        for i, a in enumerate(names):
            for b in names[i + 1:]:
                ta, tb = self.trajectories[a], self.trajectories[b]
                dp = float(np.max(np.linalg.norm(ta.position - tb.position, axis=1)))
                dv = float(np.max(np.linalg.norm(ta.velocity - tb.velocity, axis=1)))
                pairs[f"{a}-{b}"] = {"position": dp, "velocity": dv}
                pos, vel = max(pos, dp), max(vel, dv)
        return pos, vel, pairs

    def summary(self) -> dict:
        """The ``relacc simulate --json`` object."""
        pos, vel, pairs = self.differences()
        eff = self.scene.effects
        engines = {}
        for name, tr in self.trajectories.items():
            p_drift, h_drift = tr.momentum_drift()
            engines[name] = {
                "g2_position_final": tr.position[-1].tolist(),
                "energy_drift": tr.energy_drift() if eff.conserves_energy else None,
                "momentum_drift": p_drift if eff.conserves_momentum else None,
                "angular_momentum_drift": h_drift if eff.conserves_momentum else None,
                "seconds": tr.seconds,
                "applied": tr.applied,
            }
        return {
            "scene": self.scene.name,
            "case": self.scene.case,
            "integrator": self.scene.integrator,
            "dt": self.scene.dt,
            "duration": self.scene.duration,
            "effects": eff.describe(),
            "engines": engines,
            "max_g2_position_difference": pos,
            "max_g2_velocity_difference": vel,
            "pairs": pairs,
            "note_acceleration_vs_engines": self.note_check,
        }


def relacc_trajectory(scene: Scene, progress=None) -> Trajectory:
    """relacc's own run of a scene: Kane's equations integrated in the scene's coordinates."""
    chain, case, eff = scene.fixture.chain, scene.case, scene.effects
    advance = stepper(chain, case, eff, scene.dt, scene.integrator)
    start = time.perf_counter()
    t, Q, U = collect(advance, scene.q, scene.u, scene.dt, scene.n_steps, scene.record_every, who="relacc",
                      integrator=scene.integrator, progress=progress)
    seconds = time.perf_counter() - start
    Udot = dynamics.accelerations(chain, case, Q, U, eff)
    k = g2_kinematics(chain, case, Q, U, Udot)
    p, H = dynamics.momenta(chain, case, Q, U)
    names_q = [f"q{i}" for i in range(Q.shape[1])]
    return Trajectory("relacc", t, Q, U, (names_q, [f"u{i}" for i in range(12)]),
                      k.position, k.velocity, k.acceleration, dynamics.energy(chain, case, Q, U, eff), p, H,
                      seconds, {"equations": "Kane, " + (", ".join(eff.active()) or "no effects")})


def _engine(name: str, engine, scene: Scene, progress=None) -> Trajectory:
    chain, eff = scene.fixture.chain, scene.effects
    q0, v0 = engine.initial_state(scene.case, scene.q, scene.u)
    start = time.perf_counter()
    t, Q, V = engine.simulate(q0, v0, eff, scene.dt, scene.n_steps, scene.integrator,
                              scene.record_every, progress)
    seconds = time.perf_counter() - start
    A = engine.forward_dynamics(Q, V, eff)
    applied = engine.configure(eff) if hasattr(engine, "configure") else None
    pts = engine.points("quaternion", Q, V, A)
    q14, nu = engine.body_state(Q, V)
    p, H = dynamics.momenta(chain, 2, q14, nu)
    velocity = np.einsum("nij,nj->ni", pts.J, V)
    if applied is not None:
        info = {"disabled": applied}
    else:
        g = "0 (off)" if eff.gravity is None else str(eff.gravity.tolist())
        forces = [n for n in eff.active() if n != "gravity"]
        info = {"model.gravity": g, "generalized forces": forces or "none"}
    return Trajectory(name, t, Q, V, ([f"q{i}" for i in range(Q.shape[1])], [f"v{i}" for i in range(V.shape[1])]),
                      pts.position, velocity, pts.acceleration, dynamics.energy(chain, 2, q14, nu, eff), p, H,
                      seconds, info)


def _note_check(scene: Scene, rel: Trajectory, engines: dict) -> dict:
    """The note's a_G2 against each engine's, at relacc's states: error and bound.

    Both sides solve their own equations of motion for ``udot``, so rounding
    is amplified by the conditioning of the mass matrix. G2's acceleration
    does not depend on the chart, so the bound uses the body-speed (Case 2)
    mass matrix: ``c eps kappa(M_body)`` (largest over the states; case 3's
    own ``M`` is ill-conditioned near gimbal lock only along angle-rate
    combinations that barely move G2). The error is normalized by the
    acceleration's term scale.
    """
    chain, case, eff = scene.fixture.chain, scene.case, scene.effects
    idx = np.unique(np.linspace(0, len(rel.t) - 1, NOTE_CHECK_STATES).astype(int))
    Q, U = rel.q[idx], rel.u[idx]
    Udot = dynamics.accelerations(chain, case, Q, U, eff)
    note = g2_kinematics(chain, case, Q, U, Udot).acceleration
    scale = term_scales(chain, case, Q, U, Udot).acceleration
    q14, nu, _ = to_body_speeds(case, Q, U)
    M_body, _ = dynamics.equations_of_motion(chain, 2, q14, nu, eff)
    bound = float(rounding_tolerance() * np.max(np.linalg.cond(M_body)))
    out = {}
    for name, engine in engines.items():
        x = engine.engine_input("quaternion", as_case(case), Q, U, None)
        A = engine.forward_dynamics(x.q, x.v, eff)
        pts = engine.points("quaternion", x.q, x.v, A)
        out[name] = {"error": float(np.max(normalized_error(pts.acceleration, note, scale))), "bound": bound}
    return out


def run(scene: Scene, engines=None, progress=None) -> SimulationResult:
    """Simulate a scene on its engines (or ``engines``) and compare them.

    Args:
        progress: callable ``(engine, fraction)`` or None.

    Raises:
        RelaccError: unknown engine or an integrator an engine lacks.
    """
    names = tuple(engines) if engines is not None else scene.engines
    bad = [n for n in names if n not in ("relacc", "pinocchio", "mujoco")]
    if bad:
        raise RelaccError(f"unknown engines {bad}: accepted are relacc, pinocchio, mujoco")
    loaded = {n: load_engine(n, scene.fixture) for n in names if n != "relacc"}
    trajectories = {}
    for name in names:
        cb = (lambda f, n=name: progress(n, f)) if progress else None
        trajectories[name] = (relacc_trajectory(scene, cb) if name == "relacc"
                              else _engine(name, loaded[name], scene, cb))
    note = _note_check(scene, trajectories["relacc"], loaded) if "relacc" in trajectories and loaded else {}
    return SimulationResult(scene, trajectories, note)


def write_csv(result: SimulationResult, directory) -> list[Path]:
    """One CSV per engine in ``directory``: time, q, u (engine coordinates), G2 r, v, a (fixed comps), energy."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, tr in result.trajectories.items():
        path = directory / f"{result.scene.name}-{name}.csv"
        header = (["t_s"] + tr.columns[0] + tr.columns[1]
                  + [f"G2_r{a}_m" for a in "xyz"] + [f"G2_v{a}_m_s" for a in "xyz"]
                  + [f"G2_a{a}_m_s2" for a in "xyz"] + ["energy_J"])
        rows = np.column_stack([tr.t, tr.q, tr.u, tr.position, tr.velocity, tr.acceleration, tr.energy])
        with path.open("w", newline="") as fh:
            fh.write(f"# relacc simulate {result.scene.name} ({name}); q, u in {name}'s coordinates; "
                     "G2 position, velocity, classical acceleration in fixed-frame components\n")
            writer = csv.writer(fh)
            writer.writerow(header)
            writer.writerows(rows.tolist())
        paths.append(path)
    return paths


def format_text(result: SimulationResult) -> str:
    """The human-readable summary printed by ``relacc simulate``."""
    scene, summary, eff = result.scene, result.summary(), result.scene.effects
    out = []
    out.append(f"{scene.title} ({scene.name}): case {scene.case}, {scene.integrator}, dt = {scene.dt} s, "
               f"{scene.duration} s, effects: {', '.join(eff.active()) or 'none'}")
    out.append(f"{'engine':10s} {'G2 position at the end (fixed comps, m)':44s} {'energy drift':>12s} "
               f"{'momentum drift':>15s} {'seconds':>8s}")
    for name, e in summary["engines"].items():
        pos = ", ".join(f"{x:.9f}" for x in e["g2_position_final"])
        ed = "-" if e["energy_drift"] is None else f"{e['energy_drift']:.2e}"
        md = "-" if e["momentum_drift"] is None else f"{e['momentum_drift']:.2e}"
        out.append(f"{name:10s} [{pos:42s}] {ed:>12s} {md:>15s} {e['seconds']:8.3f}")
    out.append(f"largest G2 difference between engines over the run: position "
               f"{summary['max_g2_position_difference']:.3e} m, "
               f"velocity {summary['max_g2_velocity_difference']:.3e} m/s")
    for name, c in summary["note_acceleration_vs_engines"].items():
        out.append(f"note's acceleration along relacc's trajectory vs {name}: {c['error']:.2e} (normalized, "
              f"{c['error'] / EPS:.1f} eps; bound c eps kappa(M) = {c['bound']:.1e})")
    out.append("energy drift: max |E - E0| / |E0| where only conservative effects act; momentum drift: max |p - p0| "
               "(kg m/s) where no external force acts")
    return "\n".join(out)
