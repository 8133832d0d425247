"""The worker plugin: relacc's kernels loaded once per worker, and a per-worker cache for what tasks load."""

from __future__ import annotations

from distributed import WorkerPlugin, get_worker


class RelaccPlugin(WorkerPlugin):
    """Registered on every worker by :func:`relacc.cluster.connect`.

    ``setup`` pins numba to the worker's one thread and compiles (or loads from numba's cache) the
    kinematics and dynamics kernels; ``cache`` holds engines and harnesses by key for the worker's
    lifetime, so tasks pickle only their arguments.
    """

    name = "relacc"

    def __init__(self):
        self.cache: dict = {}

    def setup(self, worker):
        import numpy as np

        import relacc
        from relacc.core.states import random_states
        from relacc.dynamics import accelerations
        from relacc.kernels.jit import numba

        if numba is not None:
            numba.set_num_threads(1)  # one task per worker thread: parallelism comes from the workers
        s = random_states(1, 4, [0])
        relacc.g2_kinematics(relacc.TwoBodyChain(q2=np.zeros(3), r2=np.zeros(3)), 1, s.q, s.u, s.udot)
        accelerations(relacc.TwoBodyChain(q2=np.zeros(3), r2=np.zeros(3)), 1, s.q, s.u)


def cached(key, make):
    """The worker's cached value for ``key``, made by ``make()`` the first time (in-process: made every time)."""
    try:
        plugin = get_worker().plugins[RelaccPlugin.name]
        cache = plugin.cache  # type: ignore[attr-defined]  # a RelaccPlugin, registered under its name
    except (ValueError, KeyError):
        return make()
    if key not in cache:
        cache[key] = make()
    return cache[key]
