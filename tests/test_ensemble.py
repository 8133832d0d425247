"""Ensembles: every member is the single run from its state, on relacc and on each engine's batched API."""

import json

import numpy as np
import pytest

from relacc.cli import main
from relacc.core.tolerances import EPS
from relacc.fixtures import shipped
from relacc.simulate import ensemble, perturbed, run, scenes
from relacc.simulate.members import largest_differences
from tests.trees import rk4_as_textbook


@pytest.fixture(scope="module")
def scene():
    return scenes.load(shipped.scene_path("forced_damped")).replace(duration=0.05, record_every=7)


def test_members_start_at_the_scene_and_at_perturbed_states(scene):
    """Member 0 is the scene's own state; the others differ by about the spread, quaternions still unit."""
    q0, u0 = perturbed(scene, 5, 0.05, seed=3)
    assert np.array_equal(q0[0], scene.q) and np.array_equal(u0[0], scene.u)
    assert 0.001 < np.abs(u0[1:] - scene.u).max() < 0.5
    # a normalized quaternion's norm: a square root of a 4-term sum, a few roundings of 1
    assert np.allclose(np.linalg.norm(q0[:, 3:7], axis=1), 1, rtol=0, atol=4 * EPS)


def test_any_range_of_members_is_the_same_slice_of_the_whole(scene):
    """Members come from per-chunk seeds: members 1000-1099 alone equal rows 1000-1099 of the first 2100."""
    from relacc.simulate.members import MEMBER_CHUNK

    q_all, u_all = perturbed(scene, 2100, 0.05, seed=9)
    q, u = perturbed(scene, 100, 0.05, seed=9, start=1000)
    assert np.array_equal(q, q_all[1000:1100]) and np.array_equal(u, u_all[1000:1100])
    assert MEMBER_CHUNK < 1100  # the range crosses a chunk boundary
    assert not np.array_equal(q_all[1:MEMBER_CHUNK], perturbed(scene, MEMBER_CHUNK, 0.05, seed=10)[0][1:])


@pytest.mark.parametrize("engine", ["relacc", "mujoco"])
def test_an_ensemble_member_is_the_single_run(scene, engine):
    """Member i of an ensemble is, bit for bit, the single run started from member i's state."""
    q0, u0 = perturbed(scene, 4, 0.05, seed=4)
    ens = ensemble(scene, q0, u0, engine=engine, threads=2)
    assert ens.t.tolist() == [0.0] + [7e-3 * k for k in range(1, 8)] + [0.05]
    for i in (0, 3):
        single = run(scene.replace(q=q0[i], u=u0[i]), engines=(engine,)).trajectories[engine]
        assert np.array_equal(ens.q[i], single.q) and np.array_equal(ens.u[i], single.u)
        assert np.array_equal(ens.position[i], single.position)


@rk4_as_textbook()
def test_engines_agree_member_by_member(scene):
    """relacc, MuJoCo's rollouts and Pinocchio's abaInParallel RKMK4 keep every member's G2 within 1e-9 m."""
    q0, u0 = perturbed(scene, 6, 0.1, seed=5)
    runs = {e: ensemble(scene, q0, u0, engine=e) for e in ("relacc", "mujoco", "pinocchio")}
    for pair, d in largest_differences(runs).items():
        assert d.shape == (6,) and d.max() < 1e-9, (pair, d)
    assert all(r.steps == 6 * scene.n_steps and r.seconds > 0 for r in runs.values())


@rk4_as_textbook()
def test_cli_ensemble_reports_rates_and_differences(capsys):
    """relacc simulate --ensemble: steps per second per engine and the largest G2 difference per pair."""
    assert main(["simulate", "tumbling", "--ensemble", "3", "--duration", "0.01", "--engines", "relacc,mujoco",
                 "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out["engines"]) == {"relacc", "mujoco"} and out["members"] == 3
    assert out["largest_point_position_difference"]["relacc-mujoco"]["max"] < 1e-9
    assert main(["simulate", "tumbling", "--ensemble", "3", "--out", "x"]) == 2
