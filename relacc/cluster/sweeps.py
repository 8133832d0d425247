"""The sweeps that run on a cluster: ``check``, ``compare`` over many models, ensembles.

Each splits the work the in-process run does into coarse tasks over the same chunks, so the answer
is the in-process answer:

* ``check``: a task is one case and a run of consecutive chunks of :data:`relacc.validation.check.CHUNK`
  states (at least :data:`CHECK_STATES` states, and at most :data:`MAX_TASKS` tasks in all); its answer
  is the merged :class:`relacc.validation.summary.Summary` of every comparison, per-state errors left
  on the worker unless the whole sweep is one chunk (then the exact median travels, as in-process);
* ``compare``: a task is one model (its states are one chunk); its answer is the comparison;
* ensembles: a task is a run of :data:`relacc.simulate.members.MEMBER_CHUNK` members on every
  engine; its answer is a :class:`relacc.simulate.members.Part`.
"""

from __future__ import annotations

import math

from relacc.cluster.client import connect, run
from relacc.cluster.plugin import cached
from relacc.fixtures.model import inline

CHECK_STATES = 100_000
"""Fewest states a ``check`` task evaluates (fewer only when the sweep is smaller)."""

MAX_TASKS = 10_000
"""Most tasks a sweep submits: beyond, tasks grow."""


def _merge_lists(a, b):
    return [x.merge(y) for x, y in zip(a, b)]


def _check_task(fixture, engines, n_states, seed, case, first, last, keep_errors):
    from relacc.validation.check import Harness

    harness = cached(("harness", fixture.digest, engines, n_states, seed),
                     lambda: Harness(fixture, engines=list(engines), n_states=n_states, seed=seed))
    merged: list = []
    for k in range(first, last):
        part = harness.check_chunk(case, k)
        merged = _merge_lists(merged, part) if merged else part
    if not keep_errors:
        from dataclasses import replace

        merged = [replace(s, errors=None) for s in merged]
    return merged


def check(address, harness, cases=(1, 2, 3), progress=None):
    """:meth:`relacc.validation.check.Harness.check` on a cluster: the same :class:`CheckReport`.

    The workers load the harness's chain (as an inline fixture: its engine files rendered there) and
    engines once each; the referee of a failed comparison runs here, on the worst state's chunk.
    """
    from relacc.validation.check import CHUNK, CheckReport
    from relacc.validation.referee import referee

    n_chunks = len(harness.chunks())
    per_task = max(math.ceil(CHECK_STATES / CHUNK), math.ceil(n_chunks * len(cases) / MAX_TASKS))
    fixture = inline(harness.fixture.name, harness.chain)
    engines = tuple(harness.engines)
    tasks = [(fixture, engines, harness.n_states, harness.seed, c, k, min(k + per_task, n_chunks), n_chunks == 1)
             for c in cases for k in range(0, n_chunks, per_task)]
    with connect(address) as client:
        per_case = run(client, _check_by_case, tasks, _merge_by_case, progress)
    summaries = [s for c in cases for s in per_case[c]]
    verdicts = tuple(referee(harness, s.case, s.quantity, s.route, s.worst_seed[2])
                     for s in summaries if not s.passed)
    return CheckReport(tuple(summaries), harness.n_states, harness.seed, harness.versions(), verdicts)


def _check_by_case(*task):
    return {task[4]: _check_task(*task)}


def _merge_by_case(a, b):
    out = dict(a)
    for case, summaries in b.items():
        out[case] = _merge_lists(out[case], summaries) if case in out else summaries
    return out


def _compare_task(model, urdf, engines, n_states, seed):
    from relacc.errors import RelaccError
    from relacc.validation.robots import compare

    try:
        return [(str(model), compare(model, urdf=urdf, engines=engines, n_states=n_states, seed=seed))]
    except RelaccError as exc:
        return [(str(model), exc)]


def compare_models(address, models, *, urdf=None, engines=None, n_states=20, seed=0, progress=None):
    """``[(model, RobotComparison or the RelaccError that stopped it)]`` in the order given, one task per model.

    Model files are read by the workers: on a remote cluster they must see the same paths.
    """
    with connect(address) as client:
        return run(client, _compare_task, [(m, urdf, engines, n_states, seed) for m in models],
                   lambda a, b: a + b, progress)


def _members_task(scene, start, n, spread, seed):
    from relacc.simulate.members import run_members

    return run_members(scene, start, n, spread, seed, threads=1)


def ensemble_members(address, scene, n, spread, seed, progress=None):
    """:func:`relacc.simulate.members.run_members` over ``n`` members on a cluster, one task per member chunk."""
    from relacc.simulate.members import MEMBER_CHUNK

    size = max(MEMBER_CHUNK, math.ceil(n / MAX_TASKS / MEMBER_CHUNK) * MEMBER_CHUNK)
    tasks = [(scene, start, min(size, n - start), spread, seed) for start in range(0, n, size)]
    with connect(address) as client:
        return run(client, _members_task, tasks, lambda a, b: a.merge(b), progress)
