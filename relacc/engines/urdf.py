"""What the engines read of a URDF: its kinematics and inertials, without its visual and collision geometry.

Dynamics need a URDF's joints, links and ``<inertial>`` elements only (a ``<mimic>`` is a constraint, which the
unconstrained dynamics compared leave out; an engine that reads it as one cannot give them); its ``<visual>`` and
``<collision>`` elements name meshes (``package://`` paths, formats an engine cannot read) that have no part in
them, and URDF defines a link's inertia by its ``<inertial>`` alone (no inertial: a massless link). So every adapter
reads the same text, :func:`dynamics_text`, with those elements removed, from memory (nothing is written anywhere),
and the warnings say how many were dropped. Engine-free: shared by the adapters.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path
from xml.parsers import expat

from relacc.errors import ModelError
from relacc.files import regular_file

GEOMETRY = ("visual", "collision")
DROPPED = GEOMETRY + ("mimic", "material", "gazebo")
ELEMENTS = re.compile(r"<(visual|collision|mimic|material|gazebo)\b[^>]*?/>"
                      r"|<(visual|collision|mimic|material|gazebo)\b.*?</\2\s*>", re.S)
"""A self-closed or a whole element of those the dynamics do not read (none of them nests in itself): geometry, the
mimic constraint, a robot-level ``<material>`` (its ``<texture filename="package://...">`` stopped Drake's parser,
which resolves it), and ``<gazebo>`` (a simulator's own settings, often with XML prefixes it never declares,
``<sensor:camera>``, which a namespace-aware parser refuses)."""
DECLARATION = re.compile(r"^<\?xml.*?\?>", re.S)


def is_urdf(path) -> bool:
    """A URDF, or a xacro file (its expansion is one, :mod:`relacc.reading.xacro`)."""
    return Path(path).suffix.lower() in (".urdf", ".xacro")


def dynamics_text(path) -> tuple[str, str | None]:
    """``(text, note)``: the URDF at ``path`` without its links' visual and collision elements, and a one-line note
    saying how many were dropped (None when there were none).

    Raises:
        ModelError: a missing or unreadable file, or XML that does not parse (the parser's message, with its line).
    """
    path = regular_file(path, ModelError, "model file")
    stat = path.stat()
    arguments: tuple[tuple[str, str], ...] = ()
    if path.suffix.lower() == ".xacro":  # its expansion depends on its arguments too
        from relacc.reading.xacro import ARGUMENTS

        arguments = tuple(sorted(ARGUMENTS.items()))
    return _dynamics_text(path, stat.st_mtime_ns, stat.st_size, arguments)  # each adapter asks; read once


@functools.lru_cache(maxsize=8)
def _dynamics_text(path: Path, mtime_ns: int, size: int, arguments: tuple = ()) -> tuple[str, str | None]:
    try:
        if path.suffix.lower() == ".xacro":  # its expansion, in memory (the reader's and every engine's)
            from relacc.reading.xacro import expand

            text = expand(path)
        else:
            text = path.read_text(encoding="utf-8-sig")
        # what MuJoCo reads: whitespace before the declaration and NUL bytes after the document left out, and the
        # (optional) declaration itself, so that the engines' messages keep the file's line numbers
        body = DECLARATION.sub(lambda m: "\n" * m.group(0).count("\n"), text.lstrip()).rstrip("\x00")
        text = "\n" * text[:len(text) - len(text.lstrip())].count("\n") + body
        parser = expat.ParserCreate()  # no namespace processing: as urdfdom's and Drake's TinyXML2 read it
        parser.Parse(text, True)  # a parse error names its line in the user's own file
    except expat.ExpatError as exc:
        raise ModelError(f"{path}: not a readable URDF: {expat.ErrorString(exc.code)} at line {exc.lineno}, column "
                         f"{exc.offset}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ModelError(f"{path}: not a readable URDF: {' '.join(str(exc).split())}") from None
    counts = dict.fromkeys(DROPPED, 0)

    def blank(match):  # the element goes, its lines stay: the engines' messages keep the file's line numbers
        counts[match.group(1) or match.group(2)] += 1
        return "\n" * match.group(0).count("\n")

    text = ELEMENTS.sub(blank, text)
    notes = []
    if counts["visual"] or counts["collision"]:
        notes.append(f"relacc dropped the URDF's {counts['visual']} visual and {counts['collision']} collision "
                     "elements (their meshes have no part in the dynamics, which read the inertials)")
    if counts["material"] or counts["gazebo"]:
        notes.append(f"relacc dropped the URDF's {counts['material']} robot-level material and {counts['gazebo']} "
                     "gazebo elements (appearance and a simulator's settings: no part in the dynamics)")
    if counts["mimic"]:
        notes.append(f"relacc dropped the URDF's {counts['mimic']} mimic element{'s' if counts['mimic'] > 1 else ''}: "
                     "the dynamics compared are the tree's without constraints, every joint free")
    note = "; ".join(notes) or None
    return text, note
