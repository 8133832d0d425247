"""The self-contained HTML page of ``relacc compare --out``: the model, the engines, the audit, the dynamics (several
models: one page, a row per model linked to its sections).

Plain data from :class:`relacc.validation.robots.RobotComparison` rendered by the report's Jinja2
environment (autoescaped) with the report's style; no script, no external reference.
"""

from __future__ import annotations

import datetime as dt

from relacc import files
from relacc.core.tolerances import EPS
from relacc.errors import RelaccError
from relacc.report.build import environment
from relacc.validation.robots.causes import CauseKind


def page_data(result) -> dict:
    """Plain data for ``robot.html.j2``: relacc's reading first, then each engine; every dynamics row (relacc's cases
    1 and 3 included) in a column of its evaluator."""
    data = result.as_json()
    names = list(data["engines"])
    columns = [e for e in names if e != data["reference"] and data["engines"][e]["loaded"]]
    columns += sorted({e for row in data["dynamics"].values() for e in row["engines"]} - set(columns))
    rows = []
    for quantity, row in data["dynamics"].items():
        cells = []
        for e in columns:
            r = row["engines"].get(e)
            cells.append(None if r is None else {**r, "eps": None if r["max_error"] is None else r["max_error"] / EPS})
        rows.append({"quantity": quantity, "cells": cells, "tolerance": row["tolerance"]})
    audit = [{"item": a["item"], "where": a["where"], "cells": [_cell(a.get(e)) for e in names],
              "cause": a["cause"], "kind": a["cause_kind"], "place": a["place"]} for a in data["audit"]]
    bad = [c for r in rows for c in r["cells"] if c is not None and not c["ok"]]
    unexplained = [c for c in bad if c["cause_kind"] == CauseKind.NOT_EXPLAINED]
    unexplained += [a for a in audit if CauseKind.NOT_EXPLAINED in a["kind"]]
    from relacc.report.drawing import drawing

    return {"n_bad": len(bad), "compared": data["compared"], "digits": SHOWN_DIGITS,
            "drawing": drawing(data["geometry"], data["audit"], data["reference"]),
            "n_unexplained": len(unexplained), "model": data["model"], "urdf": data["urdf"],
            "engines": data["engines"], "names": names, "reference": data["reference"],
            "others": columns, "audit": audit, "dynamics": rows, "agree": data["agree"], "states": data["states"],
            "seed": data["seed"], "referee": data["referee"], "findings": data["findings"], "taken": data["taken"],
            "unevaluated": data["not_evaluated"], "notes": data["notes"], "odd": odd_ones_out(data["referee"]),
            "absent": [e for e in names if not data["engines"][e]["loaded"]],
            "created": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}


def odd_ones_out(referee) -> list[dict]:
    """The referee at a glance: ``[{"who": odd ones out (text), "quantities": [...], "agreeing": [...]}]``, one entry
    per distinct verdict shape, and the splits as ``who`` "no majority"."""
    out: dict = {}
    for v in referee:
        key = (tuple(v["odd_ones_out"]), tuple(v["agreeing"])) if v["agreeing"] else ("no majority", ())
        entry = out.setdefault(key, {"who": ", ".join(v["odd_ones_out"]) if v["agreeing"] else "no majority",
                                     "agreeing": list(v["agreeing"]), "quantities": []})
        entry["quantities"].append(v["quantity"])
    return list(out.values())


SHOWN_DIGITS = 6
"""Significant digits of the audit's values on the page (each cell's title, and the JSON, keep every digit)."""


def _show(value, digits: int | None = None) -> str:
    """A value as text: numbers to ``digits`` significant digits, or every digit (``repr``) when None; lists element
    by element."""
    if value is None:
        return "-"
    if isinstance(value, list):
        return "[" + ", ".join(_show(v, digits) for v in value) + "]"
    if isinstance(value, float):
        return repr(value) if digits is None else f"{value:.{digits}g}"
    return str(value)


def _cell(value) -> dict:
    """An audit cell: ``{"shown": 6 significant digits, "full": every digit}``."""
    return {"shown": _show(value, SHOWN_DIGITS), "full": _show(value)}


def render(result) -> str:
    return environment().get_template("robot.html.j2").render(d=page_data(result))


def write(result, out) -> str:
    """Write the page atomically; returns its path."""
    path = files.check_output_file(out)
    files.write_text(path, render(result))
    return str(path)


def render_many(results) -> str:
    """One page for several models: ``results`` ``[(model path, RobotComparison or the RelaccError that stopped
    it)]``; a summary table with a row per model, linked to each compared model's sections."""
    rows: list[dict] = []
    for model, r in results:
        if isinstance(r, Exception):  # an input error (2), or relacc's own failure on that file (3)
            rows.append({"model": str(model), "exit": 2 if isinstance(r, RelaccError) else 3, "error": str(r),
                         "d": None})
        else:
            rows.append({"model": str(model), "exit": r.exit_code, "error": None, "d": page_data(r)})
    codes = [r["exit"] for r in rows]
    counts = {"agree": codes.count(0), "disagree": codes.count(1), "cannot": codes.count(2) + codes.count(3)}
    summary = f"{counts['agree']} agree, {counts['disagree']} disagree, {counts['cannot']} cannot be compared"
    return environment().get_template("robots.html.j2").render(
        rows=rows, summary=summary, counts=counts,
        created=dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"))


def write_many(results, out) -> str:
    """Write the page of several models atomically; returns its path."""
    path = files.check_output_file(out)
    files.write_text(path, render_many(results))
    return str(path)
