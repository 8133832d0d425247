"""The errata: every equation id's status follows from engine comparisons."""

import json

import pytest

from relacc.core.note.equations import BY_ID, IDS
from relacc.validation.check import Harness
from relacc.validation.errata import STATUSES, errata

from .conftest import SEED


@pytest.fixture(scope="module")
def items(fixture):
    return errata(Harness(fixture, n_states=300, seed=SEED + 1))


def test_every_id_is_reported_once(items):
    """The errata cover eq1..eq12, case1-a, case2-a/b/c and the case-3 ids, each once."""
    assert [e.id for e in items] == list(IDS)
    numbered = {i.split(".")[0] for i in IDS if i.startswith("eq")}
    assert numbered == {f"eq{k}" for k in range(1, 13)}


def test_every_corrected_form_agrees_with_both_engines(items):
    """Whatever the status, the corrected (or printed-and-ok) form agrees with the engines."""
    for e in items:
        assert e.agrees, f"{e.id}: corrected error {e.corrected_error:.3g} > {e.tolerance:.3g}"


def test_statuses_match_the_registry(items):
    """ok where printed equals corrected; wrong/ambiguous where the printed form differs; eq11 missing."""
    for e in items:
        eq = BY_ID[e.id]
        assert e.status in STATUSES
        if eq.kind == "missing":
            assert e.status == "missing" and e.printed_error is None
        elif eq.differs:
            assert e.status == ("ambiguous" if eq.kind == "ambiguous" else "wrong")
            assert e.printed_error > 1e3 * e.tolerance
        else:
            assert e.status == "ok"


def test_json_has_exactly_the_documented_keys(items):
    """relacc errata --json objects carry id, status, printed_error, corrected_error, explanation."""
    for e in items:
        d = json.loads(json.dumps(e.as_dict()))
        assert set(d) == {"id", "status", "printed_error", "corrected_error", "explanation"}
