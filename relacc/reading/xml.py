"""An XML description read into nodes that remember their file and line (the standard library's expat).

Every element relacc reads from a model file keeps where it came from, so that any difference found later names
the element of the file it comes from (:attr:`Node.place`). What a robot description's own tools accept, this
accepts too: whitespace before the XML declaration and NUL bytes after the document (both seen in published URDFs;
MuJoCo reads them) are left out, and the reading's notes say so; comments are left out before parsing (XML forbids
``--`` inside a comment, which MuJoCo's parser and published models, relacc's own examples among them, allow).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import overload
from xml.parsers import expat

from relacc.errors import ModelError
from relacc.files import regular_file


@dataclass(eq=False)
class Node:
    """One XML element: ``tag``, ``attrib`` (as written), ``children`` (elements only, in order), ``file`` and
    ``line`` (1-based) of its start tag."""

    tag: str
    attrib: dict
    file: str
    line: int
    children: list = field(default_factory=list)

    @property
    def place(self) -> str:
        """``file:line`` of the element."""
        return f"{self.file}:{self.line}"

    def get(self, key: str, default=None):
        return self.attrib.get(key, default)

    def find(self, tag: str):
        """The first child with ``tag``, or None."""
        return next((c for c in self.children if c.tag == tag), None)

    def findall(self, tag: str) -> list:
        return [c for c in self.children if c.tag == tag]

    def iter(self, tag: str | None = None):
        """This element and every element below it, in document order (``tag``: only those)."""
        if tag is None or self.tag == tag:
            yield self
        for c in self.children:
            yield from c.iter(tag)


COMMENT = re.compile(r"<!--.*?-->", re.S)


def parse_text(text: str, file: str, notes: list | None = None) -> Node:
    """The root :class:`Node` of XML ``text`` read from ``file`` (for the places). ``notes`` gets a line for what was
    left out (leading whitespace, trailing NUL bytes).

    Raises:
        ModelError: the text is not well-formed XML (expat's message, with the line and column).
    """
    stripped = text.lstrip()
    if len(stripped) != len(text) and notes is not None and stripped.startswith("<?xml"):
        notes.append(f"{file}: whitespace before the XML declaration left out (as MuJoCo reads it)")
    lead = text[:len(text) - len(stripped)].count("\n")  # lines left out: the places stay the file's own
    body = stripped.rstrip("\x00")
    if len(body) != len(stripped) and notes is not None:
        notes.append(f"{file}: {len(stripped) - len(body)} NUL bytes after the document left out (as MuJoCo reads it)")
    body = COMMENT.sub(lambda m: "\n" * m.group(0).count("\n"), body)  # its lines stay: places keep the file's
    parser = expat.ParserCreate()
    stack: list[Node] = []
    root: list[Node] = []

    def start(tag, attrib):
        node = Node(tag, dict(attrib), file, parser.CurrentLineNumber + lead)
        (stack[-1].children if stack else root).append(node)
        stack.append(node)

    def end(tag):
        stack.pop()

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    try:
        parser.Parse(body, True)
    except expat.ExpatError as exc:
        raise ModelError(f"{file}: not well-formed XML: {expat.ErrorString(exc.code)} at line {exc.lineno + lead}, "
                         f"column {exc.offset}") from None
    if not root:
        raise ModelError(f"{file}: no XML element in it")
    return root[0]


def parse_file(path, notes: list | None = None) -> Node:
    """:func:`parse_text` of a file (UTF-8).

    Raises:
        ModelError: a missing, unreadable or non-UTF-8 file, or text that is not XML.
    """
    path = regular_file(path, ModelError, "model file")
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise ModelError(f"{path}: cannot read it ({exc.strerror or exc})") from None
    if not raw.strip(b"\x00 \t\r\n"):
        raise ModelError(f"{path}: the file is empty")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ModelError(f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    return parse_text(text, str(path), notes)


@overload
def numbers(node: Node, key: str, count: int | None = None, default: None = None) -> list[float] | None: ...


@overload
def numbers(node: Node, key: str, count: int | None, default: list[float]) -> list[float]: ...


def numbers(node: Node, key: str, count: int | None = None, default: list[float] | None = None) -> list[float] | None:
    """The attribute ``key`` of ``node`` as ``count`` real numbers (any count when None), or ``default`` when absent.

    Numbers are separated by whitespace, as URDF and MJCF specify; a comma is refused, as urdfdom, MuJoCo and Drake
    refuse it (reading ``"0.07, 0, -0.69"`` as three numbers would make a model no engine reads).

    Raises:
        ModelError: not numbers, separated by commas, the wrong count, or a NaN or infinity (naming the element, its
            place and the attribute).
    """
    text = node.get(key)
    if text is None:
        return default
    if "," in text:
        raise ModelError(f"{node.place}: <{node.tag}> {key}={text!r} separates its numbers with commas; URDF and MJCF "
                         "separate them with spaces (urdfdom, MuJoCo and Drake refuse commas too)")
    try:
        values = [float(x) for x in text.split()]
    except ValueError:
        raise ModelError(f"{node.place}: <{node.tag}> {key}={text!r} is not a list of numbers") from None
    if count is not None and len(values) != count:
        raise ModelError(f"{node.place}: <{node.tag}> {key}={text!r} has {len(values)} numbers; expected {count}")
    bad = [v for v in values if v != v or v in (float("inf"), float("-inf"))]
    if bad:
        raise ModelError(f"{node.place}: <{node.tag}> {key}={text!r} holds {bad[0]}; expected finite numbers")
    return values


def required_numbers(node: Node, key: str, count: int | None = None) -> list[float]:
    """:func:`numbers` of an attribute the element must have.

    Raises:
        ModelError: it is absent, or as :func:`numbers`.
    """
    values = numbers(node, key, count)
    if values is None:
        raise ModelError(f"{node.place}: <{node.tag}> needs {key}")
    return values


@overload
def number(node: Node, key: str, default: None = None) -> float | None: ...


@overload
def number(node: Node, key: str, default: float) -> float: ...


def number(node: Node, key: str, default: float | None = None) -> float | None:
    """One real number (see :func:`numbers`)."""
    values = numbers(node, key, 1)
    return default if values is None else values[0]
