"""The report's untimed work on this process and, where the machine has a second core, one more.

A job is a function of picklable arguments (a scene's run, a scene's integrator sweep, the hard-case catalogue,
the Hypothesis search), so it gives the same result in either process. The jobs are ordered by their expected cost
(:attr:`Job.cost`); each process takes the next from the front (the largest first: a short job is left for the end,
when the other process finishes its own), until none is left, then this one runs the ``idle`` jobs while it waits.
Results come back in the list's order. With one core, or ``second=False``, every job runs here, in the list's order.
"""

from __future__ import annotations

import functools
import multiprocessing
import os
import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass, field
from typing import Any

from relacc.kernels.jit import compiling_seconds

QUEUED = 1
"""Jobs in the second process's queue: each one done hands it the next from the front (a callback of its future), so
that it never waits for this process to hand on the next, and none waits there that this process could take."""


@dataclass(frozen=True)
class Job:
    """``fn(*args)``, named ``label`` in the progress messages; ``cost``: its expected seconds (only their order
    matters: measured on this project's 2-core machine, docs/architecture.md)."""

    label: str
    fn: Callable[..., Any]
    args: tuple = ()
    cost: float = 0.0


@dataclass
class Estimate:
    """A run's progress messages with the time so far and an estimate of what is left: ``say(label)`` becomes
    ``say("label  [12 s; about 18 s left]")``.

    The run's expected seconds on this project's 2-core machine with its kernels compiled are ``first`` (the first
    phase: where kernels are compiled or loaded) and ``rest`` (the phases after it); ``done`` is the expected seconds
    of the phases finished so far (:meth:`add`). Until the first phase is done what is left is the expected rest of
    the run; after it, that rest scaled by how much longer or shorter the phases since took than expected, less the
    seconds this process spent compiling kernels (:func:`relacc.kernels.jit.compiling_seconds`), so that a slower or
    busier machine gets a longer estimate and a first run's compiling does not count against the rest."""

    say: Callable[[str], object]
    first: float
    rest: float
    done: float = 0.0
    clock: Callable[[], float] = time.perf_counter
    start: float = -1.0  # the clock when made (default)
    _calibrated: tuple[float, float, float] | None = None  # (time, done, compiling) when the first phase ended
    _lock: threading.Lock = field(default_factory=threading.Lock, repr=False)

    def __post_init__(self) -> None:
        if self.start < 0:
            self.start = self.clock()

    def add(self, seconds: float) -> None:
        """``seconds`` more of the expected work done (a phase, a job); thread-safe."""
        with self._lock:
            self.done += seconds
            if self._calibrated is None and self.done >= self.first - 1e-9:
                self._calibrated = (self.clock(), self.done, compiling_seconds())

    def drop(self, seconds: float) -> None:
        """``seconds`` of the expected rest that will not be run after all (done in the first phase); thread-safe."""
        with self._lock:
            self.rest -= seconds

    def left(self) -> float:
        """Seconds expected to be left."""
        with self._lock:
            rest, mark = max(self.first + self.rest - self.done, 0.0), self._calibrated
            if mark is None:
                return rest
            spent = self.clock() - mark[0] - (compiling_seconds() - mark[2])  # compiling this process's kernels
            expected = self.done - mark[1]                                 # is no measure of the rest
        return rest * (spent / expected) if expected > 0.5 else rest

    def __call__(self, label: str) -> None:
        elapsed = self.clock() - self.start
        self.say(f"{label}  [{elapsed:.0f} s; about {self.left():.0f} s left]")


def cores() -> int:
    """The CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


class Processes:
    """This process and, with ``second``, one spawned process (a fresh interpreter: no engine's threads or handles are
    forked), kept for every phase of a report: its imports and caches are paid once."""

    def __init__(self, second: bool):
        self.second = second
        self._pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> Processes:
        if self.second:
            self._pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn"))
        return self

    def __exit__(self, *exc: object) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)

    def submit(self, job: Job) -> Future | None:
        """Start ``job`` in the second process now; None without one (then nobody runs it)."""
        return None if self._pool is None else self._pool.submit(job.fn, *job.args)

    def run(self, jobs: Sequence[Job], *, progress: Callable[[str], object] | None = None,
            idle: Sequence[Job] = (), finished: Callable[[Job], object] | None = None) -> list:
        """Every job's result, in ``jobs``' order, on this process and the second one (the module docstring).
        ``idle``: jobs of this process alone, run once every other job is taken, and only with a second process
        (their results are not returned: they fill what their arguments hold, as the report's sections drawn
        early). ``finished(job)`` is called as each job ends, on either process (from another thread for the second
        process's: an :class:`Estimate`'s :meth:`Estimate.add` is thread-safe).

        Raises:
            whatever a job raises, as it raised it (a second process's exception is carried back).
        """
        say = progress or (lambda _: None)
        end = finished or (lambda _: None)
        results: list = [None] * len(jobs)
        pending = deque(enumerate(jobs))
        pool_ = self._pool
        if pool_ is None:
            for i, job in pending:
                say(job.label)
                results[i] = job.fn(*job.args)
                end(job)
            return results
        pending = deque(sorted(pending, key=lambda x: -x[1].cost))
        lock, stop = threading.Lock(), threading.Event()
        futures: dict[int, Future] = {}
        ended: set[int] = set()

        def once(i: int) -> None:  # a future's callbacks may still be running when its result is back
            with lock:
                first = i not in ended
                ended.add(i)
            if first:
                end(jobs[i])

        def feed(_: object = None) -> None:  # the next job from the front, as soon as one is done there
            with lock:
                if not pending or stop.is_set():
                    return
                i, job = pending.popleft()
                futures[i] = pool_.submit(job.fn, *job.args)
            futures[i].add_done_callback(functools.partial(lambda i, _: once(i), i))
            futures[i].add_done_callback(feed)

        say(f"{len(pending)} jobs shared with a second process")
        try:
            for _ in range(QUEUED):
                feed()
            while True:
                with lock:
                    if not pending:
                        break
                    i, job = pending.popleft()
                say(job.label)
                results[i] = job.fn(*job.args)
                end(job)
            for job in idle:
                job.fn(*job.args)
            with lock:
                running = dict(futures)
            for i, fut in running.items():
                results[i] = fut.result()
                once(i)
        except BaseException:
            stop.set()
            for fut in futures.values():
                fut.cancel()
            raise
        return results


__all__ = ["QUEUED", "Estimate", "Job", "Processes", "cores"]
