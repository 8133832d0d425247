"""The boundary with a user's own code (``relacc grade``): loading it and calling it apart from relacc.

A user's function runs in a forked child (:mod:`relacc.isolate`), after relacc has computed its truth: whatever
it does to the chain or tree and the arrays it is given (read-only flags flipped, values edited), to the process
(``os._exit``, ``sys.exit``, a signal, ``GeneratorExit`` or ``KeyboardInterrupt`` raised) or to file descriptor 1
stays in the child; its numbers come back by value, and its output goes to stderr. Each call gets its own deep copy
of the subject and of the state.

A formula is called one state at a time, as relacc's conventions define it; when it also takes a whole batch
(``q (n, nq)`` ... returning ``(n, ...)``), that form is graded too: a function right on batches and wrong for one
state (or the reverse) is wrong.
"""

from __future__ import annotations

import contextlib
import copy
import os
import sys
from dataclasses import dataclass

import numpy as np

from relacc import isolate
from relacc.errors import RelaccError


class CallError(RelaccError):
    """The user's function cannot be called as a formula (it raised, ended the process, or returned the wrong
    shape)."""


@dataclass(frozen=True)
class Forms:
    """A user's values ``(n,) + shape`` at a batch of states: ``one`` one state at a time, ``batch`` from one call
    with the whole batch (None when the function does not take batches)."""

    one: np.ndarray
    batch: np.ndarray | None

    def each(self) -> list[tuple[str, np.ndarray]]:
        """``[(how it was called, values)]``."""
        return [("one state at a time", self.one)] + ([] if self.batch is None else [("a batch", self.batch)])


def _real(name: str, value, what: str) -> np.ndarray:
    arr = np.asarray(value)
    if arr.dtype.kind == "c":
        raise CallError(f"{name} returned complex numbers for {what}; return real numbers (relacc does not drop an "
                        "imaginary part)")
    if arr.dtype.kind not in "iuf":
        raise CallError(f"{name} returned {arr.dtype} values for {what}; expected real numbers")
    return arr.astype(float)


def evaluate_user(fn, subject, case, q, u, udot, shape, *, called: str = "f(chain, q, u, udot)") -> Forms:
    """The user's values at states ``q (n, nq)``, ``u (n, nv)``, ``udot (n, nv)`` of ``case``, each ``shape``
    (see the module docstring). ``subject``: the chain or tree the function is given.

    Raises:
        CallError: one state's call raised or ended the process, returned the wrong shape, complex or non-numeric
            values (the message names the function, the state and how it was called).
    """
    name = getattr(fn, "__name__", repr(fn))
    q, u, udot = (np.array(x, dtype=float) for x in (q, u, udot))
    n = len(q)

    def fresh(*arrays):
        return (copy.deepcopy(subject),) + tuple(np.array(a) for a in arrays)

    def step():
        one = []
        for i in range(n):
            try:
                one.append(np.asarray(fn(*fresh(q[i], u[i], udot[i]))))
            except BaseException as exc:  # noqa: BLE001 - SystemExit, GeneratorExit, KeyboardInterrupt: the user's
                text = str(exc)
                return "raised", i, type(exc).__name__, text.splitlines()[0] if text else ""
        try:
            batch = np.asarray(fn(*fresh(q, u, udot)))
        except BaseException:  # noqa: BLE001 - a function that does not take batches
            batch = None
        return "values", one, batch

    got = isolate.run(step, output="stderr")
    where = f"called as {name}{called[1:]} with one state of case {case}"
    if isinstance(got, isolate.Ended):
        raise CallError(f"{name} {got.sentence()} ({where}); relacc ran it in a child process and carried on")
    if isinstance(got, isolate.Raised):
        raise CallError(f"{name}: {got.type}: {got.message} ({where})")
    if got[0] == "raised":
        _, i, kind, message = got
        if kind == "SystemExit":
            raise CallError(f"{name} called sys.exit({message!r}) ({where}, state {i})")
        raise CallError(f"{name} raised {kind}: {message} ({where}, state {i})")
    _, one, batch = got
    values = []
    for i, value in enumerate(one):
        arr = _real(name, value, "one state")
        if arr.shape != shape:
            raise CallError(f"{name} returned shape {arr.shape} for one state (state {i}); expected {shape} (see "
                            "relacc grade --help for the conventions)")
        values.append(arr)
    if batch is not None:
        try:
            batch = _real(name, batch, "a batch")
        except CallError as exc:
            if "complex" in str(exc):
                raise
            batch = None
        if batch is not None and batch.shape != (n,) + shape:
            batch = None  # not a batched formula: graded one state at a time
    return Forms(np.stack(values) if values else np.zeros((0,) + shape), batch)


def load_function(spec: str):
    """``MODULE:FUNCTION`` (a dotted module, or a path to a ``.py`` file) -> the function. What the module prints
    while it is imported goes to stderr, at the level of file descriptors (``os.write(1, ...)`` included).

    Raises:
        CallError: the module cannot be imported, or has no such function.
    """
    import importlib
    import importlib.util

    from relacc.files import regular_file

    module_name, sep, func = spec.rpartition(":")
    if not sep or not module_name or not func:
        raise CallError(f"{spec!r}: expected MODULE:FUNCTION, e.g. examples/student_correct.py:velocity")
    try:
        with _stdout_to_stderr():
            if module_name.endswith(".py") or "/" in module_name:
                path = regular_file(module_name, CallError, "Python module")
                loader = importlib.util.spec_from_file_location(path.stem, path)
                if loader is None or loader.loader is None:
                    raise CallError(f"{path}: Python cannot load it as a module")
                module = importlib.util.module_from_spec(loader)
                sys.path.insert(0, str(path.resolve().parent))  # as running the file would: its siblings import
                try:
                    loader.loader.exec_module(module)
                finally:
                    sys.path.remove(str(path.resolve().parent))
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
