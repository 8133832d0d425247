"""relacc's own tree as an evaluator in ``relacc compare``: rows in the three cases, and the referee."""

from pathlib import Path

import gymnasium
import pytest

from relacc.engines.mujoco_.adapter import MUJOCO_JACDOT
from relacc.validation.robots import compare

ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"

BALL_THEN_SLIDE = """<mujoco model="ball_then_slide"><compiler angle="radian"/><worldbody>
  <body name="a" pos="0 0 1"><freejoint name="root"/><inertial pos="0.1 0 0" mass="2" diaginertia=".1 .2 .25"/>
    <body name="b"><joint name="ball" type="ball"/><joint name="slide" type="slide" axis="0 0 1"/>
      <inertial pos="0.2 0.1 0" mass="1" diaginertia=".05 .06 .07"/></body></body>
</worldbody></mujoco>"""


@pytest.mark.slow
def test_relacc_evaluates_every_quantity_in_every_case():
    """On the free-root ant every engine agrees with relacc's reading; relacc's cases 1 and 3 agree with its case 2."""
    result = compare(ASSETS / "ant.xml", n_states=4, seed=3)
    data = result.as_json()
    for quantity, row in data["dynamics"].items():
        for who in ("relacc (case 1)", "relacc (case 3)", "mujoco", "pinocchio", "drake"):
            r = row["engines"][who]
            assert r["ok"], (quantity, who, r)
    assert data["referee"] == [] and result.exit_code == 0


def test_the_referee_names_mujoco_when_relacc_and_the_engines_agree(tmp_path):
    """A ball then a slide on one body: MuJoCo's mj_jacDot is off. Every engine's classical acceleration (its own
    acceleration routine) agrees; on J_dot v, relacc's reading and Drake agree, and so does Pinocchio once its known
    composite-joint difference is removed (Pinocchio as loaded makes the same slip as MuJoCo): the referee names
    MuJoCo, and MuJoCo's row carries the reproduced cause; relacc's cases agree among themselves."""
    path = tmp_path / "ball_then_slide.xml"
    path.write_text(BALL_THEN_SLIDE)
    data = compare(path, n_states=4, seed=1).as_json()
    assert data["dynamics"]["classical acceleration"]["ok"]
    row = data["dynamics"]["J_dot v"]["engines"]
    for case in (1, 3):
        assert row[f"relacc (case {case})"]["ok"]
    assert not row["mujoco"]["ok"] and row["mujoco"]["cause"] == MUJOCO_JACDOT
    assert row["drake"]["ok"]
    verdict = {v["quantity"]: v for v in data["referee"]}["J_dot v"]
    assert verdict["odd_ones_out"] == ["mujoco"]
    assert set(verdict["agreeing"]) == {"relacc", "pinocchio", "drake"}
    assert set(verdict["voted_as"]) == {"pinocchio"}
    assert data["dynamics"]["forward dynamics"]["ok"]  # MuJoCo's dynamics use the right rates
