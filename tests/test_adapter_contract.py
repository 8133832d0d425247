"""One contract over every engine adapter (as mink's ``test_axioms.py`` runs its axioms over every Lie group).

Every adapter is a :class:`relacc.engines.base.Adapter`; every method a caller outside ``engines/`` uses is declared
there or by a capability (:mod:`relacc.engines.capabilities`), and each capability an adapter declares is run on it;
states go to the engine and back unchanged; and the engine's forward dynamics solves its own equations of motion.
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
from relacc.fixtures.shipped import models_dir

PACKAGE = Path(relacc.__file__).parent
MODEL = models_dir() / "two_body.xml"
URDF_MODEL = models_dir() / "two_body_euler.urdf"


def model_of(engine: str) -> Path:
    """The shipped model an engine's loader reads: the chain's MJCF, or (a URDF engine) its URDF."""
    from relacc.engines import reads

    return MODEL if reads(engine, "mjcf") else URDF_MODEL


def _engine_only_methods() -> set:
    """Methods some concrete adapter defines that :class:`Adapter` does not declare."""
    from relacc.engines import adapter_module

    out = set()
    for engine in [e for e in ENGINES if installed(e)]:
        for cls in vars(adapter_module(engine)).values():
            if isinstance(cls, type) and issubclass(cls, Adapter) and cls is not Adapter:
                out |= {name for name, value in vars(cls).items() if callable(value) and not name.startswith("_")}
    from relacc.engines.capabilities import CAPABILITIES

    return out - set(dir(Adapter)).union(*(set(dir(c)) for c in CAPABILITIES))


def test_every_method_callers_use_is_declared_by_the_interface():
    """The benchmark anchors and batched runs included: no caller outside ``engines/`` calls a method that neither
    the interface nor a capability declares."""
    only = _engine_only_methods()
    calls = []
    for path in PACKAGE.rglob("*.py"):
        if "engines" in path.relative_to(PACKAGE).parts:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in only:
                calls.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.func.attr}")
    assert calls == [], f"called outside engines/ but declared by neither Adapter nor a capability: {calls}"


@pytest.mark.parametrize("engine", [e for e in ENGINES if installed(e)])
def test_the_contract(engine):
    tree = relacc.Tree.from_file(model_of(engine))
    adapter = load(engine, model_of(engine), tree)
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
    # a match kind the adapter does not declare varying has one speed map at every position (the joint forces of a
    # stepper invert it once): exactly the same matrix at the random states as at zero positions
    for m in adapter.matches:
        if m.kind not in adapter.varying_speed_maps:
            T, _ = adapter.v_block(m, st.q[:, list(m.ref_q)], st.u[:, list(m.ref_v)])
            T0, _ = adapter.v_block(m, np.zeros((1, len(m.ref_q))), np.zeros((1, len(m.ref_v))))
            assert np.array_equal(T, np.broadcast_to(T0[0], T.shape)), f"{engine}: {m.kind}'s speed map varies"
        # its inverse (closed-form where the adapter gives one) inverts it: a product of rotations, c eps
        T, _ = adapter.v_block(m, st.q[:, list(m.ref_q)], st.u[:, list(m.ref_v)])
        eye = np.broadcast_to(np.eye(len(m.ref_v)), (len(st.q), len(m.ref_v), len(m.ref_v)))
        np.testing.assert_allclose(adapter.v_block_inverse(m, st.q[:, list(m.ref_q)]) @ T, eye, rtol=0,
                                   atol=ROUNDING_FACTOR * EPS, err_msg=f"{engine}: {m.kind}'s inverse speed map")
    M, f = adapter.equations(qe, ve)
    a = adapter.forward(qe, ve)
    # the engine's forward dynamics solves its own M a = f: the residual of a solve, c eps (|M| |a| + |f|)
    residual = np.abs(np.einsum("nij,nj->ni", M, a) - f).max(axis=1)
    scale = np.abs(M).max(axis=(1, 2)) * np.abs(a).max(axis=1) * M.shape[1] + np.abs(f).max(axis=1)
    assert np.all(residual <= ROUNDING_FACTOR * EPS * scale), f"{engine}: {np.max(residual / scale) / EPS:.1f} eps"
    from relacc.engines import capabilities as cap

    spec = ("body", tree.body_names[0])
    calls = {cap.PointLoop: [("point_loop", (qe, ve, ae, spec, False))],
             cap.KinematicsLoops: [("jacobian_loop", (qe, ve, [spec])), ("motion_loop", (qe, ve, ae, [spec]))],
             cap.BatchedForward: [("batched_forward", (1, qe.T, ve.T))],
             cap.Rollout: [("work_data", (1,)), ("step_loop", (qe[0], ve[0], 2)), ("rollout_loop", (qe, ve, 2, 1))],
             cap.ManifoldRates: [("space", ())], cap.BodyMotion: [("body_motion", (qe, ve, ae))],
             cap.ThreadedStepper: [], cap.AccelerationRoutine: [("jdot_cause", (tree,))]}
    assert set(calls) == set(cap.CAPABILITIES)  # every capability is exercised here
    for capability, methods in calls.items():
        if not isinstance(adapter, capability):
            continue
        for method, args in methods:
            made = getattr(adapter, method)(*args)
            assert made is not None, f"{engine}.{method} returned nothing"
            if hasattr(made, "close"):
                made.close()


@pytest.mark.parametrize("engine", [e for e in ENGINES if installed(e)])
def test_each_engine_has_the_traits_it_declares(engine):
    """What :func:`relacc.engines.traits` says of an engine (so callers need not branch on its name) is what its
    adapter does: compiled per-state loops that return (not raise), a URDF reader of its own in its loader, its own
    error-controlled integrators, steppers of its own, the mesh compiler relacc asks."""
    import importlib.util
    import inspect

    from relacc.engines import MESH_ENGINE, adapter_module, traits
    from relacc.engines.capabilities import CAPABILITIES, KinematicsLoops, PointLoop
    from relacc.simulate.scenes import INTEGRATORS

    t = traits(engine)
    module = adapter_module(engine)
    package = t.package_name
    adapter = load(engine, model_of(engine), relacc.Tree.from_file(model_of(engine)))
    # the capabilities its card declares (chosen by without importing it) are the ones its adapter implements
    assert t.capabilities == {c.__name__ for c in CAPABILITIES if isinstance(adapter, c)}
    assert (isinstance(adapter, PointLoop) and isinstance(adapter, KinematicsLoops)) == t.compiled_loops
    assert ("urdf" in inspect.signature(module.load).parameters) == t.own_urdf
    # its own integrators are the ones a scene's [simulate] table does not offer (Drake's error-controlled schemes)
    assert bool(set(t.integrators) - set(INTEGRATORS)) == t.error_controlled
    # an engine that steps itself has a run module driving its integrators (mj_step, Drake's Simulator)
    assert (importlib.util.find_spec(f"{package}.run") is not None) == t.own_steppers
    assert (importlib.util.find_spec(f"{package}.meshes") is not None) == t.mesh_source == (engine == MESH_ENGINE)
