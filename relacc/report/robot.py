"""The self-contained HTML page of ``relacc compare --out``: the model, the engines, the audit, the dynamics.

Plain data from :class:`relacc.validation.robots.RobotComparison` rendered by the report's Jinja2
environment (autoescaped) with the report's style; no script, no external reference.
"""

from __future__ import annotations

import datetime as dt

from relacc import files
from relacc.core.tolerances import EPS
from relacc.report import environment


def page_data(result) -> dict:
    """Plain data for ``robot.html.j2``."""
    data = result.as_json()
    engines = list(data["engines"])
    others = [e for e in engines if e != "mujoco" and data["engines"][e]["loaded"]]
    rows = []
    for quantity, row in data["dynamics"].items():
        cells = []
        for e in others:
            r = row["engines"].get(e)
            cells.append(None if r is None else {**r, "eps": None if r["max_error"] is None else r["max_error"] / EPS})
        rows.append({"quantity": quantity, "cells": cells})
    audit = [{"item": a["item"], "where": a["where"], "cells": [_show(a.get(e)) for e in engines],
              "cause": a["cause"]} for a in data["audit"]]
    bad = [c for r in rows for c in r["cells"] if c is not None and not c["ok"]]
    unexplained = [c for c in bad if c["cause"].startswith("not explained")]
    unexplained += [a for a in audit if "not explained" in a["cause"]]
    return {"n_bad": len(bad), "n_unexplained": len(unexplained), "model": data["model"], "urdf": data["urdf"],
            "engines": data["engines"], "names": engines,
            "others": others, "audit": audit, "dynamics": rows, "agree": data["agree"], "states": data["states"],
            "seed": data["seed"], "referee": data["referee"],
            "created": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}


def _show(value) -> str:
    """A value as text, every digit kept (nothing rounded): numbers by ``repr``, lists element by element."""
    if value is None:
        return "-"
    if isinstance(value, list):
        return "[" + ", ".join(_show(v) for v in value) + "]"
    return repr(value) if isinstance(value, float) else str(value)


def render(result) -> str:
    return environment().get_template("robot.html.j2").render(d=page_data(result))


def write(result, out) -> str:
    """Write the page atomically; returns its path."""
    path = files.check_output_file(out)
    files.write_text(path, render(result))
    return str(path)
