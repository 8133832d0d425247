"""The one step loop: every fixed-step run, relacc's and each engine's, goes through :func:`blocks`.

An integrator is a :class:`Stepper`: ``advance(x, v, k) -> (x, v)`` takes ``k``
steps of its own fixed ``dt`` from the state ``(x, v)`` (engine coordinates);
``record(x, v, gaps) -> (X, V, n)`` takes ``gaps[j]`` steps before storing
record ``j``, for a whole block of records at once (relacc's compiled
integrators do it in one call; the default loops over :meth:`Stepper.advance`).
:func:`blocks` owns what every run shares:

* the recording rule (:func:`recorded_steps`): step 0, every
  ``record_every``-th step, and always the last step, so the state at
  ``t = duration`` is recorded whatever ``record_every`` is;
* the divergence check: a non-finite state raises
  :class:`relacc.IntegrationError` naming the integrator, ``dt`` and the
  interval of time where it happened;
* progress: ``progress(fraction)`` after each block.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np

from relacc.errors import IntegrationError

BLOCK = 512
"""Records per block: a block is advanced, checked and handed on at once."""


class Stepper:
    """An integrator: ``advance(x, v, k)``, and ``record(x, v, gaps)`` (default: a loop over ``advance``); ``load()``
    readies what ``advance`` runs (a compiled stepper compiles its batch loops there the first time on a machine), so
    that a caller that times ``advance`` times the integration alone (default: nothing to ready)."""

    def __init__(self, advance: Callable, record: Callable | None = None, load: Callable | None = None):
        self.advance = advance
        self._record = record
        self._load = load

    def load(self) -> None:
        """Ready :meth:`advance` (see the class docstring)."""
        if self._load is not None:
            self._load()

    @property
    def records_blocks(self) -> bool:
        """Whether it records a block at once itself (a compiled loop, ``mujoco.rollout``) rather than step by
        step through :meth:`advance`."""
        return self._record is not None

    def record(self, x, v, gaps):
        """``(X, V, n)``: the states after ``gaps[0]``, ``gaps[0] + gaps[1]``, ... steps; ``n < len(gaps)`` when
        record ``n`` became non-finite (those before it are valid)."""
        if self._record is not None:
            return self._record(x, v, gaps)
        X, V = np.empty((len(gaps), np.size(x))), np.empty((len(gaps), np.size(v)))
        for j, k in enumerate(gaps):
            if k:
                x, v = self.advance(x, v, int(k))
            if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
                return X, V, j
            X[j], V[j] = x, v
        return X, V, len(gaps)


def recorded_steps(n_steps: int, record_every: int) -> np.ndarray:
    """Step indices recorded: ``0, e, 2e, ...`` and ``n_steps`` (the end), ascending, ``(m,)`` int."""
    steps = np.arange(0, n_steps + 1, record_every, dtype=np.int64)
    return steps if steps[-1] == n_steps else np.append(steps, n_steps)


def blocks(stepper: Stepper, x, v, steps, *, who: str, dt: float, integrator: str, progress=None,
           size: int = BLOCK) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Yield ``(steps_block, X, V)``: the states at the step indices ``steps`` (ascending, the first 0), a block
    of ``size`` records at a time.

    Raises:
        IntegrationError: the state became non-finite (or overflowed on the way); the message names ``who``,
            the interval of time and the step.
    """
    x, v = np.array(x, dtype=float), np.array(v, dtype=float)
    steps = np.asarray(steps, dtype=np.int64)
    n = int(steps[-1]) if len(steps) else 0
    done = 0
    for start in range(0, len(steps), size):
        chunk = steps[start:start + size]
        gaps = np.diff(np.concatenate([[done], chunk]))
        try:
            X, V, got = stepper.record(x, v, gaps)
        except IntegrationError as exc:
            raise IntegrationError(f"{who}: between t = {done * dt:.6g} s and t = {chunk[-1] * dt:.6g} s "
                                   f"(dt = {dt} s, {integrator}): {exc}") from None
        except (FloatingPointError, RuntimeWarning) as exc:  # an overflow on the way to a non-finite state
            raise IntegrationError(f"{who}: the integration diverged between t = {done * dt:.6g} s and "
                                   f"t = {chunk[-1] * dt:.6g} s (dt = {dt} s, {integrator}; {exc}); reduce the "
                                   "step") from None
        if got < len(chunk):
            before = int(chunk[got - 1]) if got else done
            raise IntegrationError(f"{who}: the integration diverged between t = {before * dt:.6g} s and "
                                   f"t = {int(chunk[got]) * dt:.6g} s (dt = {dt} s, {integrator}); reduce the step")
        x, v, done = X[-1], V[-1], int(chunk[-1])
        if progress and n:
            progress(done / n)
        yield chunk, X, V


def collect(stepper: Stepper, x, v, dt: float, n_steps: int, record_every: int, *, who: str, integrator: str,
            progress=None):
    """Run :func:`blocks` over :func:`recorded_steps` and keep every record.

    Returns:
        ``(t, X, V)``: times ``(m,)`` in s, states ``(m, nx)`` and ``(m, nv)``
        in the integrator's own coordinates, the initial state first and the
        state at ``n_steps dt`` last.
    """
    steps = recorded_steps(n_steps, record_every)
    parts = list(blocks(stepper, x, v, steps, who=who, dt=dt, integrator=integrator, progress=progress))
    return steps * dt, np.concatenate([p[1] for p in parts]), np.concatenate([p[2] for p in parts])
