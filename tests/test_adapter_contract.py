"""One contract over every engine adapter (as mink's ``test_axioms.py`` runs its axioms over every Lie group).

Every adapter is a :class:`relacc.engines.base.Adapter`; every method a caller outside ``engines/`` uses is declared
there (an engine without it raises :class:`relacc.EngineError` naming itself, never ``AttributeError``); states go
to the engine and back unchanged; and the engine's forward dynamics solves its own equations of motion.
"""

import ast
from pathlib import Path

import numpy as np
import pytest

import relacc
from relacc.core.tolerances import EPS, ROUNDING_FACTOR
from relacc.core.tree import random_states
from relacc.core.tree.coordinates import rotations
from relacc.engines import ENGINES, installed, load
from relacc.engines.base import Adapter
from relacc.errors import EngineError
from relacc.fixtures.shipped import models_dir

PACKAGE = Path(relacc.__file__).parent
MODEL = models_dir() / "two_body.xml"


def _engine_only_methods() -> set:
    """Methods some concrete adapter defines that :class:`Adapter` does not declare."""
    from relacc.engines import adapter_module

    out = set()
    for engine in [e for e in ENGINES if installed(e)]:
        for cls in vars(adapter_module(engine)).values():
            if isinstance(cls, type) and issubclass(cls, Adapter) and cls is not Adapter:
                out |= {name for name, value in vars(cls).items() if callable(value) and not name.startswith("_")}
    return out - set(dir(Adapter))


def test_every_method_callers_use_is_declared_by_the_interface():
    """The benchmark anchors and batched runs included: no caller outside ``engines/`` calls a method only some
    adapters define."""
    only = _engine_only_methods()
    calls = []
    for path in PACKAGE.rglob("*.py"):
        if "engines" in path.relative_to(PACKAGE).parts:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in only:
                calls.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.func.attr}")
    assert calls == [], f"called outside engines/ but declared by no relacc.engines.base.Adapter: {calls}"


@pytest.mark.parametrize("engine", [e for e in ENGINES if installed(e)])
def test_the_contract(engine):
    tree = relacc.Tree.from_file(MODEL)
    adapter = load(engine, MODEL, tree)
    assert isinstance(adapter, Adapter) and adapter.engine == engine
    st = random_states(tree, 2, 16, 3)
    states_e = adapter.to_engine(st.q, st.u, st.udot)
    qe, ve, ae = states_e.q, states_e.v, states_e.a
    q, v = adapter.from_engine(qe, ve)
    for _, _, a, _ in rotations(tree, 2):  # a quaternion and its negative are one rotation (Drake keeps w >= 0)
        flip = np.sum(q[:, a:a + 4] * st.q[:, a:a + 4], axis=1) < 0
        q[flip, a:a + 4] *= -1
    # a conversion is a few rotations and products: c eps times the states' magnitude
    np.testing.assert_allclose(q, st.q, rtol=0, atol=ROUNDING_FACTOR * EPS * max(1.0, np.abs(st.q).max()))
    np.testing.assert_allclose(v, st.u, rtol=0, atol=ROUNDING_FACTOR * EPS * np.abs(st.u).max())
    M, f = adapter.equations(qe, ve)
    a = adapter.forward(qe, ve)
    # the engine's forward dynamics solves its own M a = f: the residual of a solve, c eps (|M| |a| + |f|)
    residual = np.abs(np.einsum("nij,nj->ni", M, a) - f).max(axis=1)
    scale = np.abs(M).max(axis=(1, 2)) * np.abs(a).max(axis=1) * M.shape[1] + np.abs(f).max(axis=1)
    assert np.all(residual <= ROUNDING_FACTOR * EPS * scale), f"{engine}: {np.max(residual / scale) / EPS:.1f} eps"
    for method, args in (("point_loop", (qe, ve, ae, ("body", tree.body_names[0]), False)),
                         ("jacobian_loop", (qe, ve, [("body", tree.body_names[0])])),
                         ("motion_loop", (qe, ve, ae, [("body", tree.body_names[0])])),
                         ("aba_in_parallel", (1, qe.T, ve.T)), ("work_data", (1,)),
                         ("step_loop", (qe[0], ve[0], 2)), ("rollout_loop", (qe, ve, 2, 1))):
        try:
            made = getattr(adapter, method)(*args)
        except EngineError as exc:
            assert engine in str(exc) and "\n" not in str(exc)
        else:
            assert made is not None, f"{engine}.{method} returned nothing"


@pytest.mark.parametrize("engine", [e for e in ENGINES if installed(e)])
def test_each_engine_has_the_traits_it_declares(engine):
    """What :func:`relacc.engines.traits` says of an engine (so callers need not branch on its name) is what its
    adapter does: compiled per-state loops that return (not raise), a URDF reader of its own in its loader, its own
    error-controlled integrators, steppers of its own, the mesh compiler relacc asks."""
    import importlib.util
    import inspect

    from relacc.core.conventions import ENGINE_INTEGRATORS
    from relacc.engines import MESH_ENGINE, adapter_module, traits
    from relacc.simulate.scenes import INTEGRATORS

    t = traits(engine)
    module = adapter_module(engine)
    tree = relacc.Tree.from_file(MODEL)
    adapter = load(engine, MODEL, tree)
    st = random_states(tree, 2, 2, 5)
    states_e = adapter.to_engine(st.q, st.u, st.udot)
    qe, ve, ae = states_e.q, states_e.v, states_e.a
    loops = {}
    for method, args in (("point_loop", (qe, ve, ae, ("body", tree.body_names[0]), False)),
                         ("jacobian_loop", (qe, ve, [("body", tree.body_names[0])]))):
        try:
            loops[method] = getattr(adapter, method)(*args) is not None
        except EngineError:
            loops[method] = False
    assert all(loops.values()) == t.compiled_loops, loops
    assert ("urdf" in inspect.signature(module.load).parameters) == t.own_urdf
    # its own integrators are the ones a scene's [simulate] table does not offer (Drake's error-controlled schemes)
    assert bool(set(ENGINE_INTEGRATORS[engine]) - set(INTEGRATORS)) == t.error_controlled
    # an engine that steps itself has a run module driving its integrators (mj_step, Drake's Simulator)
    assert (importlib.util.find_spec(f"{module.__name__}.run") is not None) == t.own_steppers
    assert (importlib.util.find_spec(f"{module.__name__}.meshes") is not None) == t.mesh_source == (
        engine == MESH_ENGINE)
