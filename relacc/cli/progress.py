"""Progress on stderr for the ``relacc`` commands: a bar that rewrites its line, and how to end that line.

Every message that follows a progress bar (an error, an interrupt) calls :func:`end_line` first, so that it
starts on a line of its own.
"""

from __future__ import annotations

import functools
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


COMPILE_LABEL = "relacc: compiling its kernels for this machine, once (numba caches them for the next run)"
"""What the command line says while numba compiles one of relacc's kernels for the first time (issue 49: the first
``simulate --model`` after install compiled for 444 s at load 12, with no word; issue 52: a bar with an estimate)."""

COMPILE_RECORD = "compile-seconds"
"""The prefix of the recorded first compilations (``benchmarks/first_compile.py``, in ``relacc.recorded``): for each
outermost kernel numba compiles (a root: the kernel a command calls), the seconds each kernel compiled under it took
on a cold cache, on the machine the record names."""


def recorded_compile_seconds(root: str) -> dict[str, float]:
    """Seconds each kernel (``module.qualname``) compiled under the outermost kernel ``root`` took on a cold cache in
    the latest recorded run; empty where that kernel was not recorded, or where the record cannot be read (the bar
    then shows the seconds so far and the count of kernels: an estimate is never worth a failed command)."""
    return dict(_compile_record().get(root, {}))


@functools.cache
def _compile_record() -> dict:
    """The latest record's roots (:data:`COMPILE_RECORD`), read once per process."""
    import json

    from relacc.fixtures.shipped import latest_recorded

    record = latest_recorded(COMPILE_RECORD)
    try:
        return dict(json.loads(record.read_text())["roots"]) if record is not None else {}
    except (OSError, ValueError, KeyError, TypeError):
        return {}


NOTICE: dict = {"listening": False, "quiet": False, "compiled": set(), "since": 0.0, "shown": False, "expected": {},
                "waited": False}
"""The compile bar's state in this process: one listener (``main`` may run many times in a process); for the
outermost compilation under way (how deep numba is in it: :data:`relacc.kernels.jit.COMPILING`), the kernels
compiled under it, the record's seconds for them, the compiling seconds when it began
(:func:`relacc.kernels.jit.compiling_seconds`), whether its bar is shown, and whether it waited for another
process."""


def compile_bar() -> str:
    """The compile bar's text for the outermost compilation under way: its seconds so far and, from the record, about
    how many are left.

    The record's seconds for the kernels still expected under it are scaled by this run's pace (seconds taken over
    the record's seconds for the kernels compiled so far, once those are at least 2 s): a loaded machine gets a longer
    estimate as it goes. Without a record of it, the seconds so far and the count of kernels."""
    from relacc.kernels.jit import COMPILING, compiling_seconds

    now = compiling_seconds() - NOTICE["since"]
    done = sum(NOTICE["expected"].get(name, 0.0) for name in NOTICE["compiled"])
    left = sum(v for name, v in NOTICE["expected"].items() if name not in NOTICE["compiled"])
    if COMPILING["depth"] == 0:
        return f"{COMPILE_LABEL}: {'ready' if NOTICE['waited'] else 'compiled'} in {now:.0f} s"
    if not NOTICE["expected"]:
        return f"{COMPILE_LABEL}: {now:.0f} s, {len(NOTICE['compiled'])} kernels so far"
    pace = now / done if done >= 2.0 else 1.0
    fraction = done / (done + left)
    return f"{COMPILE_LABEL} [{'#' * int(20 * fraction):20s}] {now:.0f} s, about {left * pace:.0f} s left"


SHOWN_AFTER = 1.0
"""Seconds an outermost compilation takes before its bar is shown (the bar is updated as each kernel is compiled)."""


def compile_notice(quiet: bool) -> None:
    """A bar on stderr while numba compiles relacc's kernels in this process (a cached kernel is loaded, not compiled:
    nothing said), shown once an outermost compilation has taken :data:`SHOWN_AFTER` seconds, rewritten as each
    kernel is compiled, and ended on its own line ("compiled in N s") when that compilation ends; a wait for another
    process compiling the same kernel (:mod:`relacc.kernels.jit`'s lock) is said when it begins, and the line then
    ends "ready in N s". Nothing with
    ``quiet``, for numba compiling anything else, or without numba."""
    NOTICE.update(quiet=quiet, shown=False)
    if NOTICE["listening"]:
        return
    try:
        from numba.core import event
    except ImportError:  # pragma: no cover - numba is a dependency
        return
    from relacc.kernels.jit import COMPILING, compiling_seconds, kernel_name

    class Bar(event.Listener):  # called after jit's counter (registered first): COMPILING is up to date here
        def on_start(self, ev) -> None:
            if NOTICE["quiet"] or not kernel_name(ev).startswith("relacc."):
                return
            if COMPILING["depth"] == 1:  # an outermost compilation begins
                NOTICE.update(expected=recorded_compile_seconds(kernel_name(ev)), compiled=set(),
                              since=compiling_seconds(), shown=False, waited=False)
            if (ev.data or {}).get("waiting"):  # another process compiles this kernel (kernels/jit's lock): said now,
                end_line()                      # as nothing else happens here until it has
                NOTICE.update(shown=True, waited=True)
                _rewrite(f"{COMPILE_LABEL}: waiting for another relacc process compiling "
                         f"{kernel_name(ev).rsplit('.', 1)[-1]} (it is cached for both)")

        def on_end(self, ev) -> None:
            if NOTICE["quiet"] or not kernel_name(ev).startswith("relacc."):
                return
            NOTICE["compiled"].add(kernel_name(ev))
            if not NOTICE["shown"] and compiling_seconds() - NOTICE["since"] >= SHOWN_AFTER:
                end_line()  # a run's bar, which this compilation interrupts
                NOTICE["shown"] = True
            if NOTICE["shown"]:
                _rewrite(compile_bar())
                if COMPILING["depth"] == 0:
                    end_line()

    event.register("numba:compile", Bar())
    NOTICE["listening"] = True


def _rewrite(text: str) -> None:
    """Rewrite the open line with ``text`` (padded over a longer text written before)."""
    width = max(len(text), WIDTH[0]) if OPEN[0] else len(text)
    print(f"\r{text:{width}s}", end="", file=sys.stderr, flush=True)
    WIDTH[0] = len(text)
    OPEN[0] = True


WIDTH = [0]
"""The length of the text on the open line."""
