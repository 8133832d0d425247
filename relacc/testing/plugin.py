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

from relacc.core.conventions import Route


@pytest.fixture(scope="session")
def relacc_chain():
    """The shipped two-body chain (``two_body.toml``)."""
    from relacc.fixtures import load

    return load().chain


@pytest.fixture(scope="session")
def relacc_states():
    """``relacc_states(case=1, n=200, seed=0, hard=False, model=None)``: seeded states of a case (hard: the
    catalogue's); with ``model`` (an MJCF, URDF or chain TOML path, or a relacc.Tree), that model's states.

    Arguments are checked as :func:`relacc.testing.states` checks them (no float ``n``, no boolean seed). The states
    are drawn once per session for each model *as it is now*: a model is keyed by the content of relacc's tree of it
    (the file is read at every call, so an edited file gives new states), and every call hands out its own read-only
    copies (:meth:`relacc.core.states.States.frozen`): a test that makes one writable changes no other test's."""
    from relacc.core.cases import as_case, check_int
    from relacc.errors import InputError
    from relacc.testing import states
    from relacc.testing.trees import as_tree

    cache = {}

    def make(case=1, n=200, seed=0, hard=False, model=None):
        if not isinstance(hard, bool):
            raise InputError(f"hard: expected True or False, got {hard!r}")
        tree = None if model is None else as_tree(model)
        key = (int(as_case(case)), check_int("n", n, minimum=1), check_int("seed", seed, minimum=0), hard,
               None if tree is None else _fingerprint(tree))
        if key not in cache:
            cache[key] = states(case, n, seed, hard=hard, model=tree)
        return cache[key].frozen()

    return make


def _fingerprint(tree) -> str:
    """A digest of everything a tree's states depend on: its bodies (joints, inertias, placements), points and
    gravity."""
    import hashlib
    import pickle

    import numpy as np

    return hashlib.sha256(pickle.dumps((tree.bodies, tree.points, np.asarray(tree.gravity).tobytes()))).hexdigest()


def _states_key(s) -> tuple:
    """States by value: their case, arrays and tree (two equal batches share an engine's truth)."""
    import hashlib

    digest = hashlib.sha256()
    for a in (s.q, s.u, s.udot):
        digest.update(repr(a.shape).encode())
        digest.update(a.tobytes())
    return int(s.case), digest.hexdigest(), None if s.tree is None else _fingerprint(s.tree)


@pytest.fixture(scope="session")
def relacc_truth():
    """``relacc_truth(states, engine=None, route="quaternion")``: an engine's (default
    :data:`relacc.engines.TRUTH_ENGINE`, MuJoCo) G2 kinematics, computed once per
    session for each batch of states (keyed by their values) and handed out as a copy."""
    import copy

    from relacc.testing import truth

    cache = {}

    def make(states, engine=None, route=Route.QUATERNION):
        if engine is None:  # the engine's traits name it (MuJoCo): resolved here, so that loading the plugin is light
            from relacc.engines import TRUTH_ENGINE

            engine = TRUTH_ENGINE
        key = (_states_key(states), engine, route)
        if key not in cache:
            cache[key] = truth(states, engine, route=route)
        return copy.deepcopy(cache[key])

    return make
