"""The self-contained HTML page of ``relacc diff A B --out``: the two files' trees of moving parts side by side, row
by row as matched, each difference numbered at its element and listed below with its kind, values and places.

Plain data from :class:`relacc.validation.diff.Diff` rendered by the report's Jinja2 environment (autoescaped) with
the report's style; no script, no external reference. The trees are HTML (an indented list in each column of one
table), so the browser lays out every label: none overlaps another.
"""

from __future__ import annotations

import datetime as dt

from relacc.report.build import environment


def _children(parts: list[dict]) -> dict[int, list[int]]:
    out: dict[int, list[int]] = {}
    for i, part in enumerate(parts):
        out.setdefault(part["parent"], []).append(i)
    return out


def _depths(parts: list[dict]) -> list[int]:
    depth = [0] * len(parts)
    for i, part in enumerate(parts):  # parents first (file order)
        depth[i] = 0 if part["parent"] < 0 else depth[part["parent"]] + 1
    return depth


def rows(trees: dict) -> list[dict]:
    """The page's rows: ``{"a": part index or None, "b": ..., "how": how matched or None}``: A's parts in tree order
    (depth first, file order), each beside its counterpart; a part of B without one right after its parent's row (at
    the end where that parent has no row)."""
    parts_a, parts_b = trees["a"]["parts"], trees["b"]["parts"]
    of_a = {i: (k, how) for i, k, how in trees["pairs"]}
    out: list[dict] = []
    children = _children(parts_a)
    stack = list(reversed(children.get(-1, [])))
    while stack:
        i = stack.pop()
        k, how = of_a.get(i, (None, None))
        out.append({"a": i, "b": k, "how": how})
        stack += reversed(children.get(i, []))
    matched_b = {k for _, k, _ in trees["pairs"]}
    for k, part in enumerate(parts_b):
        if k in matched_b:
            continue
        at = next((n for n, row in enumerate(out) if row["b"] is not None and row["b"] == part["parent"]), None)
        out.insert(len(out) if at is None else at + 1, {"a": None, "b": k, "how": None})
    return out


def _where(difference: dict, by_a: dict, by_b: dict) -> int | None:
    """The row (index) of a difference's element: a part's or a joint's name (``A / B`` where they differ; a fused
    body's suffix ``(fused body X)`` left out); None for the whole robot and the world."""
    element = difference["element"]
    if element.endswith(")") and " (" in element and "fused body" in element:
        element = element[:element.index(" (")]
    if element in by_a:
        return by_a[element]
    if element in by_b:
        return by_b[element]
    if " / " in element:
        a, b = element.split(" / ", 1)
        return by_a.get(a, by_b.get(b))
    return None


def page_data(result) -> dict:
    """Plain data for ``diff.html.j2``: the verdict, the rows of the two trees with each difference's number at its
    element, the differences, the dynamics, the notes and the engines' verdicts."""
    data = result.as_json()
    trees = data["trees"]
    table = rows(trees)
    by_a: dict = {}
    by_b: dict = {}
    for n, row in enumerate(table, start=1):  # row 0 is the world's
        for side, names in (("a", by_a), ("b", by_b)):
            if row[side] is None:
                continue
            part = trees[side]["parts"][row[side]]
            names.setdefault(part["name"], n)
            for joint, _ in part["joints"]:
                names.setdefault(joint, n)
    differences = []
    marks: dict[int, list[int]] = {}
    for number, d in enumerate(data["differences"], start=1):
        at = _where(d, by_a, by_b)
        at = 0 if at is None else at
        marks.setdefault(at, []).append(number)
        differences.append({**d, "number": number, "row": at})
    depth = {"a": _depths(trees["a"]["parts"]), "b": _depths(trees["b"]["parts"])}

    def cell(side: str, index: int | None) -> dict | None:
        if index is None:
            return None
        part = trees[side]["parts"][index]
        return {"name": part["name"] or "(unnamed)", "depth": depth[side][index] + 1,
                "fused": part["bodies"][1:], "joints": [f"{name} ({kind})" for name, kind in part["joints"]]}

    shown = [{"a": {"name": "world", "depth": 0, "fused": trees["a"]["world"], "joints": []},
              "b": {"name": "world", "depth": 0, "fused": trees["b"]["world"], "joints": []},
              "how": None, "marks": marks.get(0, [])}]
    shown += [{"a": cell("a", row["a"]), "b": cell("b", row["b"]), "how": row["how"], "marks": marks.get(n, [])}
              for n, row in enumerate(table, start=1)]
    from relacc.validation.diff_dynamics import row_words

    return {"a": data["a"], "b": data["b"], "same": data["same"], "headline": result.verdict(), "rows": shown,
            "differences": differences, "dynamics": [{**row, "words": row_words(row)} for row in data["dynamics"]],
            "notes": data["notes"],
            "engines": data["engines"], "rtol": data["rtol"],
            "created": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}


def render(result) -> str:
    """The page's HTML text (the command writes it with its other outputs, all or none)."""
    return environment().get_template("diff.html.j2").render(d=page_data(result))

