"""The ``relacc`` pytest plugin (entry point ``pytest11``): fixtures for anyone's test suite.

Importing it loads nothing heavy; each fixture loads what it needs when a
test asks for it, and engine truth is cached for the session.

* ``relacc_chain``: the shipped chain, a :class:`relacc.TwoBodyChain`.
* ``relacc_states``: a factory, ``relacc_states(case=1, n=200, seed=0, hard=False)``
  returning :class:`relacc.core.states.States` (``.q``, ``.u``, ``.udot``, ``.seed``).
* ``relacc_truth``: a factory, ``relacc_truth(states, engine="mujoco", route="quaternion")``
  returning a :class:`relacc.testing.Truth` (``.position``, ``.velocity``,
  ``.acceleration``, ``.V``, ``.Vdot`` as :class:`relacc.testing.Expected`), cached per session.

With :func:`relacc.testing.assert_agrees`::

    def test_my_velocity(relacc_chain, relacc_states, relacc_truth):
        s = relacc_states(case=1, n=100, seed=3)
        mine = [my_velocity(relacc_chain, q, u) for q, u in zip(s.q, s.u)]
        assert_agrees(mine, relacc_truth(s, engine="pinocchio").velocity)
"""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def relacc_chain():
    """The shipped two-body chain (``two_body.toml``)."""
    from relacc.fixtures import load

    return load().chain


@pytest.fixture(scope="session")
def relacc_states():
    """``relacc_states(case=1, n=200, seed=0, hard=False)``: seeded states of a case (hard: the catalogue's)."""
    from relacc.testing import states

    cache = {}

    def make(case=1, n=200, seed=0, hard=False):
        key = (int(case), int(n), int(seed), bool(hard))
        if key not in cache:
            cache[key] = states(case, n, seed, hard=hard)
        return cache[key]

    return make


@pytest.fixture(scope="session")
def relacc_truth():
    """``relacc_truth(states, engine="mujoco", route="quaternion")``: an engine's G2 kinematics, cached per session."""
    from relacc.testing import truth

    cache = {}

    def make(states, engine="mujoco", route="quaternion"):
        key = (id(states), engine, route)
        if key not in cache:
            cache[key] = (states, truth(states, engine, route=route))  # keep states alive: its id stays unique
        return cache[key][1]

    return make
