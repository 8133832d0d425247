"""Every file relacc writes goes through here: atomically, all or nothing, and checked before any work.

* :func:`write_text` / :func:`write_bytes`: a temporary file in the
  destination's directory, flushed and synced, then renamed over the
  destination. On any error, and on SIGINT or SIGTERM (the command line turns
  both into exceptions, :func:`terminate_as_interrupt`), the previous file is
  left byte for byte and the temporary file is removed.
* :func:`replace_all`: a set of files that belong together (the engine files
  of one chain) is staged completely first; only then are the files renamed
  into place, and a failed rename puts the earlier ones back.
* :func:`check_output_file` / :func:`check_new_directory`: what ``--out``
  names is checked before a command does its work.
* :func:`inputs`: the files a command reads are registered for its duration;
  an output that resolves to one of them (the same path after symbolic links,
  or the same file by a hard link) is refused, by the checks above before any
  work and again by every writer before anything is replaced: no input file is
  ever an output.
* :func:`regular_file`: what a command reads is a regular file (a FIFO would block it, a directory is no model).
"""

from __future__ import annotations

import contextlib
import logging
import os
import signal
import sys
import tempfile
from pathlib import Path

from relacc.errors import InputError, OutputError


def _stage(path: Path, data: bytes) -> Path:
    """``data`` in a new temporary file beside ``path``, synced, with the usual permissions."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return Path(tmp)


def _os_error(path, exc: OSError) -> OutputError:
    return OutputError(f"{path}: cannot write the file ({exc.strerror or exc})")


def write_bytes(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (see the module docstring).

    Raises:
        InputError: ``path`` is one of the command's inputs (:func:`inputs`).
        OutputError: the file cannot be written (the message names it and why);
            the previous file, if any, is unchanged.
    """
    path = Path(path)
    check_not_input(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)  # --out creates its parents, in every command
        tmp = _stage(path, data)
    except OSError as exc:
        raise _os_error(path, exc) from None
    try:
        check_interrupt()
        os.replace(tmp, path)
    except BaseException as exc:
        tmp.unlink(missing_ok=True)
        if isinstance(exc, OSError):
            raise _os_error(path, exc) from None
        raise
    return path


def write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return write_bytes(path, text.encode("utf-8"))


def replace_all(files: dict) -> list[Path]:
    """Write several files ``{path: text}`` all or nothing.

    Every file is staged first; if any staging fails nothing is replaced. The
    renames then follow; if one fails, the files already replaced are put
    back from copies of their previous contents.

    Raises:
        InputError: one of the paths is one of the command's inputs (:func:`inputs`): nothing is written.
        OutputError: naming the file that could not be written.
    """
    for path in files:
        check_not_input(Path(path))
    staged = {}
    try:
        for path, text in files.items():
            path = Path(path)
            try:
                staged[path] = _stage(path, text.encode("utf-8"))
            except OSError as exc:
                raise _os_error(path, exc) from None
        _rename_all(staged)
    finally:
        for tmp in staged.values():
            tmp.unlink(missing_ok=True)
    return list(staged)


@contextlib.contextmanager
def streams(paths):
    """Text handles ``{path: handle}`` for files written piece by piece, replaced all or nothing at the end.

    Each handle writes to a temporary file beside its path. When the block
    ends normally the files are renamed into place (a failed rename puts back
    the ones already replaced); on any exception, SIGINT or SIGTERM included,
    the temporary files are removed and the previous files are unchanged.

    Raises:
        OutputError: a file cannot be created or written.
    """
    paths = [Path(p) for p in paths]
    for path in paths:
        check_not_input(path)
    handles: dict = {}
    temps: dict[Path, Path] = {}
    try:
        for path in paths:
            try:
                fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
            except OSError as exc:
                raise _os_error(path, exc) from None
            temps[path] = Path(tmp)
            handles[path] = os.fdopen(fd, "w", encoding="utf-8", newline="")
        try:
            yield handles
            for path, fh in handles.items():
                fh.flush()
                os.fsync(fh.fileno())
        except OSError as exc:
            raise _os_error(next(iter(handles)), exc) from None
        for fh in handles.values():
            fh.close()
        umask = os.umask(0)
        os.umask(umask)
        for staged in temps.values():
            os.chmod(staged, 0o666 & ~umask)
        _rename_all(temps)
    finally:
        for fh in handles.values():
            with contextlib.suppress(OSError):
                fh.close()
        for staged in temps.values():
            staged.unlink(missing_ok=True)


def _rename_all(temps: dict) -> None:
    """Rename each staged temporary file over its path; on a failure put back the ones already replaced."""
    done: list[Path] = []
    backups: dict[Path, bytes | None] = {}
    try:
        check_interrupt()
        for path, tmp in temps.items():
            try:
                backups[path] = path.read_bytes() if path.exists() else None
                os.replace(tmp, path)
            except OSError as exc:
                raise _os_error(path, exc) from None
            done.append(path)
    except BaseException:
        for path in done:
            with contextlib.suppress(OSError, OutputError):
                backup = backups[path]
                if backup is None:
                    path.unlink()
                else:
                    write_bytes(path, backup)
        raise


def regular_file(path, error=InputError, what: str = "file") -> Path:
    """``path`` if it names an existing regular file (symbolic links followed), else one ``error``: no such file, a
    directory, or another kind (a FIFO, a socket, a device: reading one could block or never end)."""
    import stat

    path = Path(path)
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except OSError as exc:
        raise error(f"{path}: cannot read the {what} ({exc.strerror or exc})") from None
    if stat.S_ISDIR(mode):
        raise error(f"{path}: is a directory, not a {what}")
    if not stat.S_ISREG(mode):
        kind = "a FIFO" if stat.S_ISFIFO(mode) else "a socket" if stat.S_ISSOCK(mode) else "a device"
        raise error(f"{path}: {kind}, not a regular file: relacc reads a {what} from a regular file")
    return path


def read_document(source, parse, kind: str, error=InputError, what: str = "file"):
    """``(value, text)`` of a text document (TOML, JSON) read from ``source`` (a path, or ``-``: stdin).

    Every way the input can be bad is one ``error`` naming the source:
    unreadable, not UTF-8, not valid ``kind``, nested too deeply, or holding a
    number too long to convert.
    """
    try:
        if str(source) == "-":
            import sys

            text = sys.stdin.buffer.read().decode("utf-8")
        else:
            with open(regular_file(source, error, what), encoding="utf-8") as fh:
                text = fh.read()
    except OSError as exc:
        raise error(f"{source}: cannot read the {what} ({exc.strerror or exc})") from None
    except UnicodeDecodeError as exc:
        raise error(f"{source}: the {what} is not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    try:
        return parse(text), text
    except RecursionError:
        raise error(f"{source}: not readable {kind}: arrays, objects or tables nested too deeply") from None
    except ValueError as exc:  # the parser's syntax errors, and numbers too long to convert
        raise error(f"{source}: not valid {kind}: {exc}") from None


def check_output_file(path, what: str = "--out") -> Path:
    """Check, before any work, that a file can be written at ``path`` (it may exist: it is replaced).

    Raises:
        InputError: ``path`` is a directory, its parent is a file or is not
            writable, or the parent cannot be created.
    """
    path = _named(path, what, "a file name such as reports/page.html")
    if path.is_dir():
        raise InputError(f"{what} {path}: is a directory; give a file name such as {path / 'agreement.html'}")
    check_not_input(path, what)
    _check_parent(path, what)
    return path


def _named(path, what: str, example: str) -> Path:
    """``path`` as a Path; an empty one (which would mean the working directory) is refused."""
    if path is None or not str(path).strip():
        raise InputError(f"{what}: empty; give {example} (relacc writes only where it is told)")
    return Path(path)


def check_new_directory(path, what: str = "--out", names=()) -> Path:
    """Check, before any work, that ``path`` can be made a directory for new files (``names``, when known).

    It may be an existing directory (files in it are replaced atomically) or
    not exist yet (it is created then, with its parents).

    Raises:
        InputError: ``path`` is an existing file, its parent is a file, or it is not writable; or one of the files
            ``names`` it would hold is one of the command's inputs (:func:`inputs`).
    """
    path = _named(path, what, "a directory name such as runs/")
    if path.exists() and not path.is_dir():
        raise InputError(f"{what} {path}: is an existing file; give a directory (new or existing)")
    for name in names:
        check_not_input(path / name, what)
    if path.is_dir():
        if not os.access(path, os.W_OK | os.X_OK):
            raise InputError(f"{what} {path}: the directory is not writable")
        return path
    _check_parent(path, what)
    return path


_INPUTS: list = []
"""The inputs of the running command: ``(given path, resolved path, (st_dev, st_ino) or None)``."""
_BLOCKS: list = []
"""The entries each open :func:`inputs` block added (innermost last): what :func:`note_input` adds goes with it."""


def _identity(path: Path):
    """``(resolved path, (st_dev, st_ino) or None)``: the file a path names, after symbolic links."""
    resolved = path.resolve()
    try:
        st = os.stat(resolved)
        return resolved, (st.st_dev, st.st_ino)
    except OSError:
        return resolved, None


@contextlib.contextmanager
def inputs(paths):
    """Inside the block, the files ``paths`` (None entries skipped) are inputs: no write may replace one (see the
    module docstring). Blocks nest; each removes only its own entries."""
    added: list = []
    _BLOCKS.append(added)
    try:
        for given in paths:
            _add_input(given, added)
        yield
    finally:
        _BLOCKS.pop()
        for entry in added:
            _INPUTS.remove(entry)


def _add_input(given, added: list) -> None:
    if given is None or not str(given).strip() or str(given) == "-":
        return
    try:
        resolved, inode = _identity(Path(given))
    except (OSError, RuntimeError, ValueError):  # a path that cannot be resolved cannot be written over either
        return
    entry = (str(given), resolved, inode)
    added.append(entry)
    _INPUTS.append(entry)


def note_input(path) -> None:
    """``path`` is read by the running command (a model's ``<include>``, a mesh, a URDF's ``package://`` target):
    an input until the innermost :func:`inputs` block ends, so that no writer replaces it. Outside any block (the
    API), nothing to do."""
    if _BLOCKS:
        _add_input(path, _BLOCKS[-1])


def check_not_input(path, what: str = "output") -> None:
    """Refuse ``path`` when it is one of the running command's inputs (:func:`inputs`).

    Raises:
        InputError: naming the input and saying what to do.
    """
    if not _INPUTS:
        return
    try:
        resolved, inode = _identity(Path(path))
    except (OSError, RuntimeError, ValueError):
        return
    for given, other, other_inode in _INPUTS:
        if resolved == other or (inode is not None and inode == other_inode):
            raise InputError(f"{what} {path}: is {given}, an input of this command; relacc never writes over its "
                             "inputs: give another path")


def _check_parent(path: Path, what: str) -> None:
    parent = path.parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    if not parent.is_dir():
        raise InputError(f"{what} {path}: {parent} is a file, not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{what} {path}: {parent} is not writable")


def make_directory(path) -> Path:
    """Create ``path`` (and its parents) as checked by :func:`check_new_directory`.

    Raises:
        OutputError: it cannot be created.
    """
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{path}: cannot create the directory ({exc.strerror or exc})") from None
    return path


@contextlib.contextmanager
def new_directory(path):
    """Create ``path`` (and its parents) for the block; if the block fails or is interrupted, the directories it
    created are removed again when they are still empty (nothing left behind but what was written completely)."""
    path = Path(path)
    created = []
    for p in [path, *path.parents]:
        if p.exists():
            break
        created.append(p)
    make_directory(path)
    try:
        yield path
    except BaseException:
        for p in created:  # deepest first
            with contextlib.suppress(OSError):
                p.rmdir()  # only an empty directory goes
        raise


@contextlib.contextmanager
def terminate_as_interrupt():
    """Inside the block, SIGTERM raises :class:`KeyboardInterrupt` like SIGINT, so writes clean up.

    Both signals also leave a pending interrupt (:func:`check_interrupt`): an exception raised while a C library
    runs a Python callback (numba's compiler calls its object cache through ctypes; Hypothesis, which the report's
    hard-case search runs, has a garbage-collector callback) is dropped there, and the command would carry on (its
    "Exception ignored" lines are kept off stderr while the interrupt is pending); every atomic write and the
    command's end check for it, so an interrupt is never lost, at the latest before any file is changed."""
    def handler(signum, frame):
        PENDING[0] = signum
        raise KeyboardInterrupt(f"signal {signum}")

    try:  # a signal the parent ignores (SIGINT in a script's background job) stays ignored
        previous = {sig: signal.signal(sig, handler) for sig in (signal.SIGTERM, signal.SIGINT)
                    if signal.getsignal(sig) is not signal.SIG_IGN}
    except ValueError:  # not the main thread: leave signals alone
        yield
        return
    unraisable = sys.unraisablehook
    sys.unraisablehook = quiet_unraisable(unraisable)
    pending = _PendingFilter()
    for name in QUIET_LOGGERS:
        logging.getLogger(name).addFilter(pending)
    try:
        check_interrupt()  # one that came before the block (relacc's entry records it too) and was lost on the way
        yield
    finally:
        sys.unraisablehook = unraisable
        for name in QUIET_LOGGERS:
            logging.getLogger(name).removeFilter(pending)
        for sig, old in previous.items():
            signal.signal(sig, old)


def quiet_unraisable(unraisable):
    """``sys.unraisablehook`` that passes everything to ``unraisable`` while no interrupt is pending, and nothing once
    one is (:data:`PENDING`): its :class:`KeyboardInterrupt` lost in a callback or a finalizer, and the finalizers of
    the objects it left half-built (llvmlite's ``TargetMachine`` interrupted while numba compiled: "Exception ignored
    ... AttributeError: 'TargetMachine' object has no attribute '_as_parameter_'", a clean clone's run at 1.6 s), are
    not news; the command's one line is."""
    def quiet(info):
        if PENDING[0] is None:
            unraisable(info)

    return quiet


QUIET_LOGGERS = ("drake",)
"""Loggers of libraries that log their own failure when an interrupt lands while they load (pydrake: "CRITICAL:drake:
Could not initialize pydrake: KeyboardInterrupt" and 40 lines of stack): silent while an interrupt is pending, whose
one line is relacc's."""


class _PendingFilter(logging.Filter):
    def filter(self, record) -> bool:
        return PENDING[0] is None


PENDING: list = [None]
"""The signal of an interrupt not yet acted on (see :func:`terminate_as_interrupt`), or None."""


def check_interrupt() -> None:
    """Raise the pending interrupt, if a signal came and its :class:`KeyboardInterrupt` was lost on the way."""
    if PENDING[0] is not None:
        raise KeyboardInterrupt(f"signal {PENDING[0]}")


def clear_interrupt() -> None:
    """The interrupt has been acted on."""
    PENDING[0] = None
