"""ROS packages found without ROS: where a URDF's ``package://PKG/...`` and a xacro's ``$(find PKG)`` point.

Engine-free; shared by the URDF reader (:mod:`relacc.reading.urdf`) and the xacro expansion
(:mod:`relacc.reading.xacro`).
"""

from __future__ import annotations

import functools
from collections.abc import Iterator
from pathlib import Path

PACKAGE_PATH = "ROS_PACKAGE_PATH"
"""The environment variable of folders (``os.pathsep``-separated) searched for packages after those around the file,
as ROS 1's ``rospack`` searches them."""

IGNORE_MARKERS = ("COLCON_IGNORE", "CATKIN_IGNORE", "AMENT_IGNORE")
"""A folder holding one of these is not searched (colcon's and catkin's rule)."""

CRAWL_LIMIT = 20_000
"""Folders a search of one tree visits at most (a workspace of hundreds of packages has a few thousand)."""


def package_folders(package: str, path: Path) -> Iterator[Path]:
    """The folders that may be the ROS package ``package`` for a file at ``path``, nearest first, found as ROS finds a
    package but without ROS:

    * each folder above the file that holds a ``package.xml`` whose ``<name>`` is ``package``, itself or one folder
      down (ROS finds a package by that name, not by its folder's: a repository cloned under another name, as a CI
      checkout is, is still the package), then, at the same level, a folder named ``package`` whose own
      ``package.xml``, if any, names no other (a package's Python module, ``ugv_description/ugv_description/``, is
      not the package: LI-DC-Long-Island-Deer-Chaser/ugv_description);
    * then the packages of the file's repository (the nearest folder above it holding ``.git``) and of each folder of
      :data:`PACKAGE_PATH`, searched as colcon and ``rospack`` search a workspace: every depth, a folder holding a
      ``package.xml`` is a package and is not searched further, hidden folders and those holding a marker of
      :data:`IGNORE_MARKERS` are skipped. A monorepo of descriptions (fiveages-sim/robot_descriptions: a humanoid's
      xacro naming the arm package two folders across) is one workspace.
    """
    seen: set[Path] = set()

    def new(found: Path) -> bool:
        fresh = found not in seen
        seen.add(found)
        return fresh

    for folder in path.resolve().parents:
        for manifest in [folder / "package.xml", *sorted(folder.glob("*/package.xml"))]:  # read only when asked on
            if _package_name(manifest) == package and new(manifest.parent):
                yield manifest.parent
        for named in (folder, folder / package):  # a folder of the package's name, without a manifest naming another
            if named.name == package and named.is_dir() and _package_name(named / "package.xml") in (None, package) \
                    and new(named):
                yield named
    for root in _workspaces(path):
        found = _crawled(str(root))[0].get(package)
        if found is not None and new(Path(found)):
            yield Path(found)


def unfinished_searches(path: Path) -> list[str]:
    """The workspaces of a file at ``path`` (:func:`package_folders`) whose search stopped at :data:`CRAWL_LIMIT`
    folders: a package not found may lie beyond it (said with the error, never silently)."""
    return [str(root) for root in _workspaces(path) if not _crawled(str(root))[1]]


def _workspaces(path: Path) -> list[Path]:
    """The file's repository (the nearest folder above it holding ``.git``), then the folders of
    :data:`PACKAGE_PATH`."""
    import os

    roots = [next((f for f in path.resolve().parents if (f / ".git").exists()), None)]
    roots += [Path(p) for p in os.environ.get(PACKAGE_PATH, "").split(os.pathsep) if p]
    return [r for r in roots if r is not None and r.is_dir()]


@functools.lru_cache(maxsize=64)
def _crawled(root: str) -> tuple[dict[str, str], bool]:
    """``({package name: folder}, whether the search ended before the limit)`` of every package below ``root``
    (:func:`package_folders`), the first of a name kept; searched once per process."""
    import os

    found: dict[str, str] = {}
    pending, visited = [root], 0
    while pending and visited < CRAWL_LIMIT:
        folder = pending.pop()
        visited += 1
        try:
            entries = sorted(os.scandir(folder), key=lambda e: e.name)
        except OSError:
            continue
        names = {e.name for e in entries}
        if any(m in names for m in IGNORE_MARKERS):
            continue
        if "package.xml" in names:
            name = _package_name(Path(folder) / "package.xml")
            if name is not None:
                found.setdefault(name, folder)
                continue
        pending += [e.path for e in reversed(entries) if e.is_dir(follow_symlinks=False) and not e.name.startswith(".")]
    return found, not pending


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


__all__ = ["package_folders", "unfinished_searches"]
