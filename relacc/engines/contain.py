"""An engine's C++ abort contained: a step run first in a forked child (:mod:`relacc.isolate`), so that an engine
that ends the process (``std::abort``, a failed assertion, a segmentation fault, ``exit``) ends only the child.

A :class:`Probe` says whether the step ends the process; the caller then runs the step itself, and its Python
exceptions are the caller's as usual. Several probes run at once. Where ``os.fork`` is missing, the step is not
probed.
"""

from __future__ import annotations

import time
from dataclasses import replace

from relacc import isolate
from relacc.errors import ModelError

PROBE_TIMEOUT = 600.0
"""Seconds a probe may take before it is stopped and the step is reported as not finishing."""


class Probe:
    """``step()`` started in a forked child whose output goes nowhere when made, judged by :meth:`survived` later: the
    engines' loads of one file probed at once, each judged before this process loads that engine itself. :meth:`stop`
    ends a probe that will not be judged (an interrupt)."""

    def __init__(self, what: str, step, timeout: float = PROBE_TIMEOUT):
        self.what, self.timeout = what, timeout
        self.deadline = time.monotonic() + timeout

        def probe():
            step()  # its value stays in the child (an engine's model does not travel); only how it ends matters

        self.child = isolate.Child(probe, isolate.pickled, "null") if isolate.FORKS else None

    def survived(self) -> None:
        """Return if the child ended by itself.

        Raises:
            ModelError: the child was ended by a signal or an exit of the engine's (``what``, how: one line) or did not
                finish in ``timeout`` seconds of the probe's start.
        """
        if self.child is None:
            return
        ended = self.child.wait(max(0.0, self.deadline - time.monotonic()))
        if isinstance(ended, isolate.Ended):
            if ended.timeout is not None:  # stopped at its deadline: the whole time it was given
                ended = replace(ended, timeout=self.timeout)
            how = ended.sentence()
            if ended.signal is not None:
                how += " (a C++ abort or crash, contained in a probe process)"
            raise ModelError(f"{self.what}: the engine {how}")

    def stop(self) -> None:
        if self.child is not None:
            self.child.stop()
