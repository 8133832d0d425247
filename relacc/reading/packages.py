"""ROS packages found without ROS: where a URDF's ``package://PKG/...`` and a xacro's ``$(find PKG)`` point.

Engine-free; shared by the URDF reader (:mod:`relacc.reading.urdf`) and the xacro expansion
(:mod:`relacc.reading.xacro`).
"""

from __future__ import annotations

import functools
from collections.abc import Iterator
from pathlib import Path


def package_folders(package: str, path: Path) -> Iterator[Path]:
    """The folders that may be the ROS package ``package`` for a file at ``path``, nearest first, found as ROS finds a
    package but without ROS: each folder above the file that is named ``package``, holds a folder so named, or holds
    a ``package.xml`` whose ``<name>`` is ``package``, itself or one folder down (ROS finds a package by that name, not
    by its folder's: a repository cloned under another name, as a CI checkout is, is still the package)."""
    seen: set[Path] = set()

    def new(found: Path) -> bool:
        fresh = found not in seen
        seen.add(found)
        return fresh

    for folder in path.resolve().parents:
        if folder.name == package and new(folder):
            yield folder
        if (folder / package).is_dir() and new(folder / package):
            yield folder / package
        for manifest in [folder / "package.xml", *sorted(folder.glob("*/package.xml"))]:  # read only when asked on
            if _package_name(manifest) == package and new(manifest.parent):
                yield manifest.parent


def _package_name(manifest: Path) -> str | None:
    """The ``<name>`` of a ROS ``package.xml``, or None (no such file, or not one that parses); read once per version
    of the file in a process (a URDF's meshes ask for every ``package.xml`` beside its package's, each)."""
    try:
        return _read_package_name(str(manifest), manifest.stat().st_mtime_ns)
    except OSError:
        return None


@functools.lru_cache(maxsize=1024)
def _read_package_name(manifest: str, mtime_ns: int) -> str | None:
    from xml.etree import ElementTree

    try:
        name = ElementTree.parse(manifest).getroot().find("name")
    except (OSError, ElementTree.ParseError):
        return None
    return None if name is None or name.text is None else name.text.strip()


__all__ = ["package_folders"]
