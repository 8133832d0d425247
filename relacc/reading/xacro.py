"""A ``.xacro`` file, the source form of most ROS robot descriptions, expanded into the URDF it describes.

The expansion is the ``xacro`` package's (PyPI; ROS's own macro processor, without ROS): properties, macros,
conditionals, includes and ``$(arg name)`` with the arguments given (``relacc compare --xacro-arg name:=value``,
:data:`ARGUMENTS`). ``$(find pkg)`` is resolved without ROS as a URDF's ``package://`` is
(:func:`relacc.reading.packages.package_folders`: the nearest folder above the file that is ``pkg``, holds it, or holds
the ``package.xml`` that names it).
The text stays in memory: relacc's reader and every engine read the same expansion, and nothing is written.

Places: xacro keeps no line numbers, so a link or joint of the expansion is placed in the source by its ``name``
(:func:`source_places`), in the xacro file or a file it includes, and its children with it: where that name is
written literally once; else where one ``name="..."`` built from ``${...}`` matches it, the one with the most written
characters (``${prefix}link8``); else where a macro is called with the longest name it ends with (franka's
``<xacro:link_with_sc name="link4">`` for ``fr3_link4``). An element none of these places, or more than one equally,
is placed in the xacro file without a line, and the reading's notes say how many.
"""

from __future__ import annotations

import contextlib
import re
import threading
from collections.abc import Callable
from pathlib import Path

from relacc.errors import ModelError

ARGUMENTS: dict[str, str] = {}
"""``$(arg name)`` values for every expansion in this process (the command line's ``--xacro-arg name:=value``)."""

_LOCK = threading.Lock()  # xacro keeps its state in module globals


def set_arguments(given) -> None:
    """:data:`ARGUMENTS` made the ``NAME:=VALUE`` strings ``given`` (``--xacro-arg``, as ROS's xacro takes them), and
    only them: each command sets its own (they stayed in the process for every later command, and for
    :meth:`relacc.Tree.from_file`, before).

    Raises:
        InputError: one not of the form ``NAME:=VALUE`` (then nothing is changed).
    """
    parsed = {}
    for text in given or []:
        name, sep, value = text.partition(":=")
        if not sep or not name:
            from relacc.errors import InputError

            raise InputError(f"--xacro-arg {text!r}: expected NAME:=VALUE, as xacro takes its arguments")
        parsed[name] = value
    ARGUMENTS.clear()
    ARGUMENTS.update(parsed)


def is_xacro(path) -> bool:
    return str(path).lower().endswith(".xacro")


def expand(path) -> str:
    """The URDF text the xacro file at ``path`` expands to (:func:`expansion`)."""
    return expansion(path)[0]


def expansion(path) -> tuple[str, list[Path]]:
    """The URDF text the xacro file at ``path`` expands to, and the files it includes.

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
            missing = text.removeprefix("Undefined substitution argument ").split(" ", 1)[0].strip()
            if missing and not text.startswith(missing) and missing.isidentifier():  # $(arg X) with no value there
                # (alone, or inside an expression: "... X when evaluating expression '...'", wei-hsuan-cheng's
                # robot_descriptions' ros2_control files)
                text += f" (xacro has no value for it where it is used: give it with --xacro-arg {missing}:=VALUE)"
            raise ModelError(f"{path}: xacro cannot expand it: {text}" + (f" ({where[:300]})" if where else ""))
        included = list(xacro.all_includes)
    from relacc.files import note_input

    for name in included:  # inputs of the command, as an MJCF's <include>s are: no output may be one of them
        note_input(Path(name))
    return doc.toprettyxml(indent="  "), [Path(name) for name in included]


@contextlib.contextmanager
def _find_without_ros(subst, path: Path, failed: list):
    """``$(find pkg)`` resolved as a ``package://`` target is, for the expansion's duration; the error of one that
    cannot be resolved is kept in ``failed`` (xacro wraps what it raises in its own message)."""
    from relacc.reading.packages import CRAWL_LIMIT, package_folders, unfinished_searches

    saved = subst._eval_find

    def find(pkg):
        folder = next(package_folders(pkg, path), None)
        if folder is not None:
            return str(folder)
        cut = unfinished_searches(path)
        failed.append(ModelError(f"{path}: $(find {pkg}): no package {pkg!r} above the file, in its repository or in "
                                 "ROS_PACKAGE_PATH: no folder so named, and no package.xml naming it (relacc finds a "
                                 "package as ROS does, without ROS; set ROS_PACKAGE_PATH to the folders that hold it)"
                                 + (f"; the search of {', '.join(cut)} stopped after {CRAWL_LIMIT:,} folders"
                                    if cut else "")))
        raise failed[-1]

    subst._eval_find = find
    try:
        yield
    finally:
        subst._eval_find = saved


NAMED = re.compile(r"""<([\w:.-]+)((?:\s+[\w:.-]+\s*=\s*(?:"[^"]*"|'[^']*'))*)""")
NAME = re.compile(r"""(?<![\w:.-])name\s*=\s*["']([^"']+)["']""")
TYPE = re.compile(r"""(?<![\w:.-])type\s*=\s*["']([^"']*)["']""")
DEFINITIONS = ("xacro:macro", "xacro:property", "xacro:arg", "xacro:include")
"""xacro elements whose ``name`` defines something rather than names an element or calls a macro."""
SUBSTITUTION = re.compile(r"\$\{[^}]*\}|\$\([^)]*\)")


def source_places(paths) -> Callable[..., tuple[str, int] | None]:
    """A function giving, for an element's tag and name in the expansion (a link, a joint and its type, the robot),
    ``(file, line)`` of the start tag in ``paths`` (the xacro file and those it includes) that the module docstring's
    rules pick, or None. A joint's is a ``<joint>`` with a ``type`` (not a transmission's) of the joint's type where
    it is written out (a joint written in both an ``xacro:if`` and an ``xacro:unless`` is told apart by it); a macro
    call is a ``<xacro:...>``."""
    entries: list[tuple[str, str | None, list[str], str, int]] = []  # (tag, joint type, name's parts, file, line)
    import bisect

    from relacc.reading.xml import COMMENT

    for path in paths:  # comments blanked, their lines kept: a commented-out <link> is not a candidate
        text = COMMENT.sub(lambda m: "\n" * m.group(0).count("\n"), Path(path).read_text(encoding="utf-8-sig"))
        ends = [k for k, c in enumerate(text) if c == "\n"]
        for start in NAMED.finditer(text):  # a start tag may span lines: its line is where it starts
            tag, attributes = start.group(1), start.group(2)
            value = next(iter(NAME.findall(attributes)), None)
            kind = next(iter(TYPE.findall(attributes)), None)
            if value is None or (tag == "joint" and kind is None) or tag in DEFINITIONS:
                continue
            entries.append(("xacro:" if tag.startswith("xacro:") else tag,
                            None if kind is None or SUBSTITUTION.search(kind) else kind,
                            SUBSTITUTION.split(value), str(path), bisect.bisect_left(ends, start.start()) + 1))

    calls: dict[str, list] = {}  # a macro call's literal name: where it is called
    for t, _, parts, f, n in entries:
        if t == "xacro:" and len(parts) == 1:
            calls.setdefault(parts[0], []).append((f, n))

    def one(found: list) -> tuple[str, int] | None:
        best = max((k for k, _ in found), default=None)
        chosen = [at for k, at in found if k == best]
        return chosen[0] if len(chosen) == 1 else None

    def place(tag: str, name: str, kind: str | None = None) -> tuple[str, int] | None:
        mine = [(parts, (f, n)) for t, k, parts, f, n in entries
                if t == tag and (k is None or kind is None or k == kind)]
        exact = [at for parts, at in mine if parts == [name]]
        if exact:
            return exact[0] if len(exact) == 1 else None
        matched = one([(len("".join(p)), at) for p, at in mine if len(p) > 1 and "".join(p)
                       and re.fullmatch(".*".join(map(re.escape, p)), name)])
        if matched is not None:
            return matched
        return one([(len(v), at[0]) for v, at in calls.items() if len(at) == 1 and len(v) < len(name)
                    and name.endswith(v) and not name[-len(v) - 1].isalnum()])

    return place


__all__ = ["ARGUMENTS", "expand", "expansion", "is_xacro", "source_places"]
