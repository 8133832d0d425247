"""A ``.xacro`` file, the source form of most ROS robot descriptions, expanded into the URDF it describes.

The expansion is the ``xacro`` package's (PyPI; ROS's own macro processor, without ROS): properties, macros,
conditionals, includes and ``$(arg name)`` with the arguments given (``relacc compare --xacro-arg name:=value``,
:data:`ARGUMENTS`). ``$(find pkg)`` is resolved without ROS as a URDF's ``package://`` is
(:func:`relacc.reading.packages.package_folders`: the nearest folder above the file that is ``pkg``, holds it, or holds
the ``package.xml`` that names it).
The text stays in memory: relacc's reader and every engine read the same expansion, and nothing is written.

Places: xacro keeps no line numbers, so an element of the expansion is placed in the source where its ``name`` is
written literally once in the xacro file (a link, a joint) and its children with it; an element whose name a macro
builds (``${prefix}_link``) is placed in the file without a line, and the reading's notes say how many.
"""

from __future__ import annotations

import contextlib
import re
import threading
from pathlib import Path

from relacc.errors import ModelError

ARGUMENTS: dict[str, str] = {}
"""``$(arg name)`` values for every expansion in this process (the command line's ``--xacro-arg name:=value``)."""

_LOCK = threading.Lock()  # xacro keeps its state in module globals


def set_arguments(given) -> None:
    """``NAME:=VALUE`` strings (``--xacro-arg``, as ROS's xacro takes them) set in :data:`ARGUMENTS`.

    Raises:
        InputError: one not of the form ``NAME:=VALUE``.
    """
    for text in given or []:
        name, sep, value = text.partition(":=")
        if not sep or not name:
            from relacc.errors import InputError

            raise InputError(f"--xacro-arg {text!r}: expected NAME:=VALUE, as xacro takes its arguments")
        ARGUMENTS[name] = value


def is_xacro(path) -> bool:
    return str(path).lower().endswith(".xacro")


def expand(path) -> str:
    """The URDF text the xacro file at ``path`` expands to.

    Raises:
        ModelError: the xacro package is missing, or the expansion fails (its message, one line).
    """
    from relacc.files import regular_file

    path = regular_file(path, ModelError, "xacro file")
    try:
        import xacro
        import xacro.substitution_args as subst
    except ImportError:  # pragma: no cover - xacro is a dependency
        raise ModelError(f"{path}: reading a .xacro file needs the xacro package (pip install xacro)") from None
    import io

    from relacc.isolate import captured_output

    written = io.StringIO()  # xacro's warnings through Python's stream (where a caller replaced it, not fd 2)
    failed: list = []
    with _LOCK, _find_without_ros(subst, path, failed), captured_output() as said, \
            contextlib.redirect_stderr(written):
        del xacro.all_includes[:]  # the files this expansion includes (xacro's own record of them)
        try:
            doc = xacro.process_file(str(path), mappings=dict(ARGUMENTS))
        except Exception as exc:  # xacro raises XacroException, and whatever a macro's Python raises
            if failed:  # relacc's own word on a package it cannot find, not xacro's wrapping of it
                raise failed[0] from None
            text = " ".join(str(exc).split())
            where = " ".join((" ".join(said) + " " + written.getvalue()).split())
            missing = text.removeprefix("Undefined substitution argument ").strip()
            if missing != text and missing.isidentifier():  # $(arg X) with no value yet where it is used
                text += f" (xacro has no value for it where it is used: give it with --xacro-arg {missing}:=VALUE)"
            raise ModelError(f"{path}: xacro cannot expand it: {text}" + (f" ({where[:300]})" if where else ""))
        included = list(xacro.all_includes)
    from relacc.files import note_input

    for name in included:  # inputs of the command, as an MJCF's <include>s are: no output may be one of them
        note_input(Path(name))
    return doc.toprettyxml(indent="  ")


@contextlib.contextmanager
def _find_without_ros(subst, path: Path, failed: list):
    """``$(find pkg)`` resolved as a ``package://`` target is, for the expansion's duration; the error of one that
    cannot be resolved is kept in ``failed`` (xacro wraps what it raises in its own message)."""
    from relacc.reading.packages import package_folders

    saved = subst._eval_find

    def find(pkg):
        folder = next(package_folders(pkg, path), None)
        if folder is not None:
            return str(folder)
        failed.append(ModelError(f"{path}: $(find {pkg}): no package {pkg!r} above the file: no folder so named, and "
                                 "no package.xml naming it (relacc finds a package as ROS does, without ROS)"))
        raise failed[-1]

    subst._eval_find = find
    try:
        yield
    finally:
        subst._eval_find = saved


NAME = re.compile(r"""\bname\s*=\s*["']([^"'$]+)["']""")


def source_lines(path) -> dict[str, int]:
    """``{name: line}`` for each ``name="..."`` written literally exactly once in the xacro file (1-based)."""
    counts: dict[str, list[int]] = {}
    for number, line in enumerate(Path(path).read_text(encoding="utf-8-sig").splitlines(), start=1):
        for name in NAME.findall(line):
            counts.setdefault(name, []).append(number)
    return {name: lines[0] for name, lines in counts.items() if len(lines) == 1}


__all__ = ["ARGUMENTS", "expand", "is_xacro", "source_lines"]
