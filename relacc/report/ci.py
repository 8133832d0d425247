"""What ``relacc compare`` found, for a description repository's CI: one result per finding, audit difference,
dynamics row outside tolerance and refusal, each with a rule of :data:`RULES`, a level and a place (``file:line``);
written as JUnit XML (one testcase per model) or SARIF 2.1.0 (what GitHub code scanning shows inline), and judged
against a baseline of accepted results (docs/ci.md has the rules and a CI job).

A result's fingerprint names what it is about, never where it is: the rule, the model (relative to the directory
relacc runs in), the element and the quantity, so that a line moved by an edit elsewhere keeps its result accepted.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

from relacc import files
from relacc.errors import InputError, RelaccError
from relacc.validation.robots.causes import CauseKind


@dataclass(frozen=True)
class Rule:
    """One kind of result: its id, a short name, what it means, and its SARIF level."""

    id: str
    name: str
    text: str
    level: str


RULES = {r.id: r for r in (
    Rule("RELACC001", "non-physical-body", "A body the file describes is not physical (a negative mass, an inertia "
         "that is not positive semidefinite or breaks the triangle inequality, no mass but an inertia, a joint that "
         "moves no mass): each engine reads it its own way.", "error"),
    Rule("RELACC002", "engine-reads-differently-explained", "An engine reads an element of the file differently from "
         "the format's specification, and relacc reproduced why (re-reading the file the engine's way): the cause "
         "names the engine's behaviour.", "warning"),
    Rule("RELACC003", "engine-reads-differently", "An engine reads an element of the file differently from the "
         "format's specification, and no known behaviour of that engine reproduces it.", "error"),
    Rule("RELACC004", "dynamics-differ-explained", "An engine's dynamics (mass matrix, bias and gravity forces, "
         "forward dynamics, a link's Jacobian, J_dot v or acceleration) differ from relacc's reading beyond the error "
         "model, for a reproduced reason.", "warning"),
    Rule("RELACC005", "dynamics-differ", "An engine's dynamics differ from relacc's reading beyond the error model, "
         "and nothing known reproduces it.", "error"),
    Rule("RELACC006", "taken-from-engine", "relacc took an element's mass properties from an engine (a primitive "
         "fitted to a mesh, from MuJoCo) and cannot judge that engine there.", "note"),
    Rule("RELACC007", "not-evaluated", "The file has what relacc's comparison leaves out (constraints, tendons, "
         "actuators with dynamics, gravity compensation, fluid forces, dry friction).", "note"),
    Rule("RELACC008", "cannot-compare", "relacc cannot read the file, or no engine takes part.", "error"),
    Rule("RELACC009", "internal-error", "relacc failed on the file (a bug in relacc; please report it).", "error"),
    Rule("RELACC010", "descriptions-differ", "Two descriptions of one robot differ (relacc diff): a mass, mass "
         "centre, inertia, joint axis, anchor, zero, armature, damping, friction, spring, range or gravity, a part "
         "or joint without a counterpart, the placement, or the dynamics beyond printing.", "error"),
)}
"""The fixed list of rules (docs/ci.md)."""

SEE = re.compile(r"\(see ([^()]+?)\)$")
PLACE = re.compile(r"^(?P<file>.+?):(?P<line>\d+)$")


@dataclass(frozen=True)
class Result:
    """One result: ``rule`` (an id of :data:`RULES`), ``message``, the model it is about, ``place`` (``file:line``,
    or a file), and ``key`` (what it is about, for its fingerprint)."""

    rule: str
    message: str
    model: str
    place: str
    key: str

    @property
    def level(self) -> str:
        return RULES[self.rule].level

    @property
    def fails(self) -> bool:
        """Whether it fails a run (errors and warnings; notes never)."""
        return self.level in ("error", "warning")

    @property
    def file(self) -> str:
        m = PLACE.match(self.place)
        return m.group("file") if m else (self.place or self.model)

    @property
    def line(self) -> int | None:
        m = PLACE.match(self.place)
        return int(m.group("line")) if m else None

    @property
    def fingerprint(self) -> str:
        text = json.dumps([self.rule, _relative(self.model), self.key])
        return hashlib.sha256(text.encode()).hexdigest()[:32]

    def located(self) -> str:
        """``file:line: message``, the file relative to the working directory."""
        where = _relative(self.file) + (f":{self.line}" if self.line is not None else "")
        return f"{where}: {self.message}"


def results(model: str, outcome) -> list[Result]:
    """Every result of one model's comparison (a :class:`relacc.validation.robots.RobotComparison`), or of the
    error that stopped it (a :class:`relacc.RelaccError`: a refusal; any other exception: an internal error)."""
    if isinstance(outcome, Exception):
        text = str(outcome)
        m = re.match(r"^(?P<place>[^\s:]+:\d+): ", text)
        place = m.group("place") if m else model
        rule = "RELACC008" if isinstance(outcome, RelaccError) else "RELACC009"
        return [Result(rule, text, model, place, "refused" if rule == "RELACC008" else "internal")]
    data = outcome.as_json()
    out = []
    for f in data["findings"]:
        out.append(Result("RELACC001", f"body {f['body']}: {f['condition']} ({f['numbers']})", model, f["place"],
                          f"{f['body']}|{f['condition']}"))
    for a in data["audit"]:
        explained = a["cause_kind"] != CauseKind.NOT_EXPLAINED
        rule = "RELACC006" if a["cause_kind"] == CauseKind.TAKEN else "RELACC002" if explained else "RELACC003"
        out.append(Result(rule, f"{a['item']}: {a['where']}: {a['cause']}", model, a.get("place") or model,
                          f"{a['item']}|{a['where']}"))
    for quantity, row in data["dynamics"].items():
        for engine, r in row["engines"].items():
            if r["ok"]:
                continue
            kind = r.get("cause_kind", "")
            rule = ("RELACC006" if kind == CauseKind.TAKEN else "RELACC005" if kind in (CauseKind.NOT_EXPLAINED, "")
                    else "RELACC004")
            see = SEE.search(r.get("cause") or "")
            out.append(Result(rule, f"{quantity}, {engine}: {r.get('cause') or 'outside tolerance'}", model,
                              see.group(1) if see else model, f"{quantity}|{engine}"))
    for line in data["not_evaluated"]:
        out.append(Result("RELACC007", f"not evaluated: {line}", model, model, line.split(":")[0]))
    return out


def diff_results(result) -> list[Result]:
    """Every result of ``relacc diff A B`` (a :class:`relacc.validation.diff.Diff`): one :data:`RULES` RELACC010 per
    difference, at its place in B (the file a conversion or an edit wrote; A's place in the message), and one per
    dynamics row beyond printing, at B."""
    from relacc.validation.diff_dynamics import row_words

    model = result.b
    out = []
    for d in result.differences:
        out.append(Result("RELACC010", f"{d.kind} {d.element}: {d.quantity}: A {d.a}, B {d.b} (A at {d.where_a})",
                          model, d.where_b, f"{d.kind}|{d.element}|{d.quantity}"))
    for row in result.dynamics:
        if row["beyond"]:
            words = row_words(row)
            out.append(Result("RELACC010", f"the {row['quantity']} of A and B differ by {row['normalized']:.3g} of its "
                              f"largest entry (printing allows {row['tolerance']:.3g})"
                              + (f"; {words}" if words else ""), model, model, f"dynamics|{row['quantity']}"))
    return out


def _relative(path: str) -> str:
    """``path`` relative to the working directory where it lies under it (as CI, run at a repository's root, wants
    it), POSIX-style; else as given."""
    try:
        rel = os.path.relpath(Path(path).resolve(), Path.cwd().resolve())
    except (OSError, ValueError):
        return str(path)
    return path if rel.startswith("..") else Path(rel).as_posix()


# --- baseline -------------------------------------------------------------------------------------------------------

BASELINE_FORMAT = "relacc-baseline 1"


def read_baseline(path) -> set[str]:
    """The fingerprints a baseline file accepts.

    Raises:
        InputError: not a baseline relacc wrote (its format, JSON, a list of fingerprints).
    """
    data, _ = files.read_document(path, json.loads, "JSON", what="baseline")
    if not (isinstance(data, dict) and data.get("format") == BASELINE_FORMAT
            and isinstance(data.get("accepted"), list) and all(isinstance(x, str) for x in data["accepted"])):
        raise InputError(f"{path}: not a relacc baseline (expected {{\"format\": \"{BASELINE_FORMAT}\", \"accepted\": "
                         "[fingerprints]}, as --write-baseline writes it)")
    return {x for x in data["accepted"]}


def write_baseline(path, found: list[Result]) -> None:
    """Every failing result's fingerprint, with its place and message for a reader (atomically)."""
    accepted = sorted({r.fingerprint for r in found if r.fails})
    described = {r.fingerprint: r.located() for r in found if r.fails}
    files.write_text(path, json.dumps({"format": BASELINE_FORMAT, "accepted": accepted,
                                       "described": [described[f] for f in accepted]}, indent=2) + "\n")


def failing(found: list[Result], accepted: set[str]) -> list[Result]:
    """The results that fail a run: errors and warnings not accepted by the baseline (internal errors always)."""
    return [r for r in found if r.fails and (r.fingerprint not in accepted or r.rule == "RELACC009")]


# --- JUnit ----------------------------------------------------------------------------------------------------------

def junit(per_model: list[tuple[str, list[Result], float]], accepted: set[str], command: str = "compare") -> str:
    """JUnit XML: one testcase per model (``name`` its path relative to the working directory, ``time`` its seconds),
    failing with each new result, ``file:line: message``, one per line; a refusal or an internal error is an
    ``<error>``. ``command``: the suite's name, ``relacc compare`` or ``relacc diff``."""
    suite = ET.Element("testsuite", name=f"relacc {command}", tests=str(len(per_model)))
    failures = errors = 0
    for model, found, seconds in per_model:
        case = ET.SubElement(suite, "testcase", classname=f"relacc.{command}", name=_relative(model),
                             file=_relative(model), time=f"{seconds:.3f}")
        new = failing(found, accepted)
        if not new:
            continue
        refused = [r for r in new if r.rule in ("RELACC008", "RELACC009")]
        tag = "error" if refused else "failure"
        errors, failures = errors + bool(refused), failures + (not refused)
        element = ET.SubElement(case, tag, message=f"{len(new)} result{'s' if len(new) > 1 else ''}: "
                                + new[0].located()[:200], type=RULES[new[0].rule].name)
        element.text = "\n".join(f"{r.located()} [{r.rule} {RULES[r.rule].name}]" for r in new)
    suite.set("failures", str(failures))
    suite.set("errors", str(errors))
    root = ET.Element("testsuites")
    root.append(suite)
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


# --- SARIF ----------------------------------------------------------------------------------------------------------

SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"


def sarif(found: list[Result], accepted: set[str] | None) -> str:
    """SARIF 2.1.0: one run of the tool ``relacc`` with :data:`RULES`, one result per :class:`Result`: its rule, level,
    message and physical location (the artifact's URI relative to the working directory, its start line); with a
    baseline, each result's ``baselineState`` (``unchanged`` for an accepted one, ``new`` otherwise)."""
    from relacc import __version__

    ids = list(RULES)
    out = []
    for r in found:
        region = {"startLine": r.line} if r.line is not None else {}
        location = {"physicalLocation": {"artifactLocation": {"uri": _relative(r.file)}, **(
            {"region": region} if region else {})}}
        result = {"ruleId": r.rule, "ruleIndex": ids.index(r.rule), "level": r.level, "message": {"text": r.message},
                  "locations": [location], "partialFingerprints": {"relacc/v1": r.fingerprint}}
        if accepted is not None:
            result["baselineState"] = "unchanged" if r.fingerprint in accepted else "new"
        out.append(result)
    rules = [{"id": rule.id, "name": rule.name, "shortDescription": {"text": rule.name.replace("-", " ")},
              "fullDescription": {"text": rule.text}, "defaultConfiguration": {"level": rule.level}}
             for rule in RULES.values()]
    doc = {"$schema": SARIF_SCHEMA, "version": "2.1.0",
           "runs": [{"tool": {"driver": {"name": "relacc", "version": __version__, "rules": rules}},
                     "results": out}]}
    return json.dumps(doc, indent=2) + "\n"


__all__ = ["RULES", "Result", "Rule", "diff_results", "failing", "junit", "read_baseline", "results", "sarif",
           "write_baseline"]
