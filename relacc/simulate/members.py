"""An ensemble's members and what it reports, chunk by chunk: the same answer in one process or on a cluster.

Members come in chunks of :data:`MEMBER_CHUNK`: chunk ``j`` is drawn from
``numpy.random.default_rng([seed, j])``, never from one shared stream, so any range of members can be
made, and run, alone (:func:`perturbed`). :func:`run_members` runs a range on every engine and keeps
the small answer (:class:`Part`): each engine's steps and integration seconds, and per member the
largest G2 position difference over the run between each pair of engines. Parts of consecutive
ranges merge (:meth:`Part.merge`); :meth:`Part.summary` is ``relacc simulate --ensemble``'s report.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from relacc.core.cases import Case, check_int
from relacc.core.rotations import quaternion_exp, quaternion_multiply
from relacc.errors import EngineError
from relacc.simulate.scenes import Scene

MEMBER_CHUNK = 1024
"""Members per random chunk (and the granularity of a cluster's ensemble tasks)."""


def perturbed(scene: Scene, n: int, spread: float, seed: int, start: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``(q0 (n, nq), u0 (n, nv))``: members ``start .. start + n - 1`` of the scene's ensemble.

    Member 0 is the scene's own state. The others: positions and angles plus ``spread`` times
    standard normals (m, rad), quaternions turned by rotation vectors of that size (they stay unit),
    speeds plus ``spread`` times standard normals (m/s, rad/s); member ``i`` comes from chunk
    ``i // MEMBER_CHUNK``, drawn from ``numpy.random.default_rng([seed, chunk])``.
    """
    n = check_int("ensemble size", n, minimum=1)
    start = check_int("first member", start, minimum=0)
    if not (isinstance(spread, (int, float)) and not isinstance(spread, bool) and np.isfinite(spread)
            and spread >= 0):
        raise EngineError(f"spread: expected a finite number >= 0, got {spread!r}")
    qs, us = [], []
    for j in range(start // MEMBER_CHUNK, (start + n - 1) // MEMBER_CHUNK + 1):
        q, u = _chunk(scene, j, float(spread), seed)
        lo, hi = max(start - j * MEMBER_CHUNK, 0), min(start + n - j * MEMBER_CHUNK, MEMBER_CHUNK)
        qs.append(q[lo:hi])
        us.append(u[lo:hi])
    return np.concatenate(qs), np.concatenate(us)


def _chunk(scene, j, spread, seed):
    """Chunk ``j``: every coordinate plus ``spread`` normals, quaternions (cases 1-2) turned by rotation
    vectors of that size, speeds plus ``spread`` normals."""
    from relacc.core.tree.coordinates import rotations

    rng = np.random.default_rng([seed, j])
    m = MEMBER_CHUNK
    q0 = np.repeat(scene.q[None].astype(float), m, axis=0)
    u0 = np.repeat(scene.u[None].astype(float), m, axis=0)
    quats = [a for _, _, a, _ in rotations(scene.subject_tree, scene.case)] if scene.case != Case.ANGLE_RATES else []
    plain = np.ones(q0.shape[1], dtype=bool)
    for a in quats:
        plain[a:a + 4] = False
        q0[:, a:a + 4] = quaternion_multiply(q0[:, a:a + 4], quaternion_exp(spread * rng.normal(size=(m, 3))))
    q0[:, plain] += spread * rng.normal(size=(m, int(plain.sum())))
    u0 += spread * rng.normal(size=u0.shape)
    if j == 0:
        q0[0], u0[0] = scene.q, scene.u
    return q0, u0


def largest_differences(runs: dict) -> dict:
    """``{"a-b": (N,) largest G2 position difference over the run per member, m}`` for every pair of engines."""
    names = list(runs)
    return {f"{a}-{b}": np.max(np.linalg.norm(runs[a].position - runs[b].position, axis=2), axis=1)
            for i, a in enumerate(names) for b in names[i + 1:]}


@dataclass(frozen=True)
class Part:
    """What a range of members leaves: ``start``, ``n``; per engine ``steps`` and integration ``seconds``
    (and ``threads``); per pair of engines the members' largest G2 position differences (m)."""

    start: int
    n: int
    steps: dict
    seconds: dict
    threads: dict
    differences: dict = field(repr=False)

    def merge(self, other: "Part") -> "Part":
        """The part of both ranges (consecutive: ``other`` starts where this one ends)."""
        if other.start != self.start + self.n:
            raise EngineError(f"ensemble parts must be consecutive: {self.start}+{self.n} then {other.start}")
        return Part(self.start, self.n + other.n, {k: v + other.steps[k] for k, v in self.steps.items()},
                    {k: v + other.seconds[k] for k, v in self.seconds.items()}, dict(self.threads),
                    {k: np.concatenate([v, other.differences[k]]) for k, v in self.differences.items()})

    def summary(self, scene: Scene, spread: float, seed: int) -> dict:
        """Plain data: steps per second per engine (over the seconds its integrations took) and the differences."""
        return {"scene": scene.name, "members": self.n, "spread": spread, "seed": seed, "steps": scene.n_steps,
                "dt": scene.dt,
                "engines": {k: {"steps_per_second": self.steps[k] / self.seconds[k] if self.seconds[k] > 0
                                else float("inf"), "seconds": self.seconds[k], "threads": self.threads[k]}
                            for k in self.steps},
                "point": scene.observe,
                "largest_point_position_difference": {
                    k: {"max": float(v.max()), "median": float(np.median(v)), "worst_member": int(np.argmax(v))}
                    for k, v in self.differences.items()}}


def acceleration_check(scene: Scene, n: int, spread: float, seed: int) -> dict:
    """``{engine: {"error", "bound"}}``: relacc's acceleration of the scene's point against each engine's at the
    initial states of the ensemble's first members (at most :data:`relacc.simulate.runs.NOTE_CHECK_STATES`), as
    :func:`relacc.simulate.subjects.note_check` judges a single run: the verdict of ``relacc simulate --ensemble``."""
    from relacc.simulate import subjects
    from relacc.simulate.runs import NOTE_CHECK_STATES

    q0, u0 = perturbed(scene, min(int(n), NOTE_CHECK_STATES), spread, seed)
    engines = {name: subjects.adapter(scene, name) for name in scene.engines if name != "relacc"}
    if not engines:
        return {}
    return subjects.note_check(scene, [(q0[i], u0[i], 0.0) for i in range(len(q0))], engines)


def run_members(scene: Scene, start: int, n: int, spread: float, seed: int, threads: int | None = None,
                progress=None) -> Part:
    """Members ``start .. start + n - 1`` on every engine of the scene (:func:`relacc.simulate.ensemble.ensemble`)."""
    from relacc.simulate.ensemble import ensemble, require_ensemble_memory

    require_ensemble_memory(scene, n)  # before the members are drawn
    q0, u0 = perturbed(scene, n, spread, seed, start)
    runs = {}
    for name in scene.engines:
        if progress is not None:
            progress(name)
        runs[name] = ensemble(scene, q0, u0, engine=name, threads=threads)
    return Part(start, n, {k: r.steps for k, r in runs.items()}, {k: r.seconds for k, r in runs.items()},
                {k: r.threads for k, r in runs.items()}, largest_differences(runs))
