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

import numpy as np

from relacc.errors import ModelError
from relacc.files import note_input, regular_file


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
        """``file:line`` of the element (the file alone where its line is not known: a xacro macro's element)."""
        return f"{self.file}:{self.line}" if self.line > 0 else self.file

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

MAX_DEPTH = 500
"""TinyXML2's ``TINYXML2_MAX_ELEMENT_DEPTH``: MuJoCo and urdfdom refuse a document whose elements nest this deep
(measured: MuJoCo reads 496 nested bodies, each with a geom, under <mujoco><worldbody>: 499 levels; and refuses
497)."""


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
        if len(stack) + 1 >= MAX_DEPTH:
            raise ModelError(f"{file}:{parser.CurrentLineNumber + lead}: elements nested {MAX_DEPTH} deep or more; "
                             "TinyXML2, the XML parser of MuJoCo and urdfdom, refuses it (XML_ELEMENT_DEPTH_EXCEEDED)")
        node = Node(tag, dict(attrib), file, parser.CurrentLineNumber + lead)
        (stack[-1].children if stack else root).append(node)
        stack.append(node)

    def end(tag):
        stack.pop()

    def declared(kind):
        def refuse(*args):
            raise ModelError(f"{file}:{parser.CurrentLineNumber + lead}: a DTD {kind} declaration; MuJoCo's and "
                             "urdfdom's XML parser (TinyXML2) apply no DTD, so the engines do not read what it "
                             "declares: write the values out in the elements")
        return refuse

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.EntityDeclHandler = declared("<!ENTITY>")
    parser.AttlistDeclHandler = declared("<!ATTLIST>")
    parser.ElementDeclHandler = declared("<!ELEMENT>")
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
    note_input(path)  # a command's output may not replace it (an <include>d file, say)
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
        values = [real(x) for x in text.split()]
    except ValueError:
        raise ModelError(f"{node.place}: <{node.tag}> {key}={text!r} is not a list of numbers (written as C's strtod "
                         "reads them, which MuJoCo and urdfdom use: ASCII digits, an optional sign, point and "
                         "exponent, or a hexadecimal 0x...p... number)") from None
    if count is not None and len(values) != count:
        raise ModelError(f"{node.place}: <{node.tag}> {key}={text!r} has {len(values)} numbers; expected {count}")
    bad = [v for v in values if v != v or v in (float("inf"), float("-inf"))]
    if bad:
        raise ModelError(f"{node.place}: <{node.tag}> {key}={text!r} holds {bad[0]}; expected finite numbers")
    huge = [v for v in values if abs(v) > MAX_MAGNITUDE]
    if huge:
        raise ModelError(f"{node.place}: <{node.tag}> {key}={text!r} holds {huge[0]:g}, beyond {MAX_MAGNITUDE:g}: the "
                         "dynamics multiply a model's numbers by each other and by squared speeds, which overflows "
                         "float64 there; relacc reads magnitudes up to that")
    return values


MAX_MAGNITUDE = 1e100
"""The largest magnitude of a number relacc reads from a model file. A mass matrix entry is a mass times a squared
length (or an inertia), and the bias forces that times a squared speed: with every number within 1e100 (no robot is
within eighty orders of magnitude of it) and speeds within 1e50, none of them overflows float64 (1.8e308)."""

DECIMAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII)
HEXADECIMAL = re.compile(r"[+-]?0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?", re.ASCII)
SPECIAL = re.compile(r"[+-]?(?:inf|infinity|nan)", re.ASCII | re.IGNORECASE)


def real(token: str) -> float:
    """One number as C's ``strtod`` reads a whole token, which MuJoCo's and urdfdom's parsers use: ASCII decimal digits
    with an optional sign, point and exponent, a hexadecimal ``0x1.8p3``, or an infinity or NaN (which
    :func:`numbers` then refuses). Python's own ``float`` reads more (``1_0`` as 10, full-width and Arabic-Indic
    digits): those a file's engines refuse, and so does relacc.

    Raises:
        ValueError: not such a number.
    """
    if DECIMAL.fullmatch(token) or SPECIAL.fullmatch(token):
        return float(token)
    if HEXADECIMAL.fullmatch(token):
        sign = -1.0 if token.startswith("-") else 1.0
        body = token.lstrip("+-")
        return sign * float.fromhex(body if "p" in body.lower() else body + "p0")
    raise ValueError(f"not a number: {token!r}")


WRITTEN_DIGITS = 6
"""The significant digits a number written with fewer is taken to hold: a hand-written ``0.1`` is 0.1 to at least
this many (MuJoCo's saved XML prints 6), so that the rounding a file's digits allow never excuses a plain violation."""


def rounding(node: Node, key: str) -> list[float]:
    """Each number of the attribute ``key``: half a unit in the last digit written (``8.53333333333e-07``: 5e-19),
    at most half a unit in the :data:`WRITTEN_DIGITS`-th significant digit; 0 for an exact zero and for an absent
    attribute. What a value written to that many digits may differ from the one meant by (the file's own rounding)."""
    text = node.get(key)
    if text is None:
        return []
    out = []
    for token in text.split():
        value = abs(real(token))
        mantissa, _, exponent = token.lower().lstrip("+-").partition("e")
        if "x" in mantissa or value == 0 or value != value or value == float("inf"):
            out.append(0.0)
            continue
        decimals = len(mantissa.partition(".")[2])
        half = 0.5 * 10.0 ** (int(exponent or 0) - decimals)
        cap = 0.5 * 10.0 ** (int(np.floor(np.log10(value))) - WRITTEN_DIGITS + 1)
        out.append(min(half, cap))
    return out


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
