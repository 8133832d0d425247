"""The one step loop: every fixed-step run, relacc's and each engine's, goes through :func:`march`.

An integrator is an *advance* function ``advance(x, v, k) -> (x, v)`` that
takes ``k`` steps of its own fixed ``dt`` from the state ``(x, v)`` (engine
coordinates). :func:`march` owns what every run shares:

* the recording rule (:func:`recorded_steps`): step 0, every
  ``record_every``-th step, and always the last step, so the state at
  ``t = duration`` is recorded whatever ``record_every`` is;
* the divergence check: a non-finite state raises
  :class:`relacc.IntegrationError` naming the integrator, ``dt`` and the
  interval of time where it happened;
* progress: ``progress(fraction)`` after each advance that takes the run past
  another 1/200th of its steps.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np

from relacc.errors import IntegrationError

Advance = Callable[[np.ndarray, np.ndarray, int], tuple]


def recorded_steps(n_steps: int, record_every: int) -> np.ndarray:
    """Step indices recorded: ``0, e, 2e, ...`` and ``n_steps`` (the end), ascending, ``(m,)`` int."""
    steps = np.arange(0, n_steps + 1, record_every, dtype=np.int64)
    return steps if steps[-1] == n_steps else np.append(steps, n_steps)


def march(advance: Advance, x, v, steps, *, who: str, dt: float, integrator: str,
          progress=None) -> Iterator[tuple[int, np.ndarray, np.ndarray]]:
    """Yield ``(k, x, v)`` at each step index of ``steps`` (ascending, the first 0), advancing between them.

    Raises:
        IntegrationError: the state became non-finite; the message names
            ``who``, the interval of time and the step.
    """
    x, v = np.array(x, dtype=float), np.array(v, dtype=float)
    n = int(steps[-1]) if len(steps) else 0
    done, shown = 0, 0
    for k in steps:
        k = int(k)
        if k > done:
            try:
                x, v = advance(x, v, k - done)
            except IntegrationError as exc:
                raise IntegrationError(f"{who}: between t = {done * dt:.6g} s and t = {k * dt:.6g} s "
                                       f"(dt = {dt} s, {integrator}): {exc}") from None
            if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
                raise IntegrationError(
                    f"{who}: the integration diverged between t = {done * dt:.6g} s and t = {k * dt:.6g} s "
                    f"(dt = {dt} s, {integrator}); reduce the step")
            done = k
            if progress and n and (200 * done) // n > shown:
                shown = (200 * done) // n
                progress(done / n)
        yield k, x, v


def collect(advance: Advance, x, v, dt: float, n_steps: int, record_every: int, *, who: str, integrator: str,
            progress=None):
    """Run :func:`march` over :func:`recorded_steps` and keep every record.

    Returns:
        ``(t, X, V)``: times ``(m,)`` in s, states ``(m, nx)`` and ``(m, nv)``
        in the integrator's own coordinates, the initial state first and the
        state at ``n_steps dt`` last.
    """
    steps = recorded_steps(n_steps, record_every)
    x, v = np.asarray(x, dtype=float), np.asarray(v, dtype=float)
    X, V = np.empty((len(steps), x.size)), np.empty((len(steps), v.size))
    for j, (_, xk, vk) in enumerate(march(advance, x, v, steps, who=who, dt=dt, integrator=integrator,
                                         progress=progress)):
        X[j], V[j] = xk, vk
    return steps * dt, X, V
