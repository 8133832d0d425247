"""What a scene is simulated on: relacc's own run and each engine's, for the chain and for any model alike.

Every engine runs through its adapter (:mod:`relacc.engines.base`) from the scene's state in the reference's
coordinates (the tree's case 2: MuJoCo's ``qpos``/``qvel``), under the scene's effects by joint and body name, and
is observed at the scene's point (G2; a model's body or point). relacc's own side of a scene is one of two objects
with one interface (``adapter``, ``run``, ``acceleration``, ``integrate``, ``point``, ``reference``), which the scene
picks (:attr:`relacc.simulate.scenes.Scene.evaluator`); nothing else asks which kind of scene it has:

* :class:`NoteChain`, the chain: its compiled kernels in the case's coordinates
  (:func:`relacc.dynamics.integrate.stepper`), G2 by the note's formulas, energy and momenta by
  :mod:`relacc.dynamics`;
* :class:`ModelTree`, a model: its tree's forward dynamics (:func:`relacc.tree_accelerations`) integrated by the
  one RKMK4 on the tree's manifold in the case's coordinates (:func:`tree_stepper`), the point by
  :func:`relacc.tree_kinematics`, energy and momenta by :mod:`relacc.dynamics.tree_energy`.

An observation of a block of records ``(t, Q, U)`` is ``{position, velocity, acceleration (n, 3), energy,
energy_scale (n,), momentum, angular_momentum (n, 3)}``, fixed-frame components.
"""

from __future__ import annotations

import time

import numpy as np

from relacc.core.cases import Case
from relacc.core.tolerances import rounding_tolerance
from relacc.errors import EngineError, InputError, IntegrationError, ModelError


def _observation(position, velocity, acceleration, energy_terms, momentum, angular_momentum) -> dict:
    """One block's observation (the module docstring): the energy from its terms ``(T, V_g, V_s)`` (J), and the
    energy's scale ``T + |V_g| + V_s`` that its drift is measured against."""
    T, g, s = energy_terms
    return {"position": position, "velocity": velocity, "acceleration": acceleration, "energy": T + g + s,
            "energy_scale": T + np.abs(g) + s, "momentum": momentum, "angular_momentum": angular_momentum}


def reference_state(scene, q, u, case=None) -> tuple[np.ndarray, np.ndarray]:
    """States of ``case`` (default the scene's) ``(n, nq)``, ``(n, nv)`` in the reference's coordinates (the
    adapters'): the case-2 coordinates of the scene's tree (the chain's too)."""
    from relacc.core.tree.coordinates import convert

    q2, u2, _ = convert(scene.subject_tree, q, u, source=scene.case if case is None else case, target=2)
    return q2, u2


def adapter(scene, name: str):
    """Engine ``name``'s adapter of the scene's model (the chain: the quaternion route's, ``two_body.xml``).

    Raises:
        EngineError: a model's engine whose reading lacks some of its joints, or whose forward dynamics at the initial
            state is not finite.
    """
    return scene.evaluator.adapter(scene, name)


def _tree_adapter(scene, name: str):
    from relacc.engines import load

    engine = load(name, scene.model_path, scene.tree)
    shared = set(engine.dofs.tolist())
    lacks = [j.name for (_, j), a in zip(scene.tree.joints, scene.tree.dofadr) if not shared >= set(range(a, a + j.nv))]
    if lacks:
        raise EngineError(f"{name} cannot simulate {scene.model_path.name}: its reading lacks the joints "
                          f"{', '.join(lacks)} (relacc compare says why)")
    q2, u2 = reference_state(scene, scene.q, scene.u)
    with np.errstate(all="ignore"):
        forward = engine.dynamics(q2, u2).forward
    if forward is not None and not np.all(np.isfinite(forward)):  # no trajectory: say why, not "reduce the step"
        raise EngineError(f"{name} cannot simulate {scene.model_path.name}: its forward dynamics at the initial state "
                          "is not finite (its mass matrix is singular: it reads the file as another model, relacc "
                          "compare says how)")
    return engine


def usable(scene) -> tuple[tuple[str, ...], tuple[tuple[str, str], ...]]:
    """``(engines, left_out)``: the scene's engines that read every joint of its model, and ``(engine, why)`` for
    each that does not (a model's default scene runs without them and says so)."""
    kept, left = [], []
    for name in scene.engines:
        if name == "relacc":
            kept.append(name)
            continue
        try:
            adapter(scene, name)
        except (EngineError, ModelError) as exc:
            left.append((name, str(exc).removeprefix(f"{name} cannot simulate {scene.model_path.name}: ")))
        else:
            kept.append(name)
    return tuple(kept), tuple(left)


def engine_observer(engine, scene):
    """An engine's observation of a block of its own states: the point, energy and momenta."""
    eff = scene.engine_effects

    def observe(t, Q, V):
        pts = engine.points(Q, V, engine.forward(Q, V, eff, t), [scene.point])
        T, g, s = engine.energy(Q, V, eff)
        p, H = engine.momenta(Q, V)
        return _observation(pts.position[:, 0], np.einsum("nij,nj->ni", pts.J[:, 0], V),
                            point_acceleration(engine, scene, Q, V, t, pts), (T, g, s), p, H)

    return observe


def point_acceleration(engine, scene, qe, ve, t, pts) -> np.ndarray:
    """``(n, 3)`` the scene's point's classical acceleration (m/s^2, fixed components) at engine states, from the
    engine's forward dynamics under the scene's effects: its own point acceleration (``pts``: its :class:`Points` at
    those rates); for an engine that offers none (:attr:`relacc.engines.base.Adapter.point_rates`, PyBullet), its joint
    accelerations carried to the point by relacc's tree, ``J a + J_dot v``, so that what is judged is still the
    engine's dynamics, at the same states."""
    if getattr(engine, "point_rates", True):
        return pts.acceleration[:, 0]
    q2, v2 = engine.from_engine(qe, ve)
    T, Td = engine.speed_map(q2, v2)
    a_e = engine.forward(qe, ve, scene.engine_effects, t)
    a2 = np.zeros_like(v2)
    a2[:, engine.dofs] = np.linalg.solve(T, (a_e - np.einsum("nij,nj->ni", Td, v2[:, engine.dofs]))[..., None])[..., 0]
    return tree_point(scene, q2, v2, a2, case=2)[2]


def relacc_run(scene, integrator):
    """``(stepper, observe, applied)``: relacc's own run of the scene in its case's coordinates."""
    return scene.evaluator.run(scene, integrator)


def tree_point(scene, Q, U, Udot, case=None):
    """``(position, velocity, acceleration)``, each ``(n, 3)``, of the scene's point (a body's mass centre or a named
    point) by relacc's tree from states ``Q, U, Udot`` in ``case`` (default the scene's): fixed-frame components, m,
    m/s and m/s^2 (classical)."""
    from relacc.core.tree import tree_kinematics

    case = scene.case if case is None else case
    kind, name = scene.point
    if kind == "point":
        points = tree_kinematics(scene.tree, case, Q, U, Udot, points=[name]).points
        if points is None or points.acceleration is None:  # asked for one point with Udot: never
            raise AssertionError(f"relacc's tree gave no kinematics of point {name!r}")
        return points.position[:, 0], points.velocity[:, 0], points.acceleration[:, 0]
    k = tree_kinematics(scene.tree, case, Q, U, Udot)
    b = scene.tree.body(name)
    if k.acceleration is None:  # given Udot: never
        raise AssertionError("relacc's tree gave no accelerations")
    return k.position[:, b], k.velocity[:, b], k.acceleration[:, b]


def tree_stepper(tree, case, effects, dt: float, integrator: str):
    """relacc's fixed-step integrator for a tree (:mod:`relacc.dynamics.integrate`: RKMK4 or semi-implicit Euler on
    the tree's manifold, :class:`relacc.dynamics.integrate.TreeSpace`) with Kane's accelerations under exactly
    ``effects``, in ``case``'s coordinates; one state or a batch of rows; time runs on from 0.

    Raises:
        EngineError: an integrator relacc lacks.
    """
    from relacc.core.tree.coordinates import convert
    from relacc.dynamics.integrate import STEPPERS, TreeSpace, space_stepper
    from relacc.dynamics.tree import tree_accelerations
    from relacc.errors import EngineError
    from relacc.kernels.jit import HAVE_NUMBA

    if integrator not in STEPPERS:
        raise EngineError(f"relacc integrators: {', '.join(STEPPERS)}; got {integrator!r}")
    def derivs(q, u, t):  # the tangent: case-2 speeds on the quaternions' manifold (cases 1-2), the rates (case 3)
        udot = tree_accelerations(tree, case, q, u, effects=effects, t=t)
        return (u if int(case) != 1 else convert(tree, q, u, source=case, target=2)[1]), np.asarray(udot)

    if HAVE_NUMBA:
        from relacc.dynamics.integrate import tree_stepper_compiled

        return tree_stepper_compiled(tree, effects, dt, integrator, derivs, case)
    return space_stepper(TreeSpace(tree, case), derivs, dt, integrator)


def note_check(scene, states, engines: dict, case=None) -> dict:
    """relacc's acceleration of the scene's point against each engine's, at states ``[(q, u, t)]`` of ``case``
    (default the scene's; 2: the reference's coordinates): error and bound.

    Both sides solve their own equations of motion, so rounding is amplified by the conditioning of the mass
    matrix: the bound is ``c eps kappa(M)`` with ``M`` in case-2 speeds (the point's acceleration does not depend
    on the chart; largest over the states). The error is normalized by the acceleration's term scale. The chain:
    the note's ``a_G2`` (:func:`relacc.g2_kinematics` with Kane's ``udot``).
    """
    from relacc.core.tolerances import normalized_error

    Q, U = np.array([s[0] for s in states]), np.array([s[1] for s in states])
    t = np.array([s[2] for s in states])
    case = scene.case if case is None else int(case)
    mine, scale, M2 = scene.evaluator.acceleration(scene, t, Q, U, case)
    bound = float(rounding_tolerance() * np.max(np.linalg.cond(M2)))
    q2, v2 = reference_state(scene, Q, U, case)
    out = {}
    for name, engine in engines.items():
        states_e = engine.to_engine(q2, v2)
        qe, ve = states_e.q, states_e.v
        pts = engine.points(qe, ve, engine.forward(qe, ve, scene.engine_effects, t), [scene.point])
        theirs = point_acceleration(engine, scene, qe, ve, t, pts)
        out[name] = {"error": float(np.max(normalized_error(theirs, mine, scale))), "bound": bound}
    return out


def _tree_acceleration(scene, t, Q, U, case):
    from relacc.core.tree import convert
    from relacc.core.tree.scales import tree_scales
    from relacc.dynamics.tree import tree_accelerations, tree_dynamics

    tree, eff = scene.tree, scene.effects
    Udot = tree_accelerations(tree, case, Q, U, effects=eff, t=t)
    _, _, acc = tree_point(scene, Q, U, Udot, case)
    kind, name = scene.point
    if kind == "point":  # the scale of the point's own offset on its body
        pt = tree.points[tree.point_names.index(name)]
        at = [np.zeros(3) if b != pt.body else pt.pos for b in range(tree.nb)]
        b = pt.body
    else:
        at, b = None, tree.body(name)
    scale = tree_scales(tree, case, Q, U, Udot, at=at).of("acceleration")[:, b]
    q2, v2 = reference_state(scene, Q, U, case)
    d = tree_dynamics(tree, 2, q2, v2, effects=eff, t=t)
    udot2 = Udot if case == Case.BODY_FRAME else convert(tree, Q, U, Udot, source=case, target=2)[2]
    return acc, scale + _solve_scale(scene, q2, v2, udot2, d), d.M


def _solve_scale(scene, q2, v2, udot, d) -> np.ndarray:
    """``(n,)`` the part of the point's acceleration's scale that its forward dynamics contributes (``udot``: relacc's
    ``(n, nv)`` accelerations at those states in case-2 speeds; ``d``: the case-2 equations there): the point's
    partial velocities times the speeds' rates as a solve perturbs them: ``|delta udot| <= c eps (kappa(M) |udot| +
    ||M^-1|| |terms of f|) = c eps kappa(M) (|udot| + |terms of f| / ||M||)``, so with the bound ``c eps kappa(M)``
    the scale is ``max|V_p| (|udot| + |terms of f| / ||M||)`` (case 2; the terms: ``|f|`` and the velocity products
    before they cancel, :func:`relacc.core.tree.scales.velocity_terms`). The kinematic term scale alone vanishes
    where a state's forces cancel by symmetry (gymnasium's ant with mirrored leg speeds: its torso's acceleration is
    zero, each engine's rounding of the legs' reactions is not), so that every engine would be called wrong there."""
    from relacc.core.tree import tree_kinematics
    from relacc.core.tree.scales import extent, velocity_terms

    tree = scene.model_tree
    kind, name = scene.point
    M, f = np.asarray(d.M), np.asarray(d.f)
    if kind == "point":
        points = tree_kinematics(tree, 2, q2, v2, points=[name]).points
        if points is None:  # asked for by name, so always evaluated
            raise InputError(f"point {name!r} of {tree.name} was not evaluated")
        V = points.required("V")[:, 0]
    else:
        V = tree_kinematics(tree, 2, q2, v2).required("V")[:, tree.body(name)]
    terms = np.abs(f).max(axis=-1) + velocity_terms(tree, q2, v2, extent(tree))
    return np.abs(V).max(axis=(-2, -1)) * (np.abs(udot).max(axis=-1) + terms / np.linalg.norm(M, 2, axis=(-2, -1)))


def gaps(steps) -> np.ndarray:
    """Steps between consecutive records ``(m,)`` (int64), the first from step 0."""
    return np.diff(np.concatenate([[0], steps])).astype(np.int64)


def check_done(done, m, steps, scene, who) -> None:
    """Each member's records made ``done (N,)`` of ``m``; the first member that stopped short diverged.

    Raises:
        IntegrationError: which member, between which records, at which step.
    """
    bad = np.flatnonzero(done < m)
    if bad.size:
        i, j = int(bad[0]), int(done[bad[0]])
        raise IntegrationError(f"{who}: member {i} diverged between t = {steps[j - 1] * scene.dt if j else 0:.6g} s "
                               f"and t = {steps[j] * scene.dt:.6g} s (dt = {scene.dt} s); reduce the step")


def batched(stepper, x, v, steps, scene, who):
    """Every member at once through a stepper that takes batches of rows; ``(Q (n, m, .), V, seconds)``."""
    n, m = len(x), len(steps)
    Q, V = np.empty((n, m, x.shape[1])), np.empty((n, m, v.shape[1]))
    Q[:, 0], V[:, 0] = x, v
    seconds = 0.0
    for j, gap in enumerate(gaps(steps)[1:], start=1):
        start = time.perf_counter()
        with np.errstate(all="ignore"):  # a diverging member is reported by its record, not by warnings
            x, v = stepper.advance(x, v, int(gap))
        seconds += time.perf_counter() - start
        Q[:, j], V[:, j] = x, v
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v))):
            check_done(np.where(np.all(np.isfinite(x), axis=1), m, j), m, steps, scene, who)
    return Q, V, seconds


class NoteChain:
    """relacc's side of a scene of the note's chain: its answer is the note's, G2 by its formulas
    (:func:`relacc.g2_kinematics`) with Kane's accelerations of the chain (:mod:`relacc.dynamics`), its runs on the
    chain's fused kernels (:mod:`relacc.kernels.dynamics`: 6.5-8x faster a step than the tree stepper on the chain's
    tree, benchmarks/history.md); the engines read the chain's generated model files. The same methods as
    :class:`ModelTree`."""

    reference = "the note's"
    """Whose acceleration the engines are judged against, in words (``relacc simulate --json``'s ``reference``)."""

    def adapter(self, scene, name: str):
        """Engine ``name``'s adapter of the chain's model file (the quaternion route's, ``two_body.xml``)."""
        from relacc.engines import load_engine

        return load_engine(name, scene.fixture).adapter

    def run(self, scene, integrator):
        """``(stepper, observe, applied)`` in the case's coordinates (:func:`relacc_run`)."""
        from relacc import dynamics
        from relacc.dynamics.integrate import stepper

        chain, case, eff = scene.fixture.chain, scene.case, scene.effects

        def observe(t, Q, U):
            T, g, s = dynamics.energy_terms(chain, case, Q, U, eff)
            p, H = dynamics.momenta(chain, case, Q, U)
            return _observation(*self.point(scene, Q, U, t), (T, g, s), p, H)

        return (stepper(chain, case, eff, scene.dt, integrator), observe,
                {"equations": "Newton-Euler per body (Kane's, solved), " + (", ".join(eff.active()) or "no effects")})

    def acceleration(self, scene, t, Q, U, case):
        """``(acceleration (n, 3), term scale (n,), M in case-2 speeds (n, nv, nv))`` of G2 at states of ``case``."""
        from relacc import dynamics
        from relacc.core.kinematics import g2_kinematics
        from relacc.core.scales import term_scales
        from relacc.core.speeds import to_body_speeds

        chain, eff = scene.fixture.chain, scene.effects
        Udot = dynamics.accelerations(chain, case, Q, U, eff)
        q14, nu, _ = to_body_speeds(case, Q, U)
        return (g2_kinematics(chain, case, Q, U, Udot).acceleration, term_scales(chain, case, Q, U, Udot).acceleration,
                dynamics.equations_of_motion(chain, 2, q14, nu, eff)[0])

    def integrate(self, scene, q0, u0, steps, threads):
        """``(Q (N, m, nq), U (N, m, 12), seconds)``: every member ``q0 (N, nq)``, ``u0 (N, 12)`` to every record
        ``steps (m,)``, in parallel on ``threads`` (one compiled loop a member).

        Raises:
            EngineError: an integrator the kernels lack. IntegrationError: a member diverged.
        """
        from relacc.kernels import dynamics as kernel
        from relacc.kernels.jit import threads as kernel_threads

        integrator, _ = scene.integrator_for("relacc")
        if integrator not in kernel.INTEGRATORS:
            raise EngineError(f"relacc integrators: {', '.join(kernel.INTEGRATORS)}; got {integrator!r}")
        n, m = len(q0), len(steps)
        Q, U, done = np.empty((n, m, q0.shape[1])), np.empty((n, m, 12)), np.empty(n, dtype=np.int64)
        args = (int(scene.case), kernel.INTEGRATORS[integrator], q0, u0, float(scene.dt), gaps(steps),
                kernel.chain_params(scene.fixture.chain), kernel.effect_params(scene.effects), Q, U, done)
        with kernel_threads(threads):
            start = time.perf_counter()
            with np.errstate(all="ignore"):
                kernel.ensemble(*args)
            seconds = time.perf_counter() - start
        check_done(done, m, steps, scene, "relacc")
        return Q, U, seconds

    def point(self, scene, Q, U, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(position, velocity, acceleration)`` ``(n, 3)`` of G2 at states ``Q``, ``U`` of the scene's case and
        times ``t (n,)``: the note's formulas with Kane's accelerations."""
        from relacc import dynamics
        from relacc.core.kinematics import g2_kinematics

        chain, case = scene.fixture.chain, scene.case
        k = g2_kinematics(chain, case, Q, U, dynamics.accelerations(chain, case, Q, U, scene.effects))
        if k.acceleration is None:  # given udot: never
            raise AssertionError("relacc's G2 kinematics gave no acceleration")
        return k.position, k.velocity, k.acceleration


class ModelTree:
    """relacc's side of a scene of a model file: its tree's forward dynamics (:func:`relacc.tree_accelerations`),
    integrated by :func:`tree_stepper`, the point by :func:`relacc.tree_kinematics`. The same methods as
    :class:`NoteChain`."""

    reference = "relacc's"
    """Whose acceleration the engines are judged against, in words (``relacc simulate --json``'s ``reference``)."""

    def adapter(self, scene, name: str):
        """Engine ``name``'s adapter of the model file, matched to relacc's tree of it (:func:`adapter`)."""
        return _tree_adapter(scene, name)

    def run(self, scene, integrator):
        """``(stepper, observe, applied)`` in the case's coordinates (:func:`relacc_run`)."""
        from relacc.dynamics.tree_energy import tree_energy, tree_momenta

        tree, eff = scene.tree, scene.effects

        def observe(t, Q, U):
            q2, v2 = reference_state(scene, Q, U)
            p, H = tree_momenta(tree, q2, v2)
            return _observation(*self.point(scene, Q, U, t), tree_energy(tree, q2, v2, eff), p, H)

        return (tree_stepper(tree, scene.case, eff, scene.dt, integrator), observe,
                {"equations": "Kane's equations of the tree (relacc.tree_accelerations), "
                              + (", ".join(eff.active()) or "no effects")})

    def acceleration(self, scene, t, Q, U, case):
        """As :meth:`NoteChain.acceleration`, of the scene's point."""
        return _tree_acceleration(scene, t, Q, U, case)

    def integrate(self, scene, q0, u0, steps, threads):
        """As :meth:`NoteChain.integrate`: the tree stepper on every member at once, each stage's forward dynamics
        over the members compiled, on ``threads``."""
        from relacc.kernels.jit import threads as kernel_threads

        integrator, _ = scene.integrator_for("relacc")
        stepper = tree_stepper(scene.tree, scene.case, scene.effects, scene.dt, integrator)
        stepper.load()  # compiled before the integration is timed
        with kernel_threads(threads):
            return batched(stepper, q0, u0, steps, scene, "relacc")

    def point(self, scene, Q, U, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """As :meth:`NoteChain.point`, of the scene's point, by relacc's tree."""
        from relacc.dynamics.tree import tree_accelerations

        return tree_point(scene, Q, U, tree_accelerations(scene.tree, scene.case, Q, U, effects=scene.effects, t=t))


NOTE_CHAIN, MODEL_TREE = NoteChain(), ModelTree()
"""The two sides relacc takes in a scene (:attr:`relacc.simulate.scenes.Scene.evaluator`)."""
