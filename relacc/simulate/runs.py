"""Run a scene on relacc and the engines, in lockstep, and compare what they do.

* relacc integrates Kane's equations (:mod:`relacc.dynamics`) in the scene's
  own coordinates (quaternions on SO(3) by RKMK4 for cases 1-2, angles for
  case 3); each engine integrates with its own stepper
  (:meth:`relacc.engines.base.Adapter.stepper`); all through the one step loop
  (:mod:`relacc.dynamics.steps`), so every run records ``t = 0``, every
  ``record_every``-th step and ``t = duration``.
* At every record: G2's position, velocity and classical acceleration (fixed
  components), the energy of the conservative effects and both momenta.
* The engines advance together, :data:`RECORD_BLOCK` records at a time; each
  block is compared between engines, summarized (:class:`relacc.simulate.trajectory.Track`)
  and, with ``out``, appended to one CSV per engine. With ``keep=False``
  nothing else is kept: memory is set by the block, whatever the steps.
* Along relacc's trajectory the note's acceleration formulas
  (:func:`relacc.g2_kinematics` with Kane's ``udot``) are compared with each
  engine's own acceleration at the same states.
"""

from __future__ import annotations

import contextlib
import csv
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from relacc import files
from relacc.core.tolerances import EPS
from relacc.dynamics.steps import BLOCK, blocks, recorded_steps
from relacc.errors import EngineError, IntegrationError
from relacc.limits import require_memory
from relacc.simulate import subjects
from relacc.simulate.scenes import SIM_ENGINES, Scene
from relacc.simulate.trajectory import Track, Trajectory

RECORD_BLOCK = BLOCK
"""Records per block: the engines advance, are compared and are written this many records at a time."""

NOTE_CHECK_STATES = 40
"""States of relacc's trajectory at which the note's accelerations meet the engines'."""


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """All engines' runs of one scene, and their comparison.

    Attributes:
        scene: what was run.
        tracks: ``{engine: Track}``, the running summaries of each run.
        trajectories: ``{engine: Trajectory}`` with every record, or ``{}`` when run with ``keep=False``.
        pairs: ``{"a-b": {"position": m, "velocity": m/s}}``, the largest G2 differences over the run.
        note_check: ``{engine: {"error", "bound", "along"}}``, the note's acceleration against each engine's (at
            relacc's states, or the first engine's when relacc does not run: ``along`` names whose; with
            ``"quaternions_normalized"``, how far off unit that engine's quaternions were, normalized for the check).
        csv: the CSV files written (``out``), else ``[]``.

    The verdict (:attr:`agree`) is the acceleration check's: the engines integrate with their own schemes in their
    own coordinates, so their trajectories differ by their truncation errors (shown, not judged), but at the same
    state every engine's acceleration must be relacc's to rounding, ``c eps kappa(M)``. An engine that is not reads
    the model (or applies the scene's effects) differently, and the run exits 1.
    """

    scene: Scene
    tracks: dict
    trajectories: dict
    pairs: dict
    note_check: dict
    csv: list

    @property
    def differing(self) -> dict:
        """``{engine: check}`` of the engines whose acceleration is not relacc's within the bound."""
        return {name: c for name, c in self.note_check.items() if not c["error"] <= c["bound"]}

    @property
    def agree(self) -> bool:
        return not self.differing

    @property
    def exit_code(self) -> int:
        return 0 if self.agree else 1

    def verdict(self) -> str:
        """One sentence: whether every engine's acceleration is relacc's at the same states."""
        who = self.scene.reference
        if not self.note_check:
            return "nothing to judge: only one evaluator ran"
        if self.agree:
            return (f"every engine's acceleration agrees with {who} at the same states "
                    f"({', '.join(self.note_check)}); how far the trajectories then drift apart (shown) is the "
                    "integrators' doing and is not judged")
        parts = [f"{name} by {c['error']:.2e} (bound {c['bound']:.1e})" + (
            " at the start, and its run diverged (left out of the run)" if "diverged" in c else "")
            for name, c in self.differing.items()]
        return (f"DISAGREE: at the same states the acceleration differs from {who}: {'; '.join(parts)}: "
                f"{'that engine reads' if len(parts) == 1 else 'those engines read'} the model or the scene's effects "
                "differently (relacc compare FILE says where)")

    def differences(self) -> tuple[float, float, dict]:
        """Largest G2 position (m) and velocity (m/s) difference over the run, over every pair; and the pairs."""
        pos = max((p["position"] for p in self.pairs.values()), default=0.0)
        vel = max((p["velocity"] for p in self.pairs.values()), default=0.0)
        return pos, vel, self.pairs

    def summary(self) -> dict:
        """The ``relacc simulate --json`` object, the same keys for the chain and a model: ``point`` names the observed
        point (``G2`` for the chain), ``reference`` whose acceleration the engines' are judged against."""
        pos, vel, pairs = self.differences()
        eff = self.scene.effects
        engines = {}
        for name, tr in self.tracks.items():
            p_drift, h_drift = tr.momentum_drift()
            engines[name] = {
                "point_position_final": tr.last["position"].tolist(),
                "t_final": float(tr.last["t"]),
                "energy_drift": tr.energy_drift() if eff.conserves_energy else None,
                "momentum_drift": p_drift if self.scene.conserves_momentum else None,
                "angular_momentum_drift": h_drift if self.scene.conserves_momentum else None,
                "seconds": tr.seconds,
                "applied": tr.applied,
            }
        return {
            "scene": self.scene.name, "case": self.scene.case, "integrator": self.scene.integrator,
            "dt": self.scene.dt, "duration": self.scene.duration, "steps": self.scene.n_steps,
            "record_every": self.scene.record_every, "effects": eff.describe(), "point": self.scene.observe,
            "reference": self.scene.reference, "engines": engines, "max_point_position_difference": pos,
            "max_point_velocity_difference": vel, "pairs": pairs, "reference_acceleration_vs_engines": self.note_check,
            "agree": self.agree, "verdict": self.verdict(), "csv": [str(c) for c in self.csv],
            "left_out": dict(self.scene.left_out), "not_evaluated": list(self.scene.unevaluated),
        }


class _Run:
    """One engine's run in progress: its blocks of records, its observation, its track."""

    def __init__(self, name, engine, scene: Scene, steps, keep, progress):
        integrator, accuracy = scene.integrator_for(name)
        if name == "relacc":
            integ, observe, applied = subjects.relacc_run(scene, integrator)
            x0, v0 = scene.q, scene.u
        else:
            q2, v2 = subjects.reference_state(scene, scene.q[None], scene.u[None])
            states_e = engine.to_engine(q2, v2)
            qe, ve = states_e.q, states_e.v
            x0, v0 = qe[0], ve[0]
            integ = engine.stepper(scene.engine_effects, scene.dt, integrator, accuracy)
            observe, applied = subjects.engine_observer(engine, scene), engine.applied(scene.engine_effects)
            if (integrator, accuracy) != (scene.integrator, None):
                applied = {"integrator": integrator + ("" if accuracy is None else f", error-controlled to "
                                                       f"{accuracy:g}"), **applied}
        x0, v0 = np.asarray(x0, dtype=float), np.asarray(v0, dtype=float)
        columns = ([f"q{i}" for i in range(x0.size)], [("u" if name == "relacc" else "v") + str(i)
                                                        for i in range(v0.size)])
        self.track = Track(name, columns, applied, keep)
        self.observe = observe
        cb = (lambda f: progress(name, f)) if progress else None
        self.blocks = blocks(integ, x0, v0, steps, who=name, dt=scene.dt, integrator=integrator, progress=cb,
                             size=RECORD_BLOCK)

    def block(self, dt) -> dict:
        """The next block of records, observed and added to the track (its seconds: the integration alone)."""
        start = time.perf_counter()
        chunk, X, V = next(self.blocks)
        self.track.seconds += time.perf_counter() - start
        block = {"t": chunk * dt, "q": X, "u": V, **self.observe(chunk * dt, X, V)}
        self.track.add(block)
        return block


def run(scene: Scene, engines: Sequence[str] | None = None, progress: Callable[[str, float], object] | None = None, *,
        keep: bool = True, out: str | os.PathLike | None = None, check: bool = True) -> SimulationResult:
    """Simulate a scene on its engines (or ``engines``), in lockstep, and compare them (:func:`_run`). An engine's
    run that diverges where relacc's does not is judged as any engine is, by its acceleration against relacc's at the
    same state (the scene's start): when it differs there, that engine reads the model differently (issue 49: a
    second free joint read into a URDF diverged as "reduce the step"), and the run goes on without it, the result
    naming it (exit 1); when it agrees, the divergence is the integrator's, and raised."""
    names = tuple(engines) if engines is not None else scene.engines
    try:
        return _run(scene, names, progress, keep=keep, out=out, check=check)
    except IntegrationError as exc:
        who = str(exc).partition(":")[0]
        if who == "relacc" or who not in names or "relacc" not in names or not check:
            raise
        engine = subjects.adapter(scene, who)
        judged = subjects.note_check(scene, [(scene.q, scene.u, 0.0)], {who: engine})[who]
        if judged["error"] <= judged["bound"]:
            raise
        rest = _run(scene, tuple(n for n in names if n != who), progress, keep=keep, out=out, check=check)
        rest.note_check[who] = {**judged, "diverged": str(exc)}
        return rest


def _run(scene: Scene, names: tuple, progress: Callable[[str, float], object] | None = None, *,
         keep: bool = True, out: str | os.PathLike | None = None, check: bool = True) -> SimulationResult:
    """Simulate a scene on the engines ``names``, in lockstep, and compare them.

    Args:
        progress: callable ``(engine, fraction)`` or None.
        keep: keep every record (``SimulationResult.trajectories``); False keeps summaries only.
        out: a directory for one CSV per engine (created if needed; the files
            are replaced all or nothing when the run ends); None writes nothing.
        check: False skips relacc's acceleration against the engines' at the run's states (``SimulationResult.note``
            empty): for runs whose trajectory alone is asked for (the integrator sweeps, which judge the engines on
            a run of their own that includes relacc). An engine's explicit integrator alone drifts its quaternions'
            norms by its truncation error (Drake's Euler: 4e-5 at dt = 0.08 s), and relacc evaluates only unit ones.

    Raises:
        EngineError: unknown engine or an integrator an engine lacks.
        IntegrationError: a run diverged. InputError: ``out`` cannot be written (checked first).
    """
    bad = [n for n in names if n not in SIM_ENGINES]
    if bad:
        raise EngineError(f"unknown engines {bad}: accepted are {', '.join(SIM_ENGINES)}")
    if out is not None:
        files.check_new_directory(out)
    steps = recorded_steps(scene.n_steps, scene.record_every)
    if keep:
        require_memory(8.0 * len(steps) * len(names) * (scene.q.size + 26 + 17), f"keeping {len(steps)} records "
                       f"of {len(names)} runs", "run with keep=False (relacc simulate does), or record_every > 1")
    loaded = {n: subjects.adapter(scene, n) for n in names if n != "relacc"}
    runs = {n: _Run(n, loaded.get(n), scene, steps, keep, progress) for n in names}
    note_at = set(np.unique(np.linspace(0, len(steps) - 1, NOTE_CHECK_STATES).astype(int)).tolist())
    note_states, pairs = [], {}
    paths = [Path(out) / f"{scene.name}-{n}.csv" for n in names] if out is not None else []
    made: contextlib.AbstractContextManager = files.new_directory(out) if out is not None else contextlib.nullcontext()
    opened: contextlib.AbstractContextManager = files.streams(paths) if paths else contextlib.nullcontext({})
    with made, opened as handles:
        writers = {n: _csv_writer(handles[p], scene, runs[n].track) for n, p in zip(names, paths)}
        for start in range(0, len(steps), RECORD_BLOCK):
            chunk = steps[start:start + RECORD_BLOCK]
            blocks_ = {n: r.block(scene.dt) for n, r in runs.items()}
            _compare_pairs(blocks_, pairs)
            first = blocks_["relacc" if "relacc" in blocks_ else names[0]]
            note_states += [(first["q"][j - start], first["u"][j - start], first["t"][j - start])
                            for j in range(start, start + len(chunk)) if j in note_at]
            for n, w in writers.items():
                b = blocks_[n]
                w.writerows(np.column_stack([b["t"], b["q"], b["u"], b["position"], b["velocity"],
                                             b["acceleration"], b["energy"]]).tolist())
    drift = 0.0
    if "relacc" not in names and note_states:  # the first engine's states, in the reference's case-2 coordinates
        q, v = loaded[names[0]].from_engine(np.array([x[0] for x in note_states]),
                                            np.array([x[1] for x in note_states]))
        q, drift = _unit_quaternions(loaded[names[0]].reference, q)
        note_states = [(q[i], v[i], x[2]) for i, x in enumerate(note_states)]
    case = scene.case if "relacc" in names else 2
    note = subjects.note_check(scene, note_states, loaded, case=case) if check and note_states and loaded else {}
    for c in note.values():  # whose trajectory the states are on, and what was done to them
        c["along"] = "relacc" if "relacc" in names else names[0]
        if drift:
            c["quaternions_normalized"] = drift
    tracks = {n: r.track for n, r in runs.items()}
    trajectories = {n: t.trajectory() for n, t in tracks.items()} if keep else {}
    return SimulationResult(scene, tracks, trajectories, pairs, note, paths)


def _unit_quaternions(tree, q) -> tuple[np.ndarray, float]:
    """``(q, drift)``: case-2 states ``q (n, nq)`` of ``tree`` with quaternions farther from unit than relacc accepts
    (an engine's explicit integrator drifts their norm by its truncation error: Drake's Euler 4e-5 at dt = 0.08 s)
    normalized, and the largest ``| |q|^2 - 1 |`` so corrected (0.0: nothing changed). The engines evaluate a
    quaternion's rotation as if unit (Drake through ``2 / |q|^2``, MuJoCo normalizing every step), so the normalized
    state is the one they mean; the caller says so."""
    from relacc.core.cases import quaternion_norm_deviation
    from relacc.core.tolerances import QUATERNION_NORM_TOLERANCE
    from relacc.core.tree.coordinates import rotations

    q, drift = np.array(q, dtype=float), 0.0
    for _, _, a, _ in rotations(tree, 2):
        dev = quaternion_norm_deviation(q[:, a:a + 4])  # what relacc's input check measures
        far = dev > QUATERNION_NORM_TOLERANCE
        if np.any(far):
            drift = max(drift, float(np.max(dev)))
            q[far, a:a + 4] /= np.linalg.norm(q[far, a:a + 4], axis=1)[:, None]
    return q, drift


def relacc_trajectory(scene: Scene, progress=None) -> Trajectory:
    """relacc's own run of a scene alone, every record kept."""
    return run(scene, engines=("relacc",), progress=progress).trajectories["relacc"]


def _compare_pairs(blocks: dict, pairs: dict) -> None:
    """Fold one block's largest G2 differences between every pair of engines into ``pairs``."""
    names = list(blocks)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            p = pairs.setdefault(f"{a}-{b}", {"position": 0.0, "velocity": 0.0})
            for key in ("position", "velocity"):
                p[key] = max(p[key], float(np.max(np.linalg.norm(blocks[a][key] - blocks[b][key], axis=1))))


def _csv_writer(handle, scene: Scene, track: Track):
    handle.write(f"# relacc simulate {scene.name} ({track.engine}); q, u in {track.engine}'s coordinates; "
                 "G2 position, velocity, classical acceleration in fixed-frame components\n")
    writer = csv.writer(handle)
    writer.writerow(["t_s"] + track.columns[0] + track.columns[1] + [f"G2_r{a}_m" for a in "xyz"]
                    + [f"G2_v{a}_m_s" for a in "xyz"] + [f"G2_a{a}_m_s2" for a in "xyz"] + ["energy_J"])
    return writer


def format_text(result: SimulationResult) -> str:
    """The human-readable summary printed by ``relacc simulate``."""
    scene, summary, eff = result.scene, result.summary(), result.scene.effects
    label = scene.observe
    out = [f"{scene.title} ({scene.name}): case {scene.case}, {scene.integrator}, dt = {scene.dt} s, "
           f"{scene.duration} s ({scene.n_steps} steps), effects: {', '.join(eff.active()) or 'none'}",
           f"{'engine':10s} {label + ' position at t = ' + format(scene.duration, 'g') + ' s (fixed comps, m)':44s} "
           f"{'energy drift':>12s} {'momentum drift':>15s} {'seconds':>8s}"]
    for name, e in summary["engines"].items():
        pos = ", ".join(f"{x:.9f}" for x in e["point_position_final"])
        ed = "-" if e["energy_drift"] is None else f"{e['energy_drift']:.2e}"
        md = "-" if e["momentum_drift"] is None else f"{e['momentum_drift']:.2e}"
        out.append(f"{name:10s} [{pos:42s}] {ed:>12s} {md:>15s} {e['seconds']:8.3f}")
    out.append(f"largest {label} difference between engines over the run: position "
               f"{summary['max_point_position_difference']:.3e} m, "
               f"velocity {summary['max_point_velocity_difference']:.3e} m/s")
    who = scene.reference.removeprefix("the ")
    for name, c in summary["reference_acceleration_vs_engines"].items():
        out.append(f"{who} acceleration along {c.get('along', 'relacc')}'s trajectory vs {name}: {c['error']:.2e} "
                   f"(normalized, {c['error'] / EPS:.1f} eps; bound c eps kappa(M) = {c['bound']:.1e})"
                   + (f"; at its states' quaternions normalized (off unit by up to {c['quaternions_normalized']:.1e}"
                      ", its integrator's drift), as the engines read them" if c.get("quaternions_normalized") else ""))
    out.append("energy drift: max |E - E0| / max (T + |V_g| + V_s) over the run, where only conservative effects "
               "act; momentum drift: max |p - p0| (kg m/s) where no external force acts")
    out += scene_notes(scene)
    out.append(f"verdict: {result.verdict()}")
    return "\n".join(out)


def scene_notes(scene: Scene) -> list[str]:
    """One line per engine a model's default scene runs without, and per kind of element the run leaves out."""
    return ([f"left out: {name}: {why}" for name, why in scene.left_out]
            + [f"not evaluated: {line}" for line in scene.unevaluated])
