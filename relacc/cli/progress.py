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


COMPILE_LABEL = "relacc: compiling its kernels for this machine, once (numba caches them for the next run)"
"""What the command line says while numba compiles one of relacc's kernels for the first time (issue 49: the first
``simulate --model`` after install compiled for 444 s at load 12, with no word; issue 52: a bar with an estimate)."""

COMPILE_RECORD = "compile-seconds"
"""The prefix of the recorded first compilations (``benchmarks/first_compile.py``, in ``relacc.recorded``): for each
command, the seconds numba took to compile each of relacc's kernels on a cold cache, on the machine it names."""


def recorded_compile_seconds(key: str) -> dict[str, float]:
    """Seconds each of relacc's kernels (``module.qualname``) took to compile on a cold cache for the command ``key``
    (:func:`compile_key`) in the latest recorded run; empty where that command was not recorded."""
    import json

    from relacc.fixtures.shipped import latest_recorded

    record = latest_recorded(COMPILE_RECORD)
    if record is None:
        return {}
    return dict(json.loads(record.read_text())["commands"].get(key, {}).get("kernels", {}))


def compile_key(command: str, model: object) -> str:
    """The key of a command's first compilation in the record: the command, and ``--model`` where it runs a model
    file (the tree's kernels) rather than the note's chain."""
    return f"{command} --model" if model else command


NOTICE: dict = {"listening": False, "quiet": False, "key": "", "compiled": set(), "depth": 0, "start": 0.0,
                "since": 0.0, "shown": False, "expected": None}
"""The compile bar's state in this process: one listener (``main`` may run many times in a process), the command's
recorded kernels (read at its first compilation), those compiled, the seconds spent compiling when the command began
and when its current outermost compilation began (:func:`relacc.kernels.jit.compiling_seconds`), and whether the
bar is shown."""


def _qualname(ev) -> str:
    fn = getattr((ev.data or {}).get("dispatcher"), "py_func", None)
    return f"{getattr(fn, '__module__', '') or ''}.{getattr(fn, '__qualname__', '')}"


def compile_bar(final: bool) -> str:
    """The compile bar's text: seconds so far and, from the record, about how many are left.

    The record's seconds for the kernels still expected are scaled by this run's pace (seconds taken over the
    record's seconds for the kernels compiled so far, once those are at least 2 s): a loaded machine gets a longer
    estimate as it goes. Without a record for the command, the seconds so far and the count of kernels."""
    from relacc.kernels.jit import compiling_seconds

    now = compiling_seconds() - NOTICE["start"]
    done = sum(NOTICE["expected"].get(name, 0.0) for name in NOTICE["compiled"])
    left = sum(v for name, v in NOTICE["expected"].items() if name not in NOTICE["compiled"])
    if not NOTICE["expected"]:
        return f"{COMPILE_LABEL}: {now:.0f} s, {len(NOTICE['compiled'])} kernels so far"
    pace = now / done if done >= 2.0 else 1.0
    if left * pace < 0.5:  # nothing left, or what is left rounds to no time
        return f"{COMPILE_LABEL}: compiled in {now:.0f} s"
    fraction = done / (done + left)
    if final:  # the outermost compilation has ended; the rest comes when the command needs those kernels
        return f"{COMPILE_LABEL} [{'#' * int(20 * fraction):20s}] {now:.0f} s so far, about {left * pace:.0f} s more"
    return f"{COMPILE_LABEL} [{'#' * int(20 * fraction):20s}] {now:.0f} s, about {left * pace:.0f} s left"


SHOWN_AFTER = 1.0
"""Seconds an outermost compilation takes before its bar is shown (the bar is updated as each kernel is compiled)."""


def compile_notice(quiet: bool, key: str = "") -> None:
    """A bar on stderr while numba compiles relacc's kernels in this process (a cached kernel is loaded, not compiled:
    nothing said), shown once an outermost compilation has taken :data:`SHOWN_AFTER` seconds, rewritten as each
    kernel is compiled and ended on its own line when that compilation ends. Nothing with ``quiet``, for numba
    compiling anything else, or without numba."""
    from relacc.kernels.jit import compiling_seconds

    NOTICE.update(quiet=quiet, key=key, compiled=set(), depth=0, start=compiling_seconds(), expected=None,
                  shown=False)
    if NOTICE["listening"]:
        return
    try:
        from numba.core import event
    except ImportError:  # pragma: no cover - numba is a dependency
        return

    class Bar(event.Listener):
        def on_start(self, ev) -> None:
            if NOTICE["quiet"] or not _qualname(ev).startswith("relacc."):
                return
            if NOTICE["depth"] == 0:
                if NOTICE["expected"] is None:  # the command's first compilation
                    NOTICE["expected"] = recorded_compile_seconds(NOTICE["key"])
                NOTICE["since"], NOTICE["shown"] = compiling_seconds(), False
            NOTICE["depth"] += 1

        def on_end(self, ev) -> None:
            if NOTICE["quiet"] or not _qualname(ev).startswith("relacc."):
                return
            NOTICE["compiled"].add(_qualname(ev))
            NOTICE["depth"] -= 1
            if not NOTICE["shown"] and compiling_seconds() - NOTICE["since"] >= SHOWN_AFTER:
                end_line()  # a run's bar, which this compilation interrupts
                NOTICE["shown"] = True
            if NOTICE["shown"]:
                _rewrite(compile_bar(final=NOTICE["depth"] == 0))
            if NOTICE["depth"] == 0 and NOTICE["shown"]:
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
