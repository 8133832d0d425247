"""relacc's tree kernels against the engines users would otherwise pick, on real models and long chains.

* ``dynamics``: forward dynamics with the file's gravity. relacc: :func:`relacc.tree_accelerations` (compiled,
  ``out=``), per case; Pinocchio: ``pin.abaInParallel`` on its own reading of the same file (a ``ModelPool``,
  inputs in its column-major layout), the same states. Microseconds per state, 1 thread and every core.
* ``kinematics``: every body's mass-centre position, velocity, classical acceleration, ``V``, ``Vdot``, ``Omega``,
  ``Omegadot``. relacc: :func:`relacc.tree_kinematics` with ``out=`` (the steady state) and on fresh memory (the
  first call's); Pinocchio: ``computeJointJacobiansTimeVariation`` and the frame getters per body in a loop;
  MuJoCo: ``mj_jac`` and ``mj_jacDot`` per body in a loop. Microseconds per state.
* ``kinematics`` without partials: relacc's ``tree_kinematics(..., partials=False)`` (each body's mass-centre
  position, velocity, classical acceleration, angular velocity and acceleration, orientation) against Pinocchio's
  ``forwardKinematics`` with frame getters and MuJoCo's ``mj_kinematics``, ``mj_comVel``, ``mj_rnePostConstraint``
  with ``mj_objectVelocity``/``mj_objectAcceleration``, per body in a loop (each row records its largest difference
  from relacc's values); and ``np.copyto`` of the full kinematics' output, the time to write those bytes once.
* ``scaling``: relacc's kinematics and dynamics on chains of 2 to 60 bodies, one hinge (or one ball) per body
  after a free root: the cost against the number of bodies and of speeds.

Models: gymnasium's ``ant.xml`` and ``humanoid.xml`` and a 30-link chain (:func:`chain_mjcf`). Every figure is the
median and the minimum of ``repeats`` timings after warm-ups (:func:`relacc.tradeoff.throughput.wall_times`).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

import relacc
from relacc.core.tree import random_states
from relacc.engines import anchors
from relacc.kernels.jit import threads as numba_threads
from relacc.kernels.tree_dynamics import optimize
from relacc.tradeoff.throughput import machine, wall_times


def chain_mjcf(n_bodies: int, joint: str = "hinge") -> str:
    """An MJCF chain: a free root, then ``n_bodies - 1`` bodies each 0.2 m on, each on one ``joint`` (hinges about
    alternating y and z axes, or balls), with off-axis mass centres and unequal principal moments."""
    lines = ['<mujoco model="chain"><compiler angle="radian"/><option gravity="0 0 -9.81"/><worldbody>',
             '<body name="b0" pos="0 0 1"><freejoint name="root"/>'
             '<inertial pos="0.1 0.01 0" mass="1" diaginertia="0.01 0.02 0.025"/>']
    for k in range(1, n_bodies):
        kind = f'type="hinge" axis="{"0 1 0" if k % 2 else "0 0 1"}"' if joint == "hinge" else 'type="ball"'
        lines.append(f'<body name="b{k}" pos="0.2 0 0"><joint name="j{k}" {kind}/>'
                     '<inertial pos="0.1 0.01 0" mass="0.5" diaginertia="0.005 0.01 0.012"/>')
    lines.append("</body>" * n_bodies + "</worldbody></mujoco>")
    return "\n".join(lines)


def gymnasium_models() -> dict:
    """``{"ant": path, "humanoid": path}`` of gymnasium's MuJoCo assets (gymnasium is the test extra)."""
    import gymnasium

    assets = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
    return {name: assets / f"{name}.xml" for name in ("ant", "humanoid")}


def thread_counts() -> tuple[int, ...]:
    cores = os.cpu_count() or 1
    return (1,) if cores == 1 else (1, cores)


def _row(section, model, who, threads, seconds, n, **extra):
    median, best = seconds
    return {"section": section, "model": model, "who": who, "threads": threads, "value": 1e6 * median / n,
            "value_best": 1e6 * best / n, "unit": "us/state", **extra}


def _outputs(tree, n):
    shapes = {"position": (3,), "velocity": (3,), "acceleration": (3,), "omega": (3,), "alpha": (3,),
              "rotation": (3, 3), "V": (3, tree.nv), "Vdot": (3, tree.nv), "Omega": (3, tree.nv),
              "Omegadot": (3, tree.nv)}
    return {k: np.zeros((n, tree.nb) + s) for k, s in shapes.items()}


LEAN = ("position", "velocity", "acceleration", "omega", "alpha", "rotation")
"""What :func:`relacc.tree_kinematics` returns with ``partials=False``."""


def _difference(loop, truth) -> float:
    """The largest difference (m, m/s, m/s^2) between an anchor loop's mass-centre position, velocity and classical
    acceleration and relacc's: the anchor computes what relacc does (gravity off in the engines' models)."""
    return float(max(np.abs(loop.pos - truth.position).max(), np.abs(loop.vel - truth.velocity).max(),
                     np.abs(loop.acc - truth.acceleration).max()))


def model_rows(name, path, n_states, repeats, seed, anchors=True) -> list:
    """The dynamics and kinematics rows of one model file (see the module docstring)."""
    from relacc.core.tree import convert
    from relacc.engines import anchor, installed, load, with_capability
    from relacc.engines.base import body, com
    from relacc.engines.capabilities import BatchedForward, KinematicsLoops

    tree = relacc.Tree.from_file(path)
    st = random_states(tree, 2, n_states, seed)
    rows = []
    acc = np.empty((n_states, tree.nv))
    for case in (1, 2, 3):
        q, u, _ = convert(tree, st.q, st.u, source=2, target=case)
        for t in thread_counts():
            with numba_threads(t):
                optimize(tree, case)  # the steady state: the lanes' -O2 code (the same bits as the first, -O0)
                secs = wall_times(lambda: relacc.tree_accelerations(tree, case, q, u, out=acc), repeats)
            rows.append(_row("dynamics", name, "relacc tree_accelerations", t, secs, n_states, case=case))
    adapters = {}
    if anchors:
        for engine in with_capability(KinematicsLoops) + with_capability(BatchedForward):
            if engine not in adapters and installed(engine):
                adapters[engine] = load(engine, path, tree)  # matched to relacc's reading, body by body
        for engine, adapter in adapters.items():
            if isinstance(adapter, BatchedForward):
                states_e = adapter.to_engine(st.q, st.u)
                for t in thread_counts():
                    secs = wall_times(adapter.batched_forward(t, states_e.q.T, states_e.v.T), repeats)
                    rows.append(_row("dynamics", name, anchor(engine, "batched_forward"), t, secs, n_states,
                                     case=None))
    small = max(200, n_states // 20)  # the loops run from Python: fewer states, the same per-state figure
    out = _outputs(tree, n_states)
    for t in thread_counts():
        with numba_threads(t):
            secs = wall_times(lambda: relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, out=out), repeats)
        rows.append(_row("kinematics", name, "relacc tree_kinematics out=", t, secs, n_states, case=2))
    lean = {k: v for k, v in _outputs(tree, n_states).items() if k in LEAN}
    for t in thread_counts():
        with numba_threads(t):
            secs = wall_times(lambda: relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, out=lean, partials=False),
                              repeats)
        rows.append(_row("kinematics", name, "relacc tree_kinematics partials=False out=", t, secs, n_states, case=2))
    full = {k: np.ones_like(v) for k, v in out.items()}
    def copy_all():
        for k in out:
            np.copyto(out[k], full[k])

    secs = wall_times(copy_all, repeats)
    rows.append(_row("kinematics", name, "np.copyto of the full output", 1, secs, n_states, case=None))
    fresh = []
    for _ in range(3):  # new output arrays on every call: fresh pages each time
        import time

        start = time.perf_counter()
        relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot)
        fresh.append(time.perf_counter() - start)
    rows.append(_row("kinematics", name, "relacc tree_kinematics (new outputs)", thread_counts()[-1],
                     (float(np.median(fresh)), float(np.min(fresh))), n_states, case=2))
    truth = relacc.tree_kinematics(tree, 2, st.q[:small], st.u[:small], st.udot[:small], partials=False) \
        if adapters else None
    for engine, adapter in adapters.items():
        if not isinstance(adapter, KinematicsLoops):
            continue
        # on the reference's bodies where they are the engine's, else on its rigid links' mass centres (no more
        # frames than relacc's bodies)
        specs = ([body(b.name) for b in tree.bodies] if adapter.LOOPS_ON_BODIES
                 else [com(link.name) for link in adapter.structure.links])
        states_e = adapter.to_engine(st.q[:small], st.u[:small], st.udot[:small])
        secs = wall_times(adapter.jacobian_loop(states_e.q, states_e.v, specs), max(3, repeats // 2), warmups=1)
        rows.append(_row("kinematics", name, anchor(engine, "jacobians"), 1, secs, small, case=None))
        loop = adapter.motion_loop(states_e.q, states_e.v, states_e.rates, specs)
        secs = wall_times(loop, max(3, repeats // 2), warmups=1)
        same = {"largest_difference": _difference(loop, truth)} if adapter.LOOPS_ON_BODIES else {}
        rows.append(_row("kinematics", name, anchor(engine, "motion"), 1, secs, small, case=None,
                         frames=len(specs), **same))
    return rows


def scaling_rows(sizes, n_states, repeats, seed) -> list:
    """relacc's kinematics (case 2, ``out=``) and dynamics (case 2) on hinge and ball chains of ``sizes`` bodies."""
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for joint in ("hinge", "ball"):
            for nb in sizes:
                path = Path(tmp) / f"chain_{joint}_{nb}.xml"
                path.write_text(chain_mjcf(nb, joint))
                tree = relacc.Tree.from_file(path)
                st = random_states(tree, 2, n_states, seed)
                out, acc = _outputs(tree, n_states), np.empty((n_states, tree.nv))
                secs = wall_times(lambda: relacc.tree_kinematics(tree, 2, st.q, st.u, st.udot, out=out), repeats)
                rows.append(_row("scaling", f"{joint} chain", "relacc tree_kinematics out=", thread_counts()[-1],
                                 secs, n_states, bodies=nb, speeds=tree.nv))
                optimize(tree, 2)
                secs = wall_times(lambda: relacc.tree_accelerations(tree, 2, st.q, st.u, out=acc), repeats)
                rows.append(_row("scaling", f"{joint} chain", "relacc tree_accelerations", thread_counts()[-1],
                                 secs, n_states, bodies=nb, speeds=tree.nv))
    return rows


def run(n_states: int = 20_000, repeats: int = 7, seed: int = 0, sizes=(2, 5, 10, 20, 30, 45, 60),
        scaling_states: int = 5000) -> dict:
    """Every section; ``{"machine": ..., "rows": [...], "ratios": {...}}``."""
    info = machine()
    rows = []
    for name, path in gymnasium_models().items():
        rows += model_rows(name, path, n_states, repeats, seed)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "chain30.xml"
        path.write_text(chain_mjcf(30))
        rows += model_rows("chain30", path, n_states, repeats, seed)
    rows += scaling_rows(sizes, scaling_states, max(3, repeats // 2), seed)
    return {"machine": info, "n_states": n_states, "repeats": repeats, "rows": rows, "ratios": ratios(rows)}


def ratios(rows) -> dict:
    """Each anchor's time over relacc's, per model, at every core: ``{model: {what: (median ratio, best ratio)}}``."""
    t = thread_counts()[-1]
    out = {}
    for model in sorted({r["model"] for r in rows if r["section"] != "scaling"}):
        pick = {(r["who"], r["threads"], r.get("case")): r for r in rows if r["model"] == model}

        slowest = max((r for r in rows if r["model"] == model and r["who"] == "relacc tree_accelerations"
                       and r["threads"] == t), key=lambda r: r["value"])
        mine_k = pick[("relacc tree_kinematics out=", t, 2)]
        entry = {}
        for who in anchors("batched_forward"):
            if (who, t, None) in pick:
                aba = pick[(who, t, None)]
                entry[f"dynamics vs {who.split(' ', 1)[1]}"] = (aba["value"] / slowest["value"], aba["value_best"] /
                                                                slowest["value_best"])
        for who in anchors("jacobians"):
            if (who, 1, None) in pick:
                r = pick[(who, 1, None)]
                entry[f"kinematics vs {who}"] = (r["value"] / mine_k["value"], r["value_best"] / mine_k["value_best"])
        lean = pick.get(("relacc tree_kinematics partials=False out=", t, 2))
        for who in anchors("motion"):
            if lean and (who, 1, None) in pick:
                r = pick[(who, 1, None)]
                entry[f"partials=False vs {who}"] = (r["value"] / lean["value"], r["value_best"] / lean["value_best"])
        copy = pick.get(("np.copyto of the full output", 1, None))
        if copy:
            entry["kinematics with partials over np.copyto of its output"] = (
                mine_k["value"] / copy["value"], mine_k["value_best"] / copy["value_best"])
        out[model] = entry
    return out


def print_table(result) -> None:
    m = result["machine"]
    print(f"relacc trees benchmark: {m['cpu']}, {m['logical_cpus']} logical CPUs, {m['date']}, relacc "
          f"{m['relacc']} ({m['relacc_commit']}); {result['n_states']} states, median (best) of {result['repeats']}")
    print(f"{'section':10s}  {'model':12s}  {'who':38s}  {'threads':>7s}  {'case':>4s}  {'us/state':>9s}  {'best':>9s}")
    for r in result["rows"]:
        model = r["model"] if r["section"] != "scaling" else f"{r['model']} {r['bodies']}"
        case = "" if r.get("case") is None else str(r["case"])
        print(f"{r['section']:10s}  {model:12s}  {r['who']:38s}  {r['threads']:7d}  {case:>4s}  {r['value']:9.3f}  "
              f"{r['value_best']:9.3f}")
    for model, entry in result["ratios"].items():
        for what, (med, best) in entry.items():
            print(f"{model}: {what}: {med:.2f}x (on best times {best:.2f}x)")
