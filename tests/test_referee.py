"""The referee names the odd ones out among three engines, relacc's kernels, its reference and complex steps."""

import json

import numpy as np
import pytest

from relacc.engines import chain, load_engine
from relacc.engines.chain import ChainEngine
from relacc.validation.check import Harness
from relacc.validation.referee import judge, referee

from .conftest import SEED


@pytest.fixture(scope="module")
def mujoco(fixture):
    return load_engine("mujoco", fixture)


def test_pinocchio_composite_joint_is_the_odd_one_out(fixture, mujoco):
    """With the split-joint workaround off, Pinocchio's Vdot fails, and the referee names Pinocchio alone."""
    engines = {"pinocchio": load_engine("pinocchio", fixture, split=False), "mujoco": mujoco,
               "drake": load_engine("drake", fixture)}
    report = Harness(fixture, engines=engines, n_states=200, seed=SEED).check()
    assert {(c.engine, c.quantity) for c in report.failures} == {("pinocchio", "Vdot")}
    assert {v.case for v in report.referee} == {1, 2, 3}
    for verdict in report.referee:
        assert verdict.odd_ones_out == ("pinocchio",), verdict.sentence()
        assert set(verdict.agreeing) == {"mujoco", "drake", "relacc", "relacc-reference", "complex-step"}
    as_json = report.as_json()["referee"][0]
    assert as_json["odd_ones_out"] == ["pinocchio"] and "the odd one out: pinocchio" in as_json["verdict"]


class _Faulty(ChainEngine):
    """Drake with a planted fault: G2's acceleration off by one part in a million (other engines unchanged)."""

    def points(self, route, q, v, a, *, jdot=True):
        pts = super().points(route, q, v, a, jdot=jdot)
        if pts.acceleration is not None and self.name == "drake":
            pts.acceleration[:] *= 1 + 1e-6
        return pts


def test_a_planted_fault_is_named(fixture, mujoco):
    """A fault planted in Drake's acceleration fails check, and the referee names Drake, not the others."""
    engines = {"pinocchio": load_engine("pinocchio", fixture), "mujoco": mujoco,
               "drake": _Faulty("drake", load_engine("drake", fixture).routes)}
    h = Harness(fixture, engines=engines, n_states=100, seed=SEED)
    report = h.check()
    assert {(c.engine, c.quantity) for c in report.failures} == {("drake", "acceleration")}
    assert [v.odd_ones_out for v in report.referee] == [("drake",)] * len(report.referee)
    clean = referee(h, 2, "Vdot")
    assert clean.everyone_agrees and clean.odd_ones_out == () and "no odd one out" in clean.sentence()


def test_the_largest_agreeing_side_blames_everyone_outside_it():
    """One judgement for the chain's routes and a model's comparison: the largest group that agrees pairwise is the side
    that agrees, and whoever is outside it is odd, however many; equal sides are a split, said so; no two agreeing
    blames everyone."""
    from relacc.validation.referee import pair_ratios

    rng = np.random.default_rng(SEED)
    x = rng.normal(size=(5, 3))
    values = {"a": x, "b": x, "c": x * (1 + 1e-6), "d": x * (1 - 1e-6)}
    bounds = {k: np.full(5, 1e-14) for k in values}
    pairs = pair_ratios(values, bounds, np.ones(5))
    assert pairs["a|b"] <= 1 < pairs["c|d"], f"seed {SEED}"
    assert judge(list(values), pairs) == (("c", "d"), ("a", "b"), ()), f"seed {SEED}"
    values["d"] = x
    assert judge(list(values), pair_ratios(values, bounds, np.ones(5))) == (("c",), ("a", "b", "d"), ())
    split = {"a": x, "b": x, "c": x * (1 + 1e-6), "d": x * (1 + 1e-6)}
    assert judge(list(split), pair_ratios(split, bounds, np.ones(5))) == ((), (), (("a", "b"), ("c", "d")))
    alone = {"a": x, "c": x * (1 + 1e-6), "d": x * (1 - 1e-6)}
    assert judge(list(alone), pair_ratios(alone, bounds, np.ones(5))) == (("a", "c", "d"), (), ())


def test_check_prints_the_referee(capsys, fixture, monkeypatch):
    """`relacc check` prints one referee line per failed comparison, and --json carries the verdicts."""
    from relacc.cli import main

    monkeypatch.setattr(chain, "ChainEngine", _Faulty)
    assert main(["check", "--states", "50", "--cases", "1", "--quiet", "--model", str(fixture.source)]) == 1
    out = capsys.readouterr().out
    assert "referee: case 1 acceleration (quaternion route): the odd one out: drake (up to" in out
    assert main(["check", "--states", "50", "--cases", "1", "--quiet", "--json", "--model", str(fixture.source)]) == 1
    assert json.loads(capsys.readouterr().out)["referee"][0]["odd_ones_out"] == ["drake"]


def test_a_referee_line_never_says_everyone_agrees_over_a_row_that_differs():
    """Issue 50 item 10: compare printed a DIFFER row for relacc's case 1, then the referee line "no odd one out ...
    agree": the referee votes on the case-2 readings. Rows outside the vote that differ are named in the line."""
    from relacc.validation.referee import Verdict

    v = Verdict("mass matrix", (), ("relacc", "mujoco"), (), {"relacc|mujoco": 0.2}, apart=("relacc (case 1)",))
    line = v.sentence()
    assert "no odd one out among the case-2 readings" in line and "relacc (case 1) differs from relacc's case 2" in line
    assert v.as_json()["apart"] == ["relacc (case 1)"]
