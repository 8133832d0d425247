"""Progress on stderr for the ``relacc`` commands: a bar that rewrites its line, and how to end that line.

Every message that follows a progress bar (an error, an interrupt) calls :func:`end_line` first, so that it
starts on a line of its own.
"""

from __future__ import annotations

import sys

OPEN = [False]
"""Whether a progress bar has left its line open on stderr."""


def end_line() -> None:
    """End an open progress bar's line on stderr, so that what follows starts on its own line."""
    if OPEN[0]:
        print(file=sys.stderr, flush=True)
        OPEN[0] = False


def bar(done: int, total: int) -> None:
    """A progress bar driven by finished cluster tasks."""
    print(f"\r  [{'#' * int(30 * done / total):30s}] {done}/{total} tasks", end="\n" if done == total else "",
          file=sys.stderr, flush=True)
    OPEN[0] = done != total


def line(label: str, fraction: float) -> None:
    """A progress bar of one run: ``label`` and the fraction done."""
    print(f"\r  {label:9s} [{'#' * int(30 * fraction):30s}] {100 * fraction:5.1f} %", end="", file=sys.stderr,
          flush=True)
    OPEN[0] = True


COMPILE_NOTICE = ("relacc: compiling its kernels for this machine (once: numba caches them beside the package for the "
                  "next run); this takes from about a minute on a quiet 2-core machine to several under load")
"""What the command line says when numba first compiles one of relacc's kernels in a process (issue 49: the first
``simulate --model`` after install compiled for 444 s at load 12, with no word)."""


NOTICE = {"listening": False, "said": False, "quiet": False}
"""The compile notice's state in this process: one listener, one notice (``main`` may run many times in a process)."""


def compile_notice(quiet: bool) -> None:
    """Say :data:`COMPILE_NOTICE` on stderr, once per process, when numba starts compiling one of relacc's kernels
    (a cached kernel is loaded, not compiled: nothing said). Nothing with ``quiet``, or without numba."""
    NOTICE["quiet"] = quiet
    if NOTICE["listening"]:
        return
    try:
        from numba.core import event
    except ImportError:  # pragma: no cover - numba is a dependency
        return

    class Notice(event.Listener):
        def on_start(self, ev) -> None:
            dispatcher = (ev.data or {}).get("dispatcher")
            module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
            if not NOTICE["said"] and not NOTICE["quiet"] and module.startswith("relacc."):
                NOTICE["said"] = True
                end_line()
                print(COMPILE_NOTICE, file=sys.stderr, flush=True)

        def on_end(self, ev) -> None:
            pass

    event.register("numba:compile", Notice())
    NOTICE["listening"] = True
