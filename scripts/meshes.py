"""relacc's mass properties of every mesh file of the pinned wheels against MuJoCo's, in each of MuJoCo's four
``inertia`` modes (issue 53 item 6; docs/reading.md's "Meshes").

For each ``.stl``, ``.obj`` and ``.msh`` file under the description folders of ``scripts/corpus.py``'s pinned wheels,
and each mode, MuJoCo compiles a model of that mesh alone (a free body, density 1000) and relacc computes the same
with :mod:`relacc.reading.mesh` (an OBJ of several objects: its first, as MuJoCo reads it). Printed per mode: the
files compared, the worst relative differences of mass, mass centre (relative to the mesh's extent) and inertia
(relative to its largest entry), the files whose mass differs beyond 1e-12, and the files one of the two refuses
(MuJoCo refuses more: inconsistent face orientations in the exact mode, its own eigenvalue checks).

Run:  python scripts/meshes.py [--cache DIR] [--sample N --seed S]
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
MODES = ("legacy", "exact", "convex", "shell")


def files(cache: Path) -> list[Path]:
    """Every mesh file of the pinned wheels' description folders, sorted."""
    spec = importlib.util.spec_from_file_location("corpus", ROOT / "scripts" / "corpus.py")
    corpus = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(corpus)
    roots = corpus.fetch(cache)
    return sorted(p for root in roots.values() for suffix in ("stl", "obj", "msh") for p in root.rglob(f"*.{suffix}"))


def compare(path: Path, mode: str) -> dict:
    """One file in one mode: ``{"mujoco": error or None, "relacc": error or None, "mass", "com", "inertia"}``
    (relative differences, when both computed it)."""
    import contextlib
    import tempfile

    import mujoco

    from relacc.core.rotations import matrix_from_quaternion
    from relacc.reading.mesh import cached, mass_properties

    row: dict = {"mujoco": None, "relacc": None}
    xml = (f'<mujoco><asset><mesh name="m" file="{path}" inertia="{mode}"/></asset><worldbody><body><freejoint/>'
           '<geom type="mesh" mesh="m" density="1000"/></body></worldbody></mujoco>')
    try:  # in a scratch directory: MuJoCo appends its warnings to MUJOCO_LOG.TXT in the working directory
        with tempfile.TemporaryDirectory() as scratch, contextlib.chdir(scratch):
            m = mujoco.MjModel.from_xml_string(xml)
        R = matrix_from_quaternion(m.body_iquat[1])
        theirs = (m.body_mass[1], m.body_ipos[1].copy(), R @ np.diag(m.body_inertia[1]) @ R.T)
    except ValueError as exc:
        row["mujoco"] = str(exc).splitlines()[0]
    try:
        vertices, objects = cached(path, str(path))
        faces = objects[0] if objects else np.zeros((0, 3), dtype=np.int64)  # MuJoCo's reading: the first object
        props = mass_properties(vertices, faces, mode, str(path))
        ours = (1000 * props.measure, props.com, 1000 * props.inertia)
    except Exception as exc:  # noqa: BLE001 - a refusal, reported as such
        row["relacc"] = str(exc)
    if row["mujoco"] is None and row["relacc"] is None:
        extent = max(float(np.abs(vertices).max()), 1e-300)
        row.update(mass=abs(theirs[0] - ours[0]) / theirs[0], com=float(np.abs(theirs[1] - ours[1]).max()) / extent,
                   inertia=float(np.abs(theirs[2] - ours[2]).max()) / float(np.abs(theirs[2]).max()),
                   inertia_abs=float(np.abs(theirs[2] - ours[2]).max()), faces=len(faces),
                   inertia_max=float(np.abs(ours[2]).max()))
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cache", type=Path, default=ROOT / ".pytest_cache" / "d" / "relacc-corpus")
    parser.add_argument("--sample", type=int, default=0, help="only this many files, drawn with --seed")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    found = files(args.cache.resolve())
    if args.sample:
        rng = np.random.default_rng(args.seed)
        found = [found[i] for i in sorted(rng.choice(len(found), args.sample, replace=False))]
    for mode in MODES:
        rows = [(p, compare(p, mode)) for p in found]
        both = [r for _, r in rows if "mass" in r]
        worst = {k: max((r[k] for r in both), default=0.0) for k in ("mass", "com", "inertia")}
        beyond = sorted(p.name for p, r in rows if r.get("mass", 0.0) > 1e-12)
        refused = {"mujoco only": sum(r["mujoco"] is not None and r["relacc"] is None for _, r in rows),
                   "relacc only": sum(r["relacc"] is not None and r["mujoco"] is None for _, r in rows),
                   "both": sum(r["relacc"] is not None and r["mujoco"] is not None for _, r in rows)}
        print(f"{mode:7s} {len(both)} of {len(rows)} files compared; worst mass {worst['mass']:.2g}, centre "
              f"{worst['com']:.2g}, inertia {worst['inertia']:.2g}; mass beyond 1e-12: {beyond or 'none'}; "
              f"refused {refused}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
