"""States and truth for any model (an MJCF, a URDF, a chain TOML or a :class:`relacc.Tree`), for others' tests.

:func:`model_states` draws seeded states of a case (ordinary or hard); :func:`model_truth` evaluates every body
with relacc's tree (the reference) or with MuJoCo (its own numbers, in the quantities MuJoCo has for the case)
and returns :class:`relacc.testing.Expected` quantities of shape ``(n, nb, ...)`` whose scales and bounds are
relacc's error model for trees (:mod:`relacc.core.tree.scales`), per body.
"""

from __future__ import annotations

import numpy as np

from relacc.core.cases import Case, as_case, check_int
from relacc.core.states import States
from relacc.core.tolerances import rounding_tolerance
from relacc.core.tree import Tree, convert, random_states, tree_kinematics
from relacc.core.tree.coordinates import rotations
from relacc.core.tree.scales import tree_scales, tree_tolerance
from relacc.errors import EngineError, InputError
from relacc.testing.expected import Expected, Truth

TREE_QUANTITIES = ("position", "velocity", "acceleration", "omega", "alpha", "V", "Vdot", "Omega", "Omegadot")
"""Per-body quantities of :class:`relacc.TreeKinematics` a test or a grade may ask for."""

PHYSICAL = ("position", "velocity", "acceleration", "omega", "alpha")
"""The quantities that do not depend on the choice of speeds (MuJoCo's in every case)."""


def as_tree(model) -> Tree:
    """A :class:`relacc.Tree` from a tree, or from a model file read with :meth:`relacc.Tree.from_file`."""
    if isinstance(model, Tree):
        return model
    if isinstance(model, (str, bytes)) or hasattr(model, "__fspath__"):
        return Tree.from_file(model)
    raise InputError(f"model: expected a relacc.Tree or a path to an MJCF, URDF or chain TOML, got {model!r:.80}")


def model_states(model, case=2, n: int = 200, seed: int = 0, hard: bool = False) -> States:
    """``n`` seeded states of a model's tree in a case (``numpy.random.default_rng(seed)``), read-only
    :class:`relacc.core.states.States` (``tree`` set).

    ``hard``: in turn, a free root 1e6 m from the origin, speeds and rates 1e3 times larger, and (case 3) every
    ball and free joint 1e-3 rad from gimbal lock; ordinary otherwise.
    """
    tree = as_tree(model)
    c = int(as_case(case))
    n, seed = check_int("n", n, minimum=1), check_int("seed", seed, minimum=0)
    s = random_states(tree, 2, n, seed)
    q, u, udot = s.q.copy(), s.u.copy(), s.udot.copy()
    if hard:
        kind = np.arange(n) % 3
        free = [a for (_, j), a in zip(tree.joints, tree.qadr(2)) if j.type == "free"]
        for a in free:
            q[kind == 0, a:a + 3] += 1e6
        u[kind == 1] *= 1e3
        udot[kind == 1] *= 1e6
    if c != Case.BODY_FRAME:
        q, u, udot = convert(tree, q, u, udot, source=2, target=c)
    if hard and c == Case.ANGLE_RATES:  # case 3's own hard states: 1e-3 rad from the lock, the rates as drawn
        for _, _, a, _ in rotations(tree, 3):
            q[2::3, a + 1] = np.pi / 2 - 1e-3
    return States(as_case(c), q, u, udot, ["hard", seed] if hard else seed, tree).frozen()


def model_truth(s: States, engine: str = "relacc", quantities=TREE_QUANTITIES) -> dict:
    """``{quantity: Expected}`` of every body, by relacc's tree or by MuJoCo; see :func:`truth_of`."""
    return _truth(s, engine, tuple(quantities))


def _truth(s: States, engine: str, quantities: tuple) -> dict:
    """``{quantity: Expected}`` of every body, by relacc's tree or by an engine that gives each body's motion
    (:meth:`relacc.engines.base.Adapter.body_motion`: MuJoCo).

    An engine gives the quantities it has for the case: ``position``, ``velocity``, ``acceleration``, ``omega``,
    ``alpha`` in every case (states converted to case 2, then to its coordinates), and ``V``, ``Omega`` (MuJoCo's
    ``mj_jac``) in case 2, mapped back to case-2 speeds (``V_e T``). Each Expected's ``bound`` is the tree tolerance
    beyond ``c eps``: ``c eps (depth - 1)`` per body.

    Raises:
        EngineError: an unknown engine, one not installed, or one whose adapter gives no per-body motion.
    """
    tree, c = s.tree, int(s.case)
    if tree is None:
        raise InputError("truth for a model: these states are the note's chain's, not a tree's")
    sc = tree_scales(tree, c, s.q, s.u, s.udot)
    bound = np.broadcast_to(tree_tolerance(tree) - rounding_tolerance(), (len(s), tree.nb))
    if engine == "relacc":
        k = tree_kinematics(tree, c, s.q, s.u, s.udot)
        values = {name: getattr(k, name) for name in quantities}
    else:
        adapter = adapter_of(tree, engine)
        states_e = adapter.to_engine(*convert(tree, s.q, s.u, s.udot, source=c, target=2))
        qe, ve, ae, T = states_e.q, states_e.v, states_e.a, states_e.T
        ref = adapter.body_motion(qe, ve, ae)
        values = {name: ref[name] for name in quantities if name in PHYSICAL}
        values.update({name: np.einsum("nbkj,nji->nbki", ref[name], T) for name in quantities
                       if c == Case.BODY_FRAME and name in ("V", "Omega")})
    return {name: Expected(name, c, v, sc.of(name), bound, s.seed, engine, tree.body_names)
            for name, v in values.items()}


def adapter_of(tree, engine: str):
    """Engine ``engine``'s adapter of the file a tree was read from (a chain TOML's generated MJCF), matched to the
    engine's default reference (:func:`relacc.engines.load`).

    Raises:
        EngineError: a tree built in Python, which no engine has read; an unknown or missing engine.
    """
    from pathlib import Path

    from relacc.engines import load

    source = Path(tree.source) if tree.source != "python" else None
    if source is not None and source.suffix.lower() == ".toml":
        from relacc.fixtures import load as load_fixture

        source = load_fixture(source).path("two_body.xml")
    if source is None or not source.is_file():
        raise EngineError(f"tree {tree.name!r} was built in Python: {engine} has no model of it (read it from a file "
                          f"to compare with {engine})")
    return load(engine, source)


def truth_of(s: States, engine: str = "relacc") -> Truth:
    """:func:`model_truth` as a :class:`relacc.testing.expected.Truth` (``truth.velocity``, ``truth.of("V")``)."""
    return Truth(engine, s, model_truth(s, engine))
