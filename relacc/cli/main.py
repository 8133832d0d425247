"""``relacc``'s entry point: parse, dispatch, and turn every relacc error into one line and exit 2.

* A :class:`relacc.RelaccError` (bad input, unreadable or unwritable files,
  a request too large for memory) prints one line on stderr and exits 2.
* SIGINT and SIGTERM interrupt the command as :class:`KeyboardInterrupt`, so
  that files being written are cleaned up (:mod:`relacc.files`); one line,
  exit 130, also when a compiled caller turned the interrupt into its own
  error (numba's dispatcher raises ``SystemError`` from it).
* numpy's floating-point warnings do not reach the user as warnings: inside
  a command they are errors, and relacc's own checks (non-finite results,
  conditioning) are what reports them; one that escapes those checks is
  reported as one line, exit 2, like an input error.
* Output cut short by the reader (``relacc check | head``) ends quietly, exit 141.
* Anything else is relacc's own failure, never a verdict: one line naming the exception, with a request to report
  it, exit :data:`INTERNAL` (3). ``RELACC_DEBUG=1`` in the environment lets the traceback through instead.
"""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

from relacc import files

INTERNAL = 3
"""The exit code of an internal error: never 0 or 1, which are verdicts, nor 2, which is the user's input."""


def main(argv=None) -> int:
    """Run ``relacc`` with ``argv`` (default ``sys.argv[1:]``); returns the exit code (see ``--help``).

    An interrupt stays pending (:data:`relacc.files.PENDING`) until the command has said its one line and let go of
    the exception: what the interrupt left half-built is freed while ``Exception ignored`` reports are still kept off
    stderr (llvmlite's ``PassBuilder`` interrupted while numba compiled the report's kernels on a clean clone printed
    "AttributeError: 'PassBuilder' object has no attribute '_as_parameter_'" and its stack after the line)."""
    try:
        return _main(argv)
    finally:
        if files.PENDING[0] is not None:
            import gc

            gc.collect()  # what the interrupt left half-built, in reference cycles too, freed while it is pending
            files.clear_interrupt()


def _main(argv) -> int:
    from relacc.cli.parser import build_parser

    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exc:  # --help, --version (0) and usage errors (2, one line already printed)
        return exc.code if isinstance(exc.code, int) else 2
    from relacc.cli import commands
    from relacc.cli.progress import compile_notice, end_line
    from relacc.errors import RelaccError

    name = f"relacc {args.command}"
    try:
        with files.terminate_as_interrupt(), warnings.catch_warnings(), files.inputs(input_paths(args)):
            warnings.simplefilter("error", RuntimeWarning)
            note_model_files(args)
            if args.command not in ("eval", "fixtures"):  # the commands that run compiled kernels
                compile_notice(bool(getattr(args, "quiet", False)))
            code = getattr(commands, f"cmd_{args.command}")(args)
            files.check_interrupt()  # an interrupt a C library's callback swallowed on the way
            return code
    except RelaccError as exc:
        end_line()
        print(f"{name}: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeWarning as exc:
        print(f"{name}: error: a floating-point failure escaped relacc's checks ({exc}); the inputs are "
              "probably beyond float64's range", file=sys.stderr)
        return 2
    except MemoryError:
        print(f"{name}: error: not enough memory for this request; ask for fewer states", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # the pending interrupt is cleared once this exception is gone (main)
        end_line()
        print(f"{name}: interrupted; no output file was changed", file=sys.stderr)
        return 130
    except BrokenPipeError:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # the reader has gone: drop what is still buffered
        return 141
    except Exception as exc:  # an interrupt a compiled caller turned into its own error (numba: SystemError)
        if files.PENDING[0] is None and not _interrupt_in(exc):
            if os.environ.get("RELACC_DEBUG"):
                raise
            end_line()
            print(f"{name}: internal error: {internal_error(exc)}", file=sys.stderr)
            return INTERNAL
        end_line()
        print(f"{name}: interrupted; no output file was changed", file=sys.stderr)
        return 130


def internal_error(exc: BaseException) -> str:
    """One line for an exception that is relacc's own failure: its type, its message's first line, where it was
    raised in relacc, and what to do."""
    import traceback

    frames = [f for f in traceback.extract_tb(exc.__traceback__) if "relacc" in f.filename]
    where = f" at {Path(frames[-1].filename).name}:{frames[-1].lineno}" if frames else ""
    text = str(exc).splitlines()[0] if str(exc) else ""
    return (f"{type(exc).__name__}: {text}{where} (a bug in relacc, not a verdict on the model; please report it "
            "with the command and its files; RELACC_DEBUG=1 shows the traceback)")


def input_paths(args) -> list[str]:
    """Every file a command's arguments name as an input (model files, a chain's engine files beside its TOML, a
    URDF, a scene, a state, the module of a graded function): no output may be one of them
    (:func:`relacc.files.inputs`). A directory given to ``compare`` is expanded there."""

    out = []
    model = getattr(args, "model", None)
    for given in model if isinstance(model, list) else [model]:
        if given is None:
            continue
        out.append(given)
        if Path(given).suffix.lower() == ".toml":  # a chain's source: its engine files beside it are read too
            from relacc.fixtures import MODEL_FILES

            out += [Path(given).parent / name for name in MODEL_FILES]
    for key in ("urdf", "scene", "state", "baseline"):
        value = getattr(args, key, None)
        if isinstance(value, str):
            out.append(value)
    function = getattr(args, "function", None)
    if isinstance(function, str) and ":" in function:
        out.append(function.rpartition(":")[0])
    return out


def note_model_files(args) -> None:
    """Every file the model files named read (includes, meshes, ``package://`` targets) noted as inputs before the
    command's work, so that an output naming one is refused up front (:func:`relacc.reading.read.note_files`)."""
    model = getattr(args, "model", None)
    paths = [p for p in (model if isinstance(model, list) else [model]) if isinstance(p, str)]
    paths += [p for p in (getattr(args, "urdf", None),) if isinstance(p, str)]
    models = [p for p in paths if Path(p).suffix.lower() in (".xml", ".urdf", ".xacro") and Path(p).is_file()]
    if models:
        from relacc.reading.read import note_files

        for path in models:
            note_files(path)


def _interrupt_in(exc) -> bool:
    """Whether a :class:`KeyboardInterrupt` is among the causes of ``exc`` (numba's dispatcher, interrupted while it
    unpickles a cached kernel, raises ``SystemError`` from it)."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def entry() -> None:
    """The ``relacc`` console command: :func:`main`, then exit with its code.

    SIGINT and SIGTERM are taken from this function's first instruction to the process's last: before the command
    starts (the parser, the imports) they interrupt it as :class:`KeyboardInterrupt`, one line and exit 130; once
    it has ended, output is flushed and the process exits at once (``os._exit``: no interpreter teardown, in which a
    signal would end it silently), a signal in between giving the same one line and 130. An interrupt a finalizer or
    a library's callback drops before the command's own handling starts stays pending (:data:`relacc.files.PENDING`,
    its "Exception ignored" report kept off stderr) and is raised as the command starts, before any file is written.
    After an error or an interrupt relacc has said what happened in one line; what libraries still print while the
    process winds down (Dask's own handlers closing a cluster that was still starting) is not the user's news."""
    import signal

    state = {"running": True, "said": False}  # one handler for the whole process: no moment without one

    def handler(signum, frame):
        if state["running"]:  # the command (or its start) is under way: unwind it, then one line
            files.PENDING[0] = signum  # kept, should a finalizer or a callback drop the exception (files.PENDING)
            raise KeyboardInterrupt(f"signal {signum}")
        os._exit(130 if state["said"] else _say_interrupted(name))  # it has ended: nothing more to unwind

    name = "relacc"
    for sig in (signal.SIGINT, signal.SIGTERM):
        if signal.getsignal(sig) is not signal.SIG_IGN:  # a signal the parent ignores (a background job) stays so
            signal.signal(sig, handler)
    sys.unraisablehook = files.quiet_unraisable(sys.unraisablehook)
    try:
        name = f"relacc {sys.argv[1]}" if len(sys.argv) > 1 and not sys.argv[1].startswith("-") else name
        code = main()
        state["running"] = False
    except KeyboardInterrupt:
        state["running"] = False
        code = _say_interrupted(name)
        state["said"] = True
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        code = 141
    sys.stderr.flush()
    os._exit(code)


def _say_interrupted(name: str) -> int:
    """The one line of an interrupt (stdout's unwritten rest dropped), and its exit code."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.write(sys.stderr.fileno(), f"{name}: interrupted; no output file was changed\n".encode())
    except OSError:
        pass
    return 130


if __name__ == "__main__":  # pragma: no cover
    entry()
