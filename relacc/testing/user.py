"""The boundary with a user's own code (``relacc grade``): loading it and calling it apart from relacc.

A user's function runs in a forked child (:mod:`relacc.isolate`), after relacc has computed its truth: whatever
it does to the chain or tree and the arrays it is given (read-only flags flipped, values edited), to the process
(``os._exit``, ``sys.exit``, a signal, ``GeneratorExit`` or ``KeyboardInterrupt`` raised) or to file descriptor 1
stays in the child; its numbers come back as plain numeric arrays (:func:`relacc.isolate.run_plain`: nothing it sends
can run code in relacc's process), and its output goes to stderr. Each call gets its own deep copy of the subject
and of the state, and the child has :data:`CALL_TIMEOUT` seconds (``relacc grade --timeout``).

A function named ``MODULE:FUNCTION`` (``relacc grade``, :func:`load_function`) is a :class:`UserFunction`: its module
is imported in the child only, never in relacc's process, so that code at the module's top level cannot reach the
grader (``relacc.testing.grade``'s globals, the engines, ``sys.modules``).

A formula is called one state at a time, as relacc's conventions define it; when it also takes a whole batch
(``q (n, nq)`` ... returning ``(n, ...)``), that form is graded too: a function right on batches and wrong for one
state (or the reverse) is wrong.
"""

from __future__ import annotations

import contextlib
import copy
import os
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from relacc import isolate
from relacc.errors import RelaccError


class CallError(RelaccError):
    """The user's function cannot be called as a formula (it raised, ended the process, or returned the wrong
    shape)."""


CALL_TIMEOUT = 120.0
"""Seconds a child running a user's function on one batch of states may take before it is stopped (``relacc grade
--timeout``)."""


@dataclass(frozen=True)
class UserFunction:
    """A function named by ``MODULE:FUNCTION`` (a dotted module, or a path to a ``.py`` file), imported only in the
    child that calls it (module docstring). ``__name__`` is the function's name, as a function's would be."""

    module: str
    function: str

    @property
    def __name__(self) -> str:  # type: ignore[override]
        return self.function

    def load(self) -> Callable:
        """Import the module and return the function: in the child only (:func:`evaluate_user`)."""
        return _import_function(self.module, self.function)


@dataclass(frozen=True)
class Forms:
    """A user's values ``(n,) + shape`` at a batch of states: ``one`` one state at a time, ``batch`` from one call
    with the whole batch (None when the function does not take batches)."""

    one: np.ndarray
    batch: np.ndarray | None

    def each(self) -> list[tuple[str, np.ndarray]]:
        """``[(how it was called, values)]``."""
        return [("one state at a time", self.one)] + ([] if self.batch is None else [("a batch", self.batch)])


def evaluate_user(fn, subject, case, q, u, udot, shape, *, called: str = "f(chain, q, u, udot)",
                  timeout: float = CALL_TIMEOUT) -> Forms:
    """The user's values at states ``q (n, nq)``, ``u (n, nv)``, ``udot (n, nv)`` of ``case``, each ``shape``
    (see the module docstring). ``fn``: a callable, or a :class:`UserFunction` (imported in the child).
    ``subject``: the chain or tree the function is given.

    Raises:
        CallError: its module cannot be imported; one state's call raised or ended the process, returned the wrong
            shape, complex or non-numeric values, or did not finish in ``timeout`` seconds (the message names the
            function, the state and how it was called).
    """
    name = getattr(fn, "__name__", repr(fn))
    q, u, udot = (np.array(x, dtype=float) for x in (q, u, udot))
    n = len(q)

    def fresh(*arrays):
        return (copy.deepcopy(subject),) + tuple(np.array(a) for a in arrays)

    def numbers(value, what: str, i: int | None = None) -> np.ndarray | str:
        """The child's own conversion: a plain array of ``shape``, or a sentence saying why not."""
        try:
            arr = np.asarray(value)
        except Exception as exc:  # noqa: BLE001 - the user's object
            return f"returned {type(value).__name__}, which is not an array ({type(exc).__name__}) for {what}"
        at = "" if i is None else f" (state {i})"
        if arr.dtype.kind == "c":
            return (f"returned complex numbers for {what}{at}; return real numbers (relacc does not drop an "
                    "imaginary part)")
        if arr.dtype.kind not in "iuf":
            return f"returned {arr.dtype} values for {what}{at}; expected real numbers"
        return arr.astype(float)

    def step():
        function = fn.load() if isinstance(fn, UserFunction) else fn
        one = []
        for i in range(n):
            try:
                value = function(*fresh(q[i], u[i], udot[i]))
            except BaseException as exc:  # noqa: BLE001 - SystemExit, GeneratorExit, KeyboardInterrupt: the user's
                text = str(exc)
                return {"raised": [i, type(exc).__name__, text.splitlines()[0] if text else ""]}, []
            arr = numbers(value, "one state", i)
            if isinstance(arr, str):
                return {"wrong": arr}, []
            if arr.shape != shape:
                return {"wrong": f"returned shape {arr.shape} for one state (state {i}); expected {shape} (see "
                                  "relacc grade --help for the conventions)"}, []
            one.append(arr)
        try:
            batch = numbers(function(*fresh(q, u, udot)), "a batch")
        except BaseException:  # noqa: BLE001 - a function that does not take batches
            batch = None
        if isinstance(batch, str):
            if "complex" in batch:
                return {"wrong": batch}, []
            batch = None
        if batch is not None and batch.shape != (n,) + shape:
            batch = None  # not a batched formula: graded one state at a time
        values = np.stack(one) if one else np.zeros((0,) + shape)
        return {"batch": batch is not None}, [values] + ([] if batch is None else [batch])

    got = isolate.run_plain(step, output="stderr", timeout=timeout)
    where = f"called as {name}{called[1:]} with one state of case {case}"
    if isinstance(got, isolate.Ended):
        raise CallError(f"{name} {got.sentence()} ({where}); relacc ran it in a child process and carried on")
    if isinstance(got, isolate.Raised):
        raise CallError(f"{name}: {got.type}: {got.message} ({where})")
    header, arrays = got
    try:
        wrong = _said(header, name, where)
    except (TypeError, ValueError, KeyError):
        wrong = f"{name}: its child process sent back a header relacc did not ask for ({where})"
    if wrong:
        raise CallError(wrong)
    # what came back is held to what was asked, whatever the child says of it
    expected = [(n,) + shape] * (1 + (header.get("batch") is True))
    if [a.shape for a in arrays] != expected or any(a.dtype != np.float64 for a in arrays):
        raise CallError(f"{name}: its child process sent back arrays of shapes {[a.shape for a in arrays]} and "
                        f"types {[str(a.dtype) for a in arrays]}, not {expected} of float64 ({where})")
    return Forms(arrays[0], arrays[1] if len(arrays) > 1 else None)


def _said(header: dict, name: str, where: str) -> str:
    """The one line a child's header says went wrong (the function raised, or returned what is not a formula's
    value), or ``""``."""
    if "raised" in header:
        i, kind, message = header["raised"]
        if kind == "SystemExit":
            return f"{name} called sys.exit({message!r}) ({where}, state {int(i)})"
        return f"{name} raised {str(kind)[:200]}: {str(message)[:500]} ({where}, state {int(i)})"
    if "wrong" in header:
        return f"{name} {str(header['wrong'])[:500]}"
    return ""


def load_function(spec: str) -> UserFunction:
    """``MODULE:FUNCTION`` (a dotted module, or a path to a ``.py`` file) -> a :class:`UserFunction`. The module is
    imported in a forked child to check that it imports and has the function (what it prints goes to stderr, at the
    level of file descriptors); relacc's own process never imports it.

    Raises:
        CallError: the module cannot be imported, has no such function, or takes over ``timeout`` seconds to import.
    """
    from relacc.files import regular_file

    module_name, sep, func = spec.rpartition(":")
    if not sep or not module_name or not func:
        raise CallError(f"{spec!r}: expected MODULE:FUNCTION, e.g. examples/student_correct.py:velocity")
    if module_name.endswith(".py") or "/" in module_name:
        module_name = str(regular_file(module_name, CallError, "Python module").resolve())
    user = UserFunction(module_name, func)

    def probe():
        user.load()
        return {}, []

    got = isolate.run_plain(probe, output="stderr", timeout=CALL_TIMEOUT)
    if isinstance(got, isolate.Raised):
        raise CallError(got.message if got.type == "CallError" else f"{module_name}: {got.type}: {got.message}")
    if isinstance(got, isolate.Ended):
        raise CallError(f"{module_name}: importing it {got.sentence()}")
    return user


def _import_function(module_name: str, func: str) -> Callable:
    """The import itself (in the child): a ``.py`` path as running the file would (its siblings import), or a dotted
    module."""
    import importlib
    import importlib.util

    try:
        with _stdout_to_stderr():
            if module_name.endswith(".py") or "/" in module_name:
                path = Path(module_name)
                loader = importlib.util.spec_from_file_location(path.stem, path)
                if loader is None or loader.loader is None:
                    raise CallError(f"{path}: Python cannot load it as a module")
                module = importlib.util.module_from_spec(loader)
                sys.path.insert(0, str(path.parent))
                try:
                    loader.loader.exec_module(module)
                finally:
                    sys.path.remove(str(path.parent))
            else:
                module = importlib.import_module(module_name)
    except CallError:
        raise
    except SystemExit as exc:  # the user's module ends the process on import: report it, do not exit
        raise CallError(f"{module_name}: calls sys.exit({exc.code!r}) when imported") from None
    except (Exception, GeneratorExit) as exc:  # the user's module: any failure to import is reported in one line
        raise CallError(f"{module_name}: cannot be imported ({type(exc).__name__}: {exc})") from None
    fn = getattr(module, func, None)
    if not callable(fn):
        raise CallError(f"{module_name} has no function {func!r}")
    return fn


@contextlib.contextmanager
def _stdout_to_stderr():
    """File descriptor 1 (and so ``sys.stdout`` and ``print``) pointed at stderr for the block."""
    sys.stdout.flush()
    saved = os.dup(1)
    os.dup2(2, 1)
    try:
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)
