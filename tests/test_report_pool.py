"""The report's work shared with a second process (relacc.report.pool): the same results, in the same order, as on
one process; a job's exception carried back as raised."""

from __future__ import annotations

import math
import operator

import numpy as np
import pytest

from relacc.report import pool


def run_jobs(jobs, *, second, **kwargs):
    with pool.Processes(second) as processes:
        return processes.run(jobs, **kwargs)


def test_jobs_shared_with_a_second_process_come_back_in_the_lists_order():
    """Results in the list's order whichever process ran them (the second takes the most expensive first); the idle
    jobs run on this process (a list of this process is filled), only with a second one."""
    seen: list = []
    jobs = [*[pool.Job(f"pow {k}", pow, (2, k), cost=float(k % 4)) for k in range(9)],
            pool.Job("factorial", math.factorial, (20,), cost=9.0)]
    said: list = []
    got = run_jobs(jobs, second=True, progress=said.append, idle=[pool.Job("idle", seen.append, ("ran",))])
    assert got == [*[2 ** k for k in range(9)], 2432902008176640000]
    assert seen == ["ran"]
    assert said[0] == "10 jobs shared with a second process"
    assert run_jobs(jobs, second=False, idle=[pool.Job("idle", seen.append, ("again",))]) == got
    assert seen == ["ran"]


def test_a_job_that_fails_in_the_second_process_raises_as_it_raised():
    jobs = [pool.Job("fine", operator.add, (1, 2), cost=0.0), pool.Job("bad", int, ("not a number",), cost=5.0)]
    with pytest.raises(ValueError, match="not a number"):
        run_jobs(jobs, second=True)


@pytest.mark.slow
def test_the_report_is_the_same_on_one_process_and_two():
    """Every number the report judges is the same bits from one process and from two (the timings aside): the
    cross-validation, the hard cases, the Hypothesis search, the scenes' differences and acceleration checks, the
    integrator and derivative sweeps' errors; and the page drawn with the sections built early is the page built
    from the whole context, byte for byte."""
    from relacc.report.build import build_context

    one, two = (build_context(quick=True, second=s) for s in (False, True))
    assert [c.max_error for c in one.check.comparisons] == [c.max_error for c in two.check.comparisons]
    assert [(r.name, r.case, r.evaluator, r.quantity, r.max_error, r.max_bound) for r in one.hard] == \
        [(r.name, r.case, r.evaluator, r.quantity, r.max_error, r.max_bound) for r in two.hard]
    assert (one.worst.ratio, one.worst.q, one.worst.u) == (two.worst.ratio, two.worst.q, two.worst.u)
    for a, b in zip(one.simulations, two.simulations, strict=True):
        assert a["sweep"] == b["sweep"]
        assert a["result"].note_check == b["result"].note_check
        for name, tr in a["result"].trajectories.items():
            np.testing.assert_array_equal(tr.position, b["result"].trajectories[name].position)
    errors = [(r["scene"], r["engine"], r["integrator"], r["dt_or_tol"], r["error"]) for r in one.tradeoff.integrators]
    assert errors == [(r["scene"], r["engine"], r["integrator"], r["dt_or_tol"], r["error"])
                      for r in two.tradeoff.integrators]
    assert [(r["case"], r["method"], r["error"]) for r in one.tradeoff.derivatives] == \
        [(r["case"], r["method"], r["error"]) for r in two.tradeoff.derivatives]
    assert one.failures() == two.failures() == []
    # the sections drawn while the first process waited are what the page would have built from the whole context
    import dataclasses

    from relacc.report.build import render

    assert {"agreement", "errata", "throughput"} <= set(two.drawn) and one.drawn == {}
    assert render(two) == render(dataclasses.replace(two, drawn={}))


def test_the_estimate_is_the_expected_rest_scaled_by_how_the_phases_since_the_first_went():
    """Estimate on a clock the test sets: before the first phase ends, what is left is the expected rest (10 - done);
    once it has, the rest times (seconds spent since) / (expected seconds done since): here phases that took twice as
    long as expected double it, and the first phase's own time (a cold compile: 50 s for an expected 2) does not
    count."""
    now = [100.0]
    said: list = []
    est = pool.Estimate(said.append, first=2.0, rest=8.0, clock=lambda: now[0])
    est("start")
    now[0] = 150.0
    est.add(2.0)  # the first phase: 50 s, compiling
    est("benchmarks")
    now[0] = 158.0
    est.add(4.0)  # 4 s expected, 8 s spent
    est("jobs")
    assert said == ["start  [0 s; about 10 s left]", "benchmarks  [50 s; about 8 s left]",
                    "jobs  [58 s; about 8 s left]"]
    assert est.left() == 2 * (10.0 - 6.0)


def test_compiling_after_the_first_phase_does_not_stretch_the_estimate(monkeypatch):
    """Issue 52: a first report compiled the scenes' kernels after the first phase, and its estimate read "about 160 s
    left" with 20 s to go. Seconds spent compiling relacc's kernels in this process are left out of the pace: here a
    4 s phase took 24 s, 16 of them compiling, so the 4 s left are estimated at 4 * (24 - 16) / 4 = 8 s."""
    from relacc.kernels import jit

    now, compiling = [100.0], [0.0]
    monkeypatch.setattr(pool, "compiling_seconds", lambda: compiling[0])
    est = pool.Estimate(lambda text: None, first=2.0, rest=8.0, clock=lambda: now[0])
    now[0] = 110.0
    est.add(2.0)
    now[0], compiling[0] = 134.0, 16.0
    est.add(4.0)
    assert est.left() == 4.0 * (24.0 - 16.0) / 4.0
    assert pool.compiling_seconds is not jit.compiling_seconds  # the test's own count, not this process's


def test_every_job_that_ends_is_counted_once_on_either_process():
    """``finished`` sees each job once, whichever process ran it (the estimate adds each job's cost)."""
    jobs = [pool.Job(f"pow {k}", pow, (3, k), cost=float(k)) for k in range(7)]
    for second in (False, True):
        ended: list = []
        run_jobs(jobs, second=second, finished=lambda job: ended.append(job.label))
        assert sorted(ended) == sorted(j.label for j in jobs), second
