"""An engine's C++ abort contained: a step run first in a forked child, so that an engine that ends the process
(``std::abort``, a failed assertion, a segmentation fault) ends only the child (engine-free, POSIX).

:func:`survives` is a probe: it says whether the step ends the process; the caller then runs the step itself, and
its Python exceptions are the caller's as usual. Where ``os.fork`` is missing, the step is not probed.
"""

from __future__ import annotations

import faulthandler
import os
import signal
import time

from relacc.errors import ModelError

PROBE_TIMEOUT = 600.0
"""Seconds a probe may take before it is stopped and the step is reported as not finishing."""


def survives(what: str, step, timeout: float = PROBE_TIMEOUT) -> None:
    """Run ``step()`` in a forked child whose output goes nowhere; return if the child ended by itself.

    Raises:
        ModelError: the child was ended by a signal (``what``, the signal's name: one line) or did not finish in
            ``timeout`` seconds.
    """
    if not hasattr(os, "fork"):
        return
    pid = os.fork()
    if pid == 0:  # the child: the step, then out without Python's exit handlers (they are the parent's)
        try:
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, 1)
            os.dup2(null, 2)
            faulthandler.disable()  # its report of the abort would go to the parent's stderr
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
            step()
        except BaseException:  # noqa: BLE001 - an exception is the parent's to see when it runs the step itself
            pass
        finally:
            os._exit(0)
    deadline = time.monotonic() + timeout
    try:
        while True:
            done, status = os.waitpid(pid, os.WNOHANG)
            if done:
                break
            if time.monotonic() > deadline:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                raise ModelError(f"{what}: did not finish in {timeout:g} s (stopped)")
            time.sleep(0.01)
    except BaseException:
        try:  # interrupted (SIGTERM, Ctrl-C): the child goes too
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
        except (ProcessLookupError, ChildProcessError):
            pass
        raise
    if os.WIFSIGNALED(status):
        sig = os.WTERMSIG(status)
        try:
            name = signal.Signals(sig).name
        except ValueError:  # a signal number Python has no name for
            name = f"signal {sig}"
        raise ModelError(f"{what}: the engine ended its process with {name} (a C++ abort or crash, contained in a "
                         "probe process)")
