"""An MJCF without its mesh geometry, for an engine that cannot read the meshes (engine-free).

Drake's MJCF parser reads ``.obj`` meshes only and refuses a file naming any other (robosuite's and
gymnasium-robotics' ``.stl`` meshes). Where every body's inertia is explicit (an ``<inertial>``, unless
``<compiler inertiafromgeom="true">`` makes MuJoCo take it from the geoms anyway; or ``inertiafromgeom="false"``),
meshes have no part in the dynamics: :func:`without_meshes` gives the text with its mesh geoms and mesh assets
removed and a note saying so; files it includes are inlined first (MuJoCo's ``<include>``: the included file's
top-level children in place of the element). Where a body's inertia would come from a mesh, the meshes cannot be
dropped without changing the dynamics, and it says which body. A body whose ``<inertial>`` is zero (mass and
inertia), which Drake's parser cannot take, loses it with its geoms: it has no mass in either reading.

Drake's continuous plant also refuses a model with constraints when asked for its forward dynamics, and reads an
MJCF's ``<connect>`` and ``<weld>`` equalities as such. The dynamics relacc compares are the tree's without
constraints (the reading names them as not evaluated), so :func:`without_equality` gives the text without its
``<equality>`` elements (its includes inlined, its mesh directory made absolute so that the text reads its meshes
from anywhere), and both functions say what they left out.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from relacc.errors import ModelError


def _mesh_geom(geom, defaults: dict | None = None, cls: str = "main") -> bool:
    """Whether a ``<geom>`` is a mesh, its class's defaults (``defaults``: :func:`_geom_defaults`; ``cls`` its class,
    or its body's ``childclass``) under its own attributes: ``type="mesh"``, or a ``mesh`` and no other type."""
    attrs = {**(defaults or {}).get(geom.get("class") or cls, {}), **geom.attrib}
    return attrs.get("type") == "mesh" or (attrs.get("mesh") is not None and attrs.get("type") in (None, "mesh"))


def _geom_defaults(root) -> dict:
    """``{class: the <geom> attributes it gives}``, each class's ancestors' under its own; the top-level
    ``<default>`` is ``main`` (MuJoCo's names)."""
    out: dict = {}

    def walk(node, inherited: dict, name: str) -> None:
        mine = {**inherited, **(node.find("geom").attrib if node.find("geom") is not None else {})}
        out[name] = {**out.get(name, {}), **mine}
        for child in node.findall("default"):
            walk(child, mine, child.get("class", ""))

    for top in root.findall("default"):
        walk(top, out.get("main", {}), "main")
    return out


def _bodies_with_class(node, cls: str = "main"):
    """Each ``<body>`` under ``node`` with the class its geoms default to (its own or an ancestor's ``childclass``,
    a ``<frame>``'s too; ``main`` where none is given)."""
    for child in node:
        if child.tag in ("body", "frame", "worldbody"):
            inner = child.get("childclass") or cls
            if child.tag == "body":
                yield child, inner
            yield from _bodies_with_class(child, inner)


def without_meshes(path) -> tuple[str, str]:
    """``(text, note)``: the MJCF at ``path`` (its includes inlined) without mesh geoms and mesh assets, and without
    zero inertials and their bodies' geoms, and a one-line note of what of that was done.

    Raises:
        ModelError: the file or one it includes does not parse, or a body's inertia comes from a mesh (named).
    """
    path = Path(path)
    root = _read(path)
    included = _inline(root, path.parent, path)
    mode = "auto"
    for compiler in root.iter("compiler"):  # the last one given holds
        mode = compiler.get("inertiafromgeom", mode)
    defaults = _geom_defaults(root)
    classes = list(_bodies_with_class(root))
    for body, cls in classes if mode != "false" else ():
        explicit = body.find("inertial") is not None and mode != "true"  # "true": geoms override <inertial>
        if not explicit and any(_mesh_geom(g, defaults, cls) for g in body.findall("geom")):
            why = 'inertiafromgeom="true"' if mode == "true" else "no <inertial>"
            raise ModelError(f"{path}: body {body.get('name', '(unnamed)')!r} takes its inertia from a mesh "
                             f"({why}), so the meshes cannot be dropped")
    massless = _drop_zero_inertials(root) if mode != "true" else 0
    geoms = assets = 0
    meshes = {id(g) for body, cls in classes for g in body.findall("geom") if _mesh_geom(g, defaults, cls)}
    for parent in list(root.iter()):
        for child in list(parent):
            if child.tag == "geom" and (id(child) in meshes or _mesh_geom(child)) and parent.tag != "default":
                parent.remove(child)
                geoms += 1
            elif child.tag == "mesh" and parent.tag == "asset":
                parent.remove(child)
                assets += 1
    for compiler in root.iter("compiler"):
        compiler.attrib.pop("meshdir", None)
    if root.get("model") is None:
        root.set("model", path.stem)
    said = []
    constraints = _drop_equality(root)
    if constraints:
        said.append(_EQUALITY_NOTE.format(n=constraints, s="s" if constraints > 1 else ""))
    if geoms or assets:
        said.append(f"relacc dropped the file's {geoms} mesh geoms and {assets} mesh assets for this engine, which "
                    "cannot read the meshes: every body's inertia is explicit, so they have no part in the dynamics")
    if included:
        said.append(f"the {included} files it includes were inlined first, as MuJoCo reads them")
    if massless:
        said.append(f"the zero <inertial> of {massless} bodies went with their geoms: Drake's parser cannot take a "
                    "zero mass (its mass > 0 assertion), and a body with neither has no mass in Drake, as the zero "
                    "inertial gives it none in MuJoCo")
    return ET.tostring(root, encoding="unicode"), "; ".join(said) or "relacc gave this engine the file's own text"


_EQUALITY_NOTE = ("relacc left the file's {n} equality constraint{s} out of this engine's model (its continuous "
                  "plant refuses constraints; the dynamics compared are the tree's without them)")


def _drop_equality(root) -> int:
    """Remove every ``<equality>`` element's constraints; returns how many."""
    count = 0
    for parent in list(root.iter()):
        for child in list(parent):
            if child.tag == "equality":
                count += len(list(child))
                parent.remove(child)
    return count


def has_equality(path) -> bool:
    """Whether the MJCF at ``path`` or a file it includes has an ``<equality>`` constraint (False for a file that does
    not parse: the engine's parser then says why)."""
    path = Path(path)
    try:
        root = _read(path)
        _inline(root, path.parent, path)
    except ModelError:
        return False
    return any(len(list(e)) for e in root.iter("equality"))


def without_equality(path) -> tuple[str, str]:
    """``(text, note)``: the MJCF at ``path`` (its includes inlined) without its ``<equality>`` constraints, its
    ``meshdir`` (or ``assetdir``) absolute so that the text reads its meshes wherever it is parsed from, and a
    one-line note saying so.

    Raises:
        ModelError: the file or one it includes does not parse.
    """
    path = Path(path)
    root = _read(path)
    _inline(root, path.parent, path)
    _anywhere(root, path)
    n = _drop_equality(root)
    return ET.tostring(root, encoding="unicode"), _EQUALITY_NOTE.format(n=n, s="s" if n > 1 else "")


def without_keyframes(path) -> tuple[str, str] | None:
    """``(text, note)``: the MJCF at ``path`` without its ``<keyframe>`` elements (its includes left as they are: the
    engine this is for expands none), its directories absolute as in :func:`without_equality`; None when it has no
    keyframe. A keyframe is a named state, no part of the dynamics; Pinocchio's parser checks each against its own
    reading of the file and refuses the file when they differ in size (its reading of only the first body of
    ``<worldbody>`` leaves it fewer coordinates than the file has).

    Raises:
        ModelError: the file does not parse.
    """
    path = Path(path)
    root = _read(path)
    keys = [(parent, child) for parent in root.iter() for child in parent if child.tag == "keyframe"]
    if not keys:
        return None
    for parent, child in keys:
        parent.remove(child)
    _anywhere(root, path)
    n = sum(len(list(child)) for _, child in keys)
    return ET.tostring(root, encoding="unicode"), (
        f"relacc left the file's {n} keyframe{'s' if n != 1 else ''} out of this engine's model: its parser checks "
        "each against its own reading of the file and refused them (a keyframe is a named state, no part of the "
        "dynamics)")


def with_defaults_merged(path) -> tuple[str, str] | None:
    """``(text, note)``: the MJCF at ``path`` with its top-level ``<default>`` elements made one (the later ones'
    classes moved into the first, in order), its directories absolute as in :func:`without_equality`; None when it has
    one such element, or when a later one sets defaults of its own (elements other than classes), which a merge could
    reorder. MuJoCo reads every top-level ``<default>`` as the main class's; Pinocchio's parser reads the first alone
    and refuses a class defined in a later one with C++'s bare ``unordered_map::at`` (SO-ARM100's SO-101 files).

    Raises:
        ModelError: the file does not parse.
    """
    path = Path(path)
    root = _read(path)
    tops = root.findall("default")
    if len(tops) < 2 or any(child.tag != "default" for top in tops[1:] for child in top):
        return None
    classes = [child for top in tops[1:] for child in top]
    for top in tops[1:]:
        root.remove(top)
    tops[0].extend(classes)
    _anywhere(root, path)
    names = ", ".join(str(c.get("class")) for c in classes)
    return ET.tostring(root, encoding="unicode"), (
        f"relacc gave this engine the file's {len(tops)} top-level <default> elements as one: its parser reads only "
        f"the first, and refused the classes of the others ({names}); MuJoCo reads them all as the main class's")


def _anywhere(root, path: Path) -> None:
    """``root``'s ``meshdir`` (or ``assetdir``, ``texturedir``) made absolute, so that its text reads its files
    wherever it is parsed from; the model named after the file where it has no name."""
    compilers = list(root.iter("compiler")) or [ET.SubElement(root, "compiler")]
    for compiler in compilers:
        for key in ("meshdir", "assetdir", "texturedir"):
            if key in compiler.attrib or key == "meshdir":
                value = compiler.get(key, compiler.get("assetdir", ""))
                compiler.set(key, str((path.parent / value).resolve()))
    if root.get("model") is None:
        root.set("model", path.stem)


def _zero(inertial) -> bool:
    """An ``<inertial>`` of zero mass and zero inertia (robosuite's mounts and fetch's gripper links)."""
    values = [inertial.get("mass", "0"), inertial.get("diaginertia", "0 0 0"), inertial.get("fullinertia", "0")]
    try:
        return all(float(x) == 0 for v in values for x in v.split())
    except ValueError:
        return False


def has_zero_inertial(path) -> bool:
    """Whether the MJCF at ``path`` or a file it includes gives a body a zero ``<inertial>`` (False for a file that
    does not parse: the engine's parser then says why)."""
    path = Path(path)
    try:
        root = _read(path)
        _inline(root, path.parent, path)
    except ModelError:
        return False
    return any(_zero(i) for i in root.iter("inertial"))


def _drop_zero_inertials(root) -> int:
    """Remove each zero ``<inertial>`` and its body's geoms (explicit inertia: the geoms have no part in the
    dynamics); returns how many bodies."""
    count = 0
    for body in root.iter("body"):
        inertial = body.find("inertial")
        if inertial is not None and _zero(inertial):
            body.remove(inertial)
            for geom in body.findall("geom"):
                body.remove(geom)
            count += 1
    return count


def _read(path: Path):
    try:
        return ET.parse(path).getroot()
    except (ET.ParseError, OSError) as exc:
        raise ModelError(f"{path}: not readable XML: {' '.join(str(exc).split())}") from None


MAX_DEPTH = 20
"""Includes nested deeper than this are refused (a file that includes itself)."""


def _inline(root, directory: Path, path: Path, depth: int = 0, seen: set | None = None) -> int:
    """Replace every ``<include file="...">`` under ``root`` by the children of the included file's root element,
    recursively, as MuJoCo does (a relative name is taken from the main file's directory; a file is included once per
    model, a second ``<include>`` of it refused); returns how many files."""
    seen = set() if seen is None else seen
    count = 0
    for parent in list(root.iter()):
        for k, child in reversed(list(enumerate(parent))):
            if child.tag != "include":
                continue
            if depth >= MAX_DEPTH:
                raise ModelError(f"{path}: includes nested more than {MAX_DEPTH} deep (a file that includes itself?)")
            name = child.get("file")
            if not name:
                raise ModelError(f"{path}: an <include> without a file")
            if (directory / name).resolve() in seen:
                raise ModelError(f"{path}: <include file={name!r}>: that file is already included; MuJoCo includes a "
                                 "file once per model")
            seen.add((directory / name).resolve())
            included = _read(directory / name)
            count += 1 + _inline(included, directory, directory / name, depth + 1, seen)
            parent.remove(child)
            for i, grandchild in enumerate(list(included)):
                parent.insert(k + i, grandchild)
    return count
