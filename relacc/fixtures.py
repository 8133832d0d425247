"""Model fixtures: the chain's TOML source of truth and the engine files made from it.

``models/two_body.toml`` holds geometry and inertia. :func:`render` turns it
into three engine files (Jinja2 templates in ``relacc/templates``):

* ``two_body.xml``: MJCF, free joint + three slides + ball (cases 1 and 2),
  loaded by MuJoCo and by Pinocchio (``buildModelFromMJCF``);
* ``two_body_euler.xml``: MJCF with slides and x, y, z hinges (case 3, MuJoCo);
* ``two_body_euler.urdf``: the same chain for Pinocchio (case 3).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from jinja2 import Environment, PackageLoader, StrictUndefined

from relacc import tomlfile
from relacc.chain import TwoBodyChain
from relacc.errors import FixtureError, InputError

MODEL_FILES = ("two_body.xml", "two_body_euler.xml", "two_body_euler.urdf")
"""The engine files written from one TOML source, in its directory."""


def models_dir() -> Path:
    """The ``models/`` directory: ``./models`` if it exists, else the one beside the package."""
    here = Path.cwd() / "models"
    return here if here.is_dir() else Path(__file__).resolve().parents[1] / "models"


def default_model_path() -> Path:
    """Path of the default source of truth, ``models/two_body.toml``."""
    return models_dir() / "two_body.toml"


@dataclass(frozen=True, eq=False)
class Fixture:
    """A chain read from its TOML source.

    Attributes:
        name: model name (the TOML's ``name``).
        chain: geometry and inertia as a :class:`TwoBodyChain`.
        source: path of the TOML file.
    """

    name: str
    chain: TwoBodyChain
    source: Path

    def path(self, filename: str) -> Path:
        """Path of one of the engine files beside the source (see ``MODEL_FILES``)."""
        return self.source.parent / filename


def load(path=None) -> Fixture:
    """Read a chain's TOML source of truth.

    Args:
        path: the TOML file; default ``models/two_body.toml``.

    Raises:
        FixtureError: missing file, TOML syntax error (line and column given),
            missing or invalid field (path, line and field named).
    """
    path = Path(path) if path is not None else default_model_path()
    data, text = tomlfile.read(path)

    def get(table, key):
        container = data if table is None else data.get(table)
        where = key if table is None else f"[{table}].{key}"
        if not isinstance(container, dict) or key not in container:
            raise FixtureError(f"{path}: missing field {where} (see models/two_body.toml for the schema)")
        return container[key]

    def field(table, key, convert):
        value = get(table, key)
        try:
            return convert(value)
        except InputError as exc:
            raise tomlfile.field_error(path, text, table, key, str(exc)) from None

    name = get(None, "name")
    if not isinstance(name, str) or not name:
        raise FixtureError(f"{path}: field name must be a non-empty string, got {name!r}")
    q2 = field("B2", "q2", lambda v: TwoBodyChain(q2=v, r2=(0, 0, 0)).q2)
    r2 = field("B2", "r2", lambda v: TwoBodyChain(q2=(0, 0, 0), r2=v).r2)
    r1 = field("B1", "r1", lambda v: TwoBodyChain(q2=q2, r2=r2, r1=v).r1)
    m1 = field("B1", "mass", lambda v: TwoBodyChain(q2=q2, r2=r2, m1=v).m1)
    m2 = field("B2", "mass", lambda v: TwoBodyChain(q2=q2, r2=r2, m2=v).m2)
    I1 = field("B1", "inertia", lambda v: TwoBodyChain(q2=q2, r2=r2, I1=v).I1)
    I2 = field("B2", "inertia", lambda v: TwoBodyChain(q2=q2, r2=r2, I2=v).I2)
    chain = TwoBodyChain(q2=q2, r2=r2, r1=r1, m1=m1, m2=m2, I1=I1, I2=I2)
    return Fixture(name=name, chain=chain, source=path)


def _num(x) -> str:
    """Shortest round-trip decimal of a float (``repr``), so files carry exact values."""
    return repr(float(x))


def _vec(v) -> str:
    return " ".join(_num(x) for x in v)


def _full_inertia(I) -> str:
    """MJCF ``fullinertia`` order: ixx iyy izz ixy ixz iyz."""
    return _vec([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]])


def _urdf_bodies(chain: TwoBodyChain):
    """The joint chains of the URDF: prismatic x, y, z then revolute x, y, z per body."""
    axes = ("1 0 0", "0 1 0", "0 0 1")
    bodies = []
    for body, parent, origin, prefix, angles, com, mass, I in (
        ("B1", "world", (0, 0, 0), "s1", "theta_B1", chain.r1, chain.m1, chain.I1),
        ("B2", "B1", chain.q2, "s2", "theta_B2", chain.r2, chain.m2, chain.I2),
    ):
        names = [f"{prefix}_{a}" for a in "xyz"] + [f"{angles}_{k}" for k in (1, 2, 3)]
        links = [f"{body}_{n}_link" for n in names[:-1]] + [body]
        joints = []
        for k, (jname, child) in enumerate(zip(names, links)):
            prismatic = k < 3
            joints.append(
                {
                    "name": jname,
                    "type": "prismatic" if prismatic else "revolute",
                    "parent": parent if k == 0 else links[k - 1],
                    "child": child,
                    "xyz": _vec(origin if k == 0 else (0, 0, 0)),
                    "axis": axes[k % 3],
                    "lower": "-1000.0",
                    "upper": "1000.0",
                }
            )
        bodies.append(
            {
                "name": body,
                "joints": joints,
                "com": _vec(com),
                "mass": _num(mass),
                "I": [[_num(x) for x in row] for row in np.asarray(I)],
            }
        )
    return bodies


def render(fixture: Fixture) -> dict[str, str]:
    """The text of each engine file (``MODEL_FILES``) for a fixture."""
    env = Environment(
        loader=PackageLoader("relacc", "templates"),
        autoescape=True,
        undefined=StrictUndefined,
        keep_trailing_newline=True,
    )
    c = fixture.chain
    values = {
        "name": fixture.name,
        "source": fixture.source.name,
        "q2": _vec(c.q2),
        "r2": _vec(c.r2),
        "r1": _vec(c.r1),
        "m1": _num(c.m1),
        "m2": _num(c.m2),
        "I1": _full_inertia(c.I1),
        "I2": _full_inertia(c.I2),
        "bodies": _urdf_bodies(c),
        # a capsule from the joint point to G2 needs some length; else a sphere at G2 (visual only)
        "b2_capsule": bool(np.linalg.norm(c.r2) >= 1e-3),
    }
    return {name: env.get_template(f"{name}.j2").render(**values) for name in MODEL_FILES}


def write(fixture: Fixture, check: bool = False) -> list[str]:
    """Write (or with ``check``, compare) the engine files beside the source.

    Returns:
        The names of files that were written, or with ``check`` that differ
        from what would be written (empty when all are up to date).
    """
    changed = []
    for name, text in render(fixture).items():
        target = fixture.path(name)
        current = target.read_text(encoding="utf-8") if target.exists() else None
        if current != text:
            changed.append(name)
            if not check:
                tmp = target.with_suffix(target.suffix + ".tmp")
                tmp.write_text(text, encoding="utf-8")
                tmp.replace(target)
    return changed
