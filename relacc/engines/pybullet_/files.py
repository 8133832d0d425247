"""The URDF text PyBullet is given where it cannot be the user's file itself (imports no engine): a xacro's
expansion, or a copy with its joints unlimited for stepping, each written for the moment of loading to a temporary
directory (never beside the user's file), its mesh files named by absolute path so that Bullet finds them from
there."""

from __future__ import annotations

import contextlib
import os
import tempfile
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path


def text_for_pybullet(path: Path, unlimited: bool = False) -> str:
    """The URDF (or a ``.xacro``'s expansion, :mod:`relacc.reading.xacro`) at ``path`` with its meshes named by
    absolute path, a relative name from the file's directory even where it is missing there (Bullet would look for it
    in the working directory too: hello-robot's ``stretch_main.xacro`` names ``./meshes/...`` from the folder above
    its own, and PyBullet read it from there and failed from anywhere else); ``unlimited``: its revolute joints made
    continuous and its prismatic joints given ``lower > upper`` (Bullet's importer then makes no limit constraint)."""
    from relacc.reading.urdf import resolve_uri
    from relacc.reading.xacro import expand, is_xacro

    root = ET.fromstring(expand(path)) if is_xacro(path) else ET.parse(path).getroot()
    if unlimited:
        for joint in root.iter("joint"):
            if joint.get("type") == "revolute":
                joint.set("type", "continuous")
            elif joint.get("type") == "prismatic":
                limit = joint.find("limit")
                if limit is None:
                    limit = ET.SubElement(joint, "limit", {"effort": "0", "velocity": "0"})
                limit.set("lower", "1")
                limit.set("upper", "-1")
    for mesh in root.iter("mesh"):
        uri = mesh.get("filename") or ""
        target = resolve_uri(uri, path)
        if target is None and "://" not in uri:  # not beside the file: named there all the same, so that Bullet does
            target = path.parent / uri  # not find it from the working directory (it looks there too)
        if target is not None:
            mesh.set("filename", str(target.resolve()))
    return ET.tostring(root, encoding="unicode")


@contextlib.contextmanager
def placed_copy(path: Path, unlimited: bool = False) -> Iterator[str]:
    """The path of :func:`text_for_pybullet` written to a temporary directory, removed when the block ends."""
    with tempfile.TemporaryDirectory(prefix="relacc-pybullet-") as folder:
        copy = os.path.join(folder, "model.urdf")
        with open(copy, "w", encoding="utf-8") as out:
            out.write(text_for_pybullet(path, unlimited))
        yield copy
