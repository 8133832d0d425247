"""An engine's C++ abort contained: a step run first in a forked child (:mod:`relacc.isolate`), so that an engine
that ends the process (``std::abort``, a failed assertion, a segmentation fault, ``exit``) ends only the child.

:func:`survives` is a probe: it says whether the step ends the process; the caller then runs the step itself, and
its Python exceptions are the caller's as usual. Where ``os.fork`` is missing, the step is not probed.
"""

from __future__ import annotations

from relacc import isolate
from relacc.errors import ModelError

PROBE_TIMEOUT = 600.0
"""Seconds a probe may take before it is stopped and the step is reported as not finishing."""


def survives(what: str, step, timeout: float = PROBE_TIMEOUT) -> None:
    """Run ``step()`` in a forked child whose output goes nowhere; return if the child ended by itself.

    Raises:
        ModelError: the child was ended by a signal or an exit of the engine's (``what``, how: one line) or did not
            finish in ``timeout`` seconds.
    """
    if not isolate.FORKS:
        return

    def probe():
        step()  # its value stays in the child (an engine's model does not travel); only how it ends matters

    ended = isolate.run(probe, output="null", timeout=timeout)
    if isinstance(ended, isolate.Ended):
        how = ended.sentence()
        if ended.signal is not None:
            how += " (a C++ abort or crash, contained in a probe process)"
        raise ModelError(f"{what}: the engine {how}")
