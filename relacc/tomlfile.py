"""Reading TOML model and scene files with errors that name the path, the line and the field."""

from __future__ import annotations

import tomllib
from pathlib import Path

from relacc.errors import FixtureError


def read(path) -> tuple[dict, str]:
    """``(data, text)`` of a TOML file.

    Raises:
        FixtureError: unreadable file, or TOML syntax error (with its line and column).
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise FixtureError(f"{path}: cannot read the file ({getattr(exc, 'strerror', None) or exc})") from None
    try:
        return tomllib.loads(text), text
    except tomllib.TOMLDecodeError as exc:
        raise FixtureError(f"{path}: not valid TOML: {exc}") from None


def line_of(text: str, table: str | None, key: str) -> int | None:
    """1-based line of ``key =`` inside ``[table]`` (``None``: top level), if found."""
    current = None
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if line.startswith("[") and line.endswith("]"):
            current = line.strip("[]").strip()
        elif current == table and "=" in line and line.split("=", 1)[0].strip() == key:
            return number
    return None


def field_error(path, text: str, table: str | None, key: str, message: str) -> FixtureError:
    """A FixtureError naming the file, the line (when found) and the field."""
    line = line_of(text, table, key)
    at = f" line {line}," if line else ""
    where = key if table is None else f"[{table}].{key}"
    return FixtureError(f"{path}:{at} field {where}: {message}")
