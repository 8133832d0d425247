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
