"""``relacc report --model FILE.xml|FILE.urdf``: the agreement report of any MJCF or URDF model.

One self-contained page (the compare page's template, extended): what each engine read (the audit) and the
dynamics against MuJoCo with the referee (:func:`relacc.validation.robots.compare`); relacc's tree against each
engine in the note's three cases, quantity by quantity and body by body (:func:`relacc.validation.treecheck.
check_tree`); the conventions of every number; and the model's default scene (tumbling in space, nothing acting)
simulated by relacc and every engine. The note's errata belong to the note's chain and appear only in the chain's
report (``relacc report``, or ``--model`` a chain TOML).

Layer rule: as the report's sections, plain data from the layers below, rendered by Jinja2 (autoescaped).
"""

from __future__ import annotations

import os

from relacc import files
from relacc.core.conventions import CASE_NAMES, MODEL_MEANINGS, TREE_JOINTS
from relacc.engines import TRAITS
from relacc.report.build import environment
from relacc.report.robot import page_data

DEFAULT_STATES = 20
QUICK_STATES = 5
"""Random states (besides the reference configuration) per comparison: each is a full dynamics evaluation."""
HARD_EXAMPLES = {True: 10, False: 30}
"""Hypothesis examples per case of the hard-case search, quick or not (about 0.1 s each on gymnasium's ant)."""
DURATION = {True: 0.05, False: 0.2}
"""Seconds of the default scene, quick or not (Pinocchio's and Drake's runs apply the effects in Python at every
stage: they, not relacc's compiled stepper, set the section's time)."""


def build(model, *, n_states=None, seed: int = 0, quick: bool = False, progress=None) -> dict:
    """The page's plain data; ``data["agree"]``: no audit difference and every comparison within tolerance."""
    from relacc import simulate
    from relacc.simulate import scenes
    from relacc.validation.robots import compare
    from relacc.validation.treecheck import check_tree

    n = n_states if n_states is not None else (QUICK_STATES if quick else DEFAULT_STATES)
    if progress:
        progress("the engines' readings and dynamics (relacc compare)")
    result = compare(model, n_states=n, seed=seed)
    check = check_tree(model, n_states=n, seed=seed, progress=progress)
    if progress:
        progress("hard cases (a Hypothesis search against MuJoCo)")
    hard = _hard(model, HARD_EXAMPLES[bool(quick)], seed)
    scene = scenes.model_scene(model, seed=seed, duration=DURATION[bool(quick)])
    if progress:
        progress(f"scene {scene.name}, {scene.duration} s")
    run = simulate.run(scene)
    data = page_data(result)
    data.update(title="relacc report", cases=_cases(check), bodies=_bodies(check), check_passed=check.passed,
                not_loaded=check.not_loaded, simulation=_simulation(run), conventions=_conventions(result),
                hard=hard, agree=result.agree and check.passed and run.agree and hard["ok"])
    return data


def _hard(model, examples, seed) -> dict:
    """The hard-case search's plain data (:func:`relacc.validation.treehard.search`); ``ok``: every case within its
    bound, or nothing searched (``reason`` says why: MuJoCo cannot compile the file)."""
    from relacc.errors import ModelError
    from relacc.validation.treehard import search

    try:
        found = search(model, examples=examples, seed=seed)
    except ModelError as exc:
        return {"ok": True, "rows": [], "reason": str(exc), "examples": examples}
    return {"ok": all(f.ratio <= 1 for f in found), "rows": [f.as_json() for f in found], "reason": None,
            "examples": examples}


def _ratio(r) -> float | None:
    """The worst error over the tolerance (None where undefined: a row's cause says why)."""
    ratio = r.max_error / r.tolerance
    return ratio if ratio != float("inf") else None


def _cases(check) -> dict:
    """Quantity by quantity, one cell per case: each engine's worst error over the tolerance."""
    cases = sorted({r.case for r in check.rows})
    rows = []
    for quantity in dict.fromkeys(r.quantity for r in check.rows):
        cells = []
        for case in cases:
            found = [r for r in check.rows if r.quantity == quantity and r.case == case]
            cells.append({"ok": all(r.passed for r in found),
                          "engines": [{"engine": r.engine, "ratio": _ratio(r), "state": r.worst_state}
                                      for r in found]})
        rows.append({"quantity": quantity, "meaning": MODEL_MEANINGS.get(quantity, ""), "cells": cells})
    return {"cases": cases, "rows": rows, "tolerance": check.rows[0].tolerance if check.rows else None}


def _bodies(check) -> list[dict]:
    """Body by body: in each case, the worst error over the tolerance of any engine and any quantity of the
    body's mass centre (position, Jacobian, ``J_dot v``, classical acceleration), and which."""
    bodies = {}
    for r in check.rows:
        for link, err in r.per_link.items():
            cell = bodies.setdefault(link, {}).setdefault(r.case, {"ratio": -1.0})
            ratio = err / r.tolerance
            if ratio > cell["ratio"]:
                cell.update(ratio=ratio, engine=r.engine, quantity=r.quantity)
    cases = sorted({r.case for r in check.rows})
    return [{"body": link, "cells": [{**per_case[c], "ok": per_case[c]["ratio"] <= 1,
                                      "ratio": per_case[c]["ratio"] if per_case[c]["ratio"] != float("inf") else None}
                                     if c in per_case else None for c in cases], "cases": cases}
            for link, per_case in bodies.items()]


def _conventions(result) -> dict:
    return {"joints": [{"joint": j, "cells": list(v)} for j, v in TREE_JOINTS.items()],
            "cases": [{"case": c, "name": n} for c, n in CASE_NAMES.items()],
            "engines": [{"engine": e, "speeds": TRAITS[e].speeds} for e in result.engines if e in TRAITS]}


def _simulation(run) -> dict:
    from relacc import simulate

    summary = run.summary()
    return {"scene": run.scene.name, "title": run.scene.title, "point": summary.get("point"),
            "duration": run.scene.duration, "dt": run.scene.dt, "integrator": run.scene.integrator,
            "engines": [{"engine": e, "seconds": s.get("seconds"), "energy_drift": s.get("energy_drift")}
                        for e, s in summary["engines"].items()],
            "pairs": [{"pair": k, "position": v["position"], "velocity": v["velocity"]}
                      for k, v in run.differences()[2].items()],
            "agree": run.agree, "verdict": run.verdict(), "notes": simulate.scene_notes(run.scene),
            "checks": [{"engine": e, "error": c["error"], "bound": c["bound"], "ok": c["error"] <= c["bound"]}
                       for e, c in run.note_check.items()]}


def write(model, out, *, n_states=None, seed: int = 0, quick: bool = False, progress=None):
    """Run everything and write the page atomically; returns ``(path, agree, notes)``, ``notes``: one line per kind
    of element of the file the page leaves out and per engine the scene ran without. The output path is checked
    first."""
    with files.inputs([model] if isinstance(model, (str, os.PathLike)) else []):  # the page never replaces the model
        path = files.check_output_file(out)
        data = build(model, n_states=n_states, seed=seed, quick=quick, progress=progress)
        path.parent.mkdir(parents=True, exist_ok=True)
        files.write_text(path, environment().get_template("model.html.j2").render(d=data))
    notes = [f"not evaluated: {u}" for u in data["unevaluated"]] + [n for n in data["simulation"]["notes"]
                                                                     if n.startswith("left out")]
    return path, data["agree"], notes
