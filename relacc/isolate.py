"""A step run in a forked child process, its result brought back by value (engine-free, POSIX).

Two uses of a forked child, one mechanism (and :func:`captured_output` for C code that writes to stderr or stdout
in this process):

* an engine's C++ abort contained (:class:`relacc.engines.contain.Probe`): the child's output goes nowhere and
  only how it ended matters;
* a user's own code run apart from relacc's (``relacc grade``): whatever it does to the objects it is given, to the
  process (``os._exit``, a signal) or to file descriptor 1 (``os.write(1, ...)``, which would corrupt ``--json``)
  stays in the child, and its output goes to stderr. Its result comes back as plain data only (:func:`run_plain`:
  a JSON header and numeric arrays in numpy's ``.npy`` format, read with ``allow_pickle=False``): nothing the child
  sends can run code in this process, whatever the user's code did to the child's own relacc.

Where ``os.fork`` is missing, :func:`run` calls the step in this process (:data:`FORKS` says which).
"""

from __future__ import annotations

import contextlib
import ctypes
import faulthandler
import io
import json
import os
import pickle
import select
import signal
import sys
import tempfile
import time
from dataclasses import dataclass

import numpy as np

FORKS = hasattr(os, "fork")
"""Whether steps run in a child process here."""


@dataclass(frozen=True)
class Ended:
    """How a child that returned no result ended: ``signal`` (its name) or ``status`` (its exit status), or
    ``timeout`` (it was stopped after that many seconds)."""

    signal: str | None = None
    status: int | None = None
    timeout: float | None = None
    garbled: str | None = None
    """What was wrong with a result that is not plain data (:func:`run_plain`)."""

    def sentence(self) -> str:
        if self.garbled is not None:
            return f"sent back something that is not plain numbers ({self.garbled[:200]})"
        if self.timeout is not None:
            return f"did not finish in {self.timeout:g} s (stopped)"
        if self.signal is not None:
            return f"ended its process with {self.signal}"
        return f"ended its process (exit status {self.status}) without returning"


@dataclass(frozen=True)
class Raised:
    """An exception the step raised in the child: its type's name and its message's first line."""

    type: str
    message: str


def signal_name(sig: int) -> str:
    try:
        return signal.Signals(sig).name
    except ValueError:  # a number Python has no name for
        return f"signal {sig}"


def run(step, *, output: str = "stderr", timeout: float | None = None):
    """``step()`` in a forked child; returns its return value, or a :class:`Raised` or an :class:`Ended`.

    ``output``: where the child's stdout and stderr go, ``"stderr"`` (both to this process' stderr) or ``"null"``.
    The return value must pickle, and is unpickled here: for relacc's own steps only (an engine's probe). A user's
    code runs through :func:`run_plain`. An interrupt of this process (SIGINT, SIGTERM raised as KeyboardInterrupt)
    kills the child and propagates.
    """
    if not FORKS:
        try:
            return step()
        except Exception as exc:  # noqa: BLE001 - the caller reports the step's failure
            return _raised(exc)

    got = _forked(step, pickled, output, timeout)
    if isinstance(got, Ended):
        return got
    _, value = pickle.loads(got)  # ("value", the step's value) or ("raised", a Raised)
    return value


def pickled(payload) -> bytes:
    """A child's ``("value", v)`` or ``("raised", Raised)`` for :func:`run`, pickled; a value that cannot travel is
    the step's failure."""
    try:
        return pickle.dumps(payload, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception as exc:  # noqa: BLE001 - a result that cannot travel is the step's failure
        return pickle.dumps(("raised", Raised(type(exc).__name__, f"its result cannot be pickled: {exc}")))


RAISED = "isolate.raised"
"""The header key of :func:`run_plain`'s own report of an exception the step raised."""

PLAIN_HEADER_BYTES = 1 << 16
"""The largest JSON header :func:`run_plain` accepts from a child."""


def run_plain(step, *, output: str = "stderr", timeout: float | None = None):
    """``step()`` in a forked child whose code is not relacc's to trust (a user's module, imported there and only
    there); ``step`` returns ``(header, arrays)``: a JSON-serializable ``header`` (dict) and a list of numpy arrays.

    Returns ``(header, arrays)`` decoded here as plain data (the header by ``json.loads``, each array by numpy's
    ``.npy`` reader with ``allow_pickle=False``: an object array is refused), or a :class:`Raised` (the step raised)
    or an :class:`Ended` (the child ended, was stopped after ``timeout`` seconds, or sent something that is not
    plain data: ``Ended.status`` then says so). Where ``os.fork`` is missing the step runs here.
    """
    if not FORKS:
        try:
            return step()
        except Exception as exc:  # noqa: BLE001 - the caller reports the step's failure
            return _raised(exc)

    def encode(payload) -> bytes:
        kind, value = payload
        if kind == "raised":
            return _plain({RAISED: [value.type, value.message]}, [])
        try:
            header, arrays = value
            return _plain(dict(header), [np.asarray(a) for a in arrays])
        except Exception as exc:  # noqa: BLE001 - a result that is not plain data is the step's failure
            return _plain({RAISED: [type(exc).__name__, f"its result is not plain data: {exc}"]}, [])

    got = _forked(step, encode, output, timeout)
    if isinstance(got, Ended):
        return got
    try:
        header, arrays = _unplain(got)
    except (ValueError, TypeError, KeyError, OSError, EOFError) as exc:
        return Ended(status=0, garbled=f"{type(exc).__name__}: {exc}")
    if RAISED in header:
        try:
            kind, message = header[RAISED]
        except (TypeError, ValueError):
            return Ended(status=0, garbled="an exception without a type and a message")
        return Raised(str(kind)[:200], str(message)[:1000])
    return header, arrays


def _plain(header: dict, arrays: list) -> bytes:
    """``header`` as JSON (its length first, 8 bytes little-endian), then each array in ``.npy`` format."""
    out = io.BytesIO()
    head = json.dumps({**header, "arrays": len(arrays)}).encode()
    out.write(len(head).to_bytes(8, "little"))
    out.write(head)
    for a in arrays:
        if a.dtype.hasobject:
            raise TypeError(f"an array of {a.dtype} objects is not plain data")
        np.lib.format.write_array(out, a, allow_pickle=False)
    return out.getvalue()


def _unplain(data: bytes) -> tuple[dict, list]:
    """The inverse of :func:`_plain`, trusting nothing: a header over :data:`PLAIN_HEADER_BYTES`, JSON that is not an
    object, a count of arrays that does not match, an object array or trailing bytes raise ``ValueError``."""
    stream = io.BytesIO(data)
    size = int.from_bytes(stream.read(8), "little")
    if not 0 < size <= PLAIN_HEADER_BYTES:
        raise ValueError(f"a header of {size} bytes")
    header = json.loads(stream.read(size).decode("utf-8"))
    if not isinstance(header, dict) or not isinstance(header.get("arrays"), int):
        raise ValueError("the header is not a JSON object with its count of arrays")
    arrays = [np.lib.format.read_array(stream, allow_pickle=False) for _ in range(header.pop("arrays"))]
    if stream.read(1):
        raise ValueError("bytes after the last array")
    return header, arrays


def _forked(step, encode, output: str, timeout: float | None):
    """The mechanism of :func:`run` and :func:`run_plain`: ``step()`` in a forked child, whose
    ``("value", v)`` or ``("raised", Raised)`` is ``encode``-d to bytes and sent through a pipe; returns those bytes,
    or an :class:`Ended`."""
    return Child(step, encode, output).wait(timeout)


class Child:
    """``step()`` started in a forked child when made; :meth:`wait` collects what it sent (:func:`_forked`), so that
    several children can run while this process does other work (:class:`relacc.engines.contain.Probe`)."""

    def __init__(self, step, encode, output: str):
        self.reader, writer = os.pipe()
        self.pid = os.fork()
        if self.pid == 0:  # the child: the step, then out without Python's exit handlers (they are the parent's)
            code = 0
            try:
                os.close(self.reader)
                faulthandler.disable()  # its report of a crash would be the parent's news
                signal.signal(signal.SIGINT, signal.SIG_DFL)
                signal.signal(signal.SIGTERM, signal.SIG_DFL)
                target = os.open(os.devnull, os.O_WRONLY) if output == "null" else 2
                os.dup2(target, 1)
                os.dup2(target, 2)
                try:
                    payload = ("value", step())
                except BaseException as exc:  # noqa: BLE001 - GeneratorExit, KeyboardInterrupt, SystemExit: the step's
                    payload = ("raised", _raised(exc))
                view = memoryview(encode(payload))
                while view:
                    view = view[os.write(writer, view):]
            except BaseException:  # noqa: BLE001
                code = 70
            finally:
                os._exit(code)
        os.close(writer)

    def wait(self, timeout: float | None = None):
        """The bytes the child sent, or an :class:`Ended`; ``timeout`` seconds from now at most (then the child is
        stopped). An interrupt of this process kills the child and propagates."""
        chunks, deadline = [], None if timeout is None else time.monotonic() + timeout
        try:
            while True:
                wait = 0.05 if deadline is None else max(0.0, min(0.05, deadline - time.monotonic()))
                ready, _, _ = select.select([self.reader], [], [], wait)
                if ready:
                    chunk = os.read(self.reader, 1 << 20)
                    if not chunk:
                        break
                    chunks.append(chunk)
                elif deadline is not None and time.monotonic() >= deadline:
                    _kill(self.pid)
                    return Ended(timeout=timeout)
            _, status = os.waitpid(self.pid, 0)
        except BaseException:
            _kill(self.pid)  # interrupted (SIGTERM, Ctrl-C): the child goes too
            raise
        finally:
            os.close(self.reader)
            self.reader = -1  # collected: nothing left to stop
        if chunks and os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0:
            return b"".join(chunks)
        if os.WIFSIGNALED(status):
            return Ended(signal=signal_name(os.WTERMSIG(status)))
        return Ended(status=os.WEXITSTATUS(status))

    def stop(self) -> None:
        """The child killed and its pipe closed, unless already collected."""
        if self.reader >= 0:
            with contextlib.suppress(OSError):
                os.close(self.reader)
            self.reader = -1
            _kill(self.pid)


def _raised(exc: BaseException) -> Raised:
    text = str(exc)
    return Raised(type(exc).__name__, text.splitlines()[0] if text else "")


def _kill(pid: int) -> None:
    try:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
    except (ProcessLookupError, ChildProcessError):
        pass


@contextlib.contextmanager
def captured_output(stdout: bool = False):
    """Inside the block, what C and C++ code writes to file descriptor 2 (a parser's own error lines, which no Python
    handler sees), and with ``stdout`` to descriptor 1 too (Pinocchio's MJCF parser prints its warnings with
    ``std::cout``, which would land in a ``--json`` document), goes to a temporary file; the list yielded receives its
    lines (stripped, non-empty) at the end, for the caller to say in its own words. Python's streams and C's
    ``stdio`` buffers are flushed before and after."""
    fds = (1, 2) if stdout else (2,)
    _flush_all()
    lines: list[str] = []
    saved = [os.dup(fd) for fd in fds]
    with tempfile.TemporaryFile() as sink:
        for fd in fds:
            os.dup2(sink.fileno(), fd)
        try:
            yield lines
        finally:
            _flush_all()
            for fd, kept in zip(fds, saved):
                os.dup2(kept, fd)
                os.close(kept)
            sink.seek(0)
            lines.extend(x.strip() for x in sink.read().decode("utf-8", "replace").splitlines() if x.strip())


def _flush_all() -> None:
    """Python's ``sys.stdout`` and ``sys.stderr``, and every C ``stdio`` stream (``fflush(NULL)``, where libc is
    found): what was written before a redirection goes where it was meant to."""
    sys.stdout.flush()
    sys.stderr.flush()
    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):  # no C library to ask (not expected on Linux or macOS)
        pass
