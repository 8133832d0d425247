"""Lanes experiment (issue 35 item 3): does laying a batch of states out across vector lanes pay for forward dynamics?

One algorithm, two memory layouts, both compiled by numba with the same flags: the articulated-body algorithm for a
serial chain of hinges (each about its frame's z axis, fixed offsets between frames), written with dense 6x6 spatial
matrices so that both layouts do exactly the same arithmetic:

* ``per state``: the states are the outer loop, every quantity a scalar or small array of one state (what relacc's
  and Pinocchio's kernels do today);
* ``lanes``: blocks of ``L`` states, every quantity an array whose innermost, contiguous axis is the block's states,
  so that each arithmetic statement is a loop over ``L`` lanes the compiler can vectorize (structure of arrays).

Both run on one thread; the two agree to rounding (checked). Reported: microseconds per state, the ratio, and the
flops per state of the dense formulation counted by hand (``flops_per_state``), against the ~430 n of an
optimized ABA. This is a measurement for the next step, not a kernel relacc ships.

    .venv/bin/python benchmarks/lanes.py [--links 30] [--states 4096] [--repeats 7] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import time
from pathlib import Path

import numba
import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def chain_model(links: int, seed: int = 0):
    """Random fixed frames (rotation E0 (links, 3, 3), offset r0 (links, 3) in the parent's frame) and spatial
    inertias (links, 6, 6) about each frame's origin: mass 1 kg, a mass centre 0.1 m out, a diagonal inertia."""
    rng = np.random.default_rng(seed)
    E0 = np.empty((links, 3, 3))
    for i in range(links):
        qv = rng.standard_normal(4)
        w, x, y, z = qv / np.linalg.norm(qv)
        E0[i] = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                 [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                 [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    r0 = np.tile([0.0, 0.0, 0.2], (links, 1))
    inertia = np.zeros((links, 6, 6))
    for i in range(links):
        m, c = 1.0, np.array([0.1, 0.0, 0.0])
        C = np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])
        Ic = np.diag([0.01, 0.02, 0.015])
        inertia[i, :3, :3] = Ic + m * C @ C.T
        inertia[i, :3, 3:] = m * C
        inertia[i, 3:, :3] = m * C.T
        inertia[i, 3:, 3:] = m * np.eye(3)
    return E0, r0, inertia


@numba.njit(cache=True)
def aba_per_state(E0, r0, inertia, q, qd, tau, out):
    """The same ABA, one state after the other, every quantity a small array of one state (gravity off)."""
    n, links = q.shape
    X = np.zeros((links, 6, 6))
    v = np.zeros((links, 6))
    cc = np.zeros((links, 6))
    IA = np.zeros((links, 6, 6))
    pA = np.zeros((links, 6))
    U = np.zeros((links, 6))
    D = np.zeros(links)
    u = np.zeros(links)
    a = np.zeros(6)
    tmp = np.zeros((6, 6))
    Iv = np.zeros(6)
    pa = np.zeros(6)
    XtIa = np.zeros((6, 6))
    for s in range(n):
        for i in range(links):
            cq, sq = np.cos(q[s, i]), np.sin(q[s, i])
            for b in range(3):
                X[i, 0, b] = cq * E0[i, b, 0] + sq * E0[i, b, 1]
                X[i, 1, b] = -sq * E0[i, b, 0] + cq * E0[i, b, 1]
                X[i, 2, b] = E0[i, b, 2]
            for a_ in range(3):
                for b in range(3):
                    X[i, a_, b + 3] = 0.0
                    X[i, a_ + 3, b + 3] = X[i, a_, b]
            r = r0[i]
            for a_ in range(3):
                X[i, a_ + 3, 0] = -(X[i, a_, 1] * r[2] - X[i, a_, 2] * r[1])
                X[i, a_ + 3, 1] = -(-X[i, a_, 0] * r[2] + X[i, a_, 2] * r[0])
                X[i, a_ + 3, 2] = -(X[i, a_, 0] * r[1] - X[i, a_, 1] * r[0])
            for rr in range(6):
                v[i, rr] = 0.0
                if i > 0:
                    for k in range(6):
                        v[i, rr] += X[i, rr, k] * v[i - 1, k]
            v[i, 2] += qd[s, i]
            qv = qd[s, i]
            cc[i, 0], cc[i, 1], cc[i, 2] = v[i, 1] * qv, -v[i, 0] * qv, 0.0
            cc[i, 3], cc[i, 4], cc[i, 5] = v[i, 4] * qv, -v[i, 3] * qv, 0.0
            for rr in range(6):
                Iv[rr] = 0.0
                for k in range(6):
                    Iv[rr] += inertia[i, rr, k] * v[i, k]
            w0, w1, w2, l0, l1, l2 = v[i, 0], v[i, 1], v[i, 2], v[i, 3], v[i, 4], v[i, 5]
            pA[i, 0] = w1 * Iv[2] - w2 * Iv[1] + l1 * Iv[5] - l2 * Iv[4]
            pA[i, 1] = w2 * Iv[0] - w0 * Iv[2] + l2 * Iv[3] - l0 * Iv[5]
            pA[i, 2] = w0 * Iv[1] - w1 * Iv[0] + l0 * Iv[4] - l1 * Iv[3]
            pA[i, 3] = w1 * Iv[5] - w2 * Iv[4]
            pA[i, 4] = w2 * Iv[3] - w0 * Iv[5]
            pA[i, 5] = w0 * Iv[4] - w1 * Iv[3]
            for rr in range(6):
                for k in range(6):
                    IA[i, rr, k] = inertia[i, rr, k]
        for i in range(links - 1, -1, -1):
            for rr in range(6):
                U[i, rr] = IA[i, rr, 2]
            D[i] = U[i, 2]
            u[i] = tau[s, i] - pA[i, 2]
            if i > 0:
                for rr in range(6):
                    for k in range(6):
                        tmp[rr, k] = IA[i, rr, k] - U[i, rr] * U[i, k] / D[i]
                for rr in range(6):
                    pa[rr] = pA[i, rr] + U[i, rr] * u[i] / D[i]
                    for k in range(6):
                        pa[rr] += tmp[rr, k] * cc[i, k]
                for rr in range(6):
                    for k in range(6):
                        XtIa[rr, k] = 0.0
                        for m in range(6):
                            XtIa[rr, k] += X[i, m, rr] * tmp[m, k]
                for rr in range(6):
                    for k in range(6):
                        for m in range(6):
                            IA[i - 1, rr, k] += XtIa[rr, m] * X[i, m, k]
                    for m in range(6):
                        pA[i - 1, rr] += X[i, m, rr] * pa[m]
        for i in range(links):
            for rr in range(6):
                tmp[0, rr] = cc[i, rr]
                if i > 0:
                    for k in range(6):
                        tmp[0, rr] += X[i, rr, k] * a[k]
            dot = 0.0
            for rr in range(6):
                dot += U[i, rr] * tmp[0, rr]
            qdd = (u[i] - dot) / D[i]
            out[s, i] = qdd
            for rr in range(6):
                a[rr] = tmp[0, rr]
            a[2] += qdd


@numba.njit(cache=True, fastmath=False)
def aba_lanes(E0, r0, inertia, q, qd, tau, out, L):
    """The same ABA on blocks of ``L`` states: every quantity's last axis is the block's states (gravity off).
    ``q``, ``qd``, ``tau``, ``out`` are ``(links, n)``: states innermost."""
    links, n = q.shape
    X = np.zeros((links, 6, 6, L))
    v = np.zeros((links, 6, L))
    cc = np.zeros((links, 6, L))
    IA = np.zeros((links, 6, 6, L))
    pA = np.zeros((links, 6, L))
    U = np.zeros((links, 6, L))
    D = np.zeros((links, L))
    u = np.zeros((links, L))
    a = np.zeros((6, L))
    tmp = np.zeros((6, 6, L))
    Iv = np.zeros((6, L))
    pa = np.zeros((6, L))
    XtIa = np.zeros((6, 6, L))
    cq = np.zeros(L)
    sq = np.zeros(L)
    for start in range(0, n, L):
        for i in range(links):
            for l in range(L):
                cq[l] = np.cos(q[i, start + l])
                sq[l] = np.sin(q[i, start + l])
            for b in range(3):
                for l in range(L):
                    X[i, 0, b, l] = cq[l] * E0[i, b, 0] + sq[l] * E0[i, b, 1]
                    X[i, 1, b, l] = -sq[l] * E0[i, b, 0] + cq[l] * E0[i, b, 1]
                    X[i, 2, b, l] = E0[i, b, 2]
            for a_ in range(3):
                for b in range(3):
                    for l in range(L):
                        X[i, a_, b + 3, l] = 0.0
                        X[i, a_ + 3, b + 3, l] = X[i, a_, b, l]
            r = r0[i]
            for a_ in range(3):
                for l in range(L):
                    # -E [r x], columns: [r x] = [[0,-r2,r1],[r2,0,-r0],[-r1,r0,0]]
                    X[i, a_ + 3, 0, l] = -(X[i, a_, 1, l] * r[2] - X[i, a_, 2, l] * r[1])
                    X[i, a_ + 3, 1, l] = -(-X[i, a_, 0, l] * r[2] + X[i, a_, 2, l] * r[0])
                    X[i, a_ + 3, 2, l] = -(X[i, a_, 0, l] * r[1] - X[i, a_, 1, l] * r[0])
            for rr in range(6):
                for l in range(L):
                    v[i, rr, l] = 0.0
                if i > 0:
                    for k in range(6):
                        for l in range(L):
                            v[i, rr, l] += X[i, rr, k, l] * v[i - 1, k, l]
            for l in range(L):
                v[i, 2, l] += qd[i, start + l]
                qv = qd[i, start + l]
                cc[i, 0, l] = v[i, 1, l] * qv
                cc[i, 1, l] = -v[i, 0, l] * qv
                cc[i, 2, l] = 0.0
                cc[i, 3, l] = v[i, 4, l] * qv
                cc[i, 4, l] = -v[i, 3, l] * qv
                cc[i, 5, l] = 0.0
            for rr in range(6):
                for l in range(L):
                    Iv[rr, l] = 0.0
                for k in range(6):
                    for l in range(L):
                        Iv[rr, l] += inertia[i, rr, k] * v[i, k, l]
            for l in range(L):
                w0, w1, w2 = v[i, 0, l], v[i, 1, l], v[i, 2, l]
                l0, l1, l2 = v[i, 3, l], v[i, 4, l], v[i, 5, l]
                pA[i, 0, l] = w1 * Iv[2, l] - w2 * Iv[1, l] + l1 * Iv[5, l] - l2 * Iv[4, l]
                pA[i, 1, l] = w2 * Iv[0, l] - w0 * Iv[2, l] + l2 * Iv[3, l] - l0 * Iv[5, l]
                pA[i, 2, l] = w0 * Iv[1, l] - w1 * Iv[0, l] + l0 * Iv[4, l] - l1 * Iv[3, l]
                pA[i, 3, l] = w1 * Iv[5, l] - w2 * Iv[4, l]
                pA[i, 4, l] = w2 * Iv[3, l] - w0 * Iv[5, l]
                pA[i, 5, l] = w0 * Iv[4, l] - w1 * Iv[3, l]
            for rr in range(6):
                for k in range(6):
                    for l in range(L):
                        IA[i, rr, k, l] = inertia[i, rr, k]
        for i in range(links - 1, -1, -1):
            for rr in range(6):
                for l in range(L):
                    U[i, rr, l] = IA[i, rr, 2, l]
            for l in range(L):
                D[i, l] = U[i, 2, l]
                u[i, l] = tau[i, start + l] - pA[i, 2, l]
            if i > 0:
                for rr in range(6):
                    for k in range(6):
                        for l in range(L):
                            tmp[rr, k, l] = IA[i, rr, k, l] - U[i, rr, l] * U[i, k, l] / D[i, l]
                for rr in range(6):
                    for l in range(L):
                        pa[rr, l] = pA[i, rr, l] + U[i, rr, l] * u[i, l] / D[i, l]
                    for k in range(6):
                        for l in range(L):
                            pa[rr, l] += tmp[rr, k, l] * cc[i, k, l]
                for rr in range(6):
                    for k in range(6):
                        for l in range(L):
                            XtIa[rr, k, l] = 0.0
                        for m in range(6):
                            for l in range(L):
                                XtIa[rr, k, l] += X[i, m, rr, l] * tmp[m, k, l]
                for rr in range(6):
                    for k in range(6):
                        for m in range(6):
                            for l in range(L):
                                IA[i - 1, rr, k, l] += XtIa[rr, m, l] * X[i, m, k, l]
                    for m in range(6):
                        for l in range(L):
                            pA[i - 1, rr, l] += X[i, m, rr, l] * pa[m, l]
        for i in range(links):
            for rr in range(6):
                for l in range(L):
                    tmp[0, rr, l] = cc[i, rr, l]
                if i > 0:
                    for k in range(6):
                        for l in range(L):
                            tmp[0, rr, l] += X[i, rr, k, l] * a[k, l]
            for l in range(L):
                dot = 0.0
                for rr in range(6):
                    dot += U[i, rr, l] * tmp[0, rr, l]
                qdd = (u[i, l] - dot) / D[i, l]
                out[i, start + l] = qdd
                for rr in range(6):
                    a[rr, l] = tmp[0, rr, l]
                a[2, l] += qdd


def flops_per_state(links: int) -> int:
    """Multiply-adds of the dense formulation per state, counted as 2 flops each (an estimate of the work both
    layouts do): per link the transform (~40), v (72), Iv (72), X^T Ia (432), (X^T Ia) X (432), X^T pa (72), the
    rank-one update and pa (~150), the forward pass (~90)."""
    return links * (40 + 72 + 72 + 432 + 432 + 72 + 150 + 90)


def _best(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), float(np.min(times))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", type=int, default=30)
    parser.add_argument("--states", type=int, default=4096)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    E0, r0, inertia = chain_model(args.links)
    rng = np.random.default_rng(1)
    n = args.states
    q, qd, tau = rng.uniform(-np.pi, np.pi, (n, args.links)), rng.standard_normal((n, args.links)), \
        rng.standard_normal((n, args.links))
    out1 = np.empty((n, args.links))
    aba_per_state(E0, r0, inertia, q[:8], qd[:8], tau[:8], out1[:8])  # compile
    per = _best(lambda: aba_per_state(E0, r0, inertia, q, qd, tau, out1), args.repeats)
    rows = [{"layout": "per state", "us_per_state": per[0] / n * 1e6, "best_us_per_state": per[1] / n * 1e6}]
    qT, qdT, tauT = (np.ascontiguousarray(a.T) for a in (q, qd, tau))
    for L in (4, 8, 16):
        out2 = np.empty((args.links, n))
        aba_lanes(E0, r0, inertia, qT[:, :L], qdT[:, :L], tauT[:, :L], out2[:, :L], L)  # compile
        t = _best(lambda: aba_lanes(E0, r0, inertia, qT, qdT, tauT, out2, L), args.repeats)
        diff = float(np.abs(out2.T - out1).max() / max(1.0, np.abs(out1).max()))
        rows.append({"layout": f"lanes L={L}", "us_per_state": t[0] / n * 1e6, "best_us_per_state": t[1] / n * 1e6,
                     "over_per_state": per[0] / t[0], "relative_difference": diff})
    flops = flops_per_state(args.links)
    for r in rows:
        r["gflops"] = flops / (r["us_per_state"] * 1e-6) / 1e9
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, cwd=ROOT).stdout
    cpu = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                if line.startswith("model name")), platform.processor())
    result = {"links": args.links, "states": n, "repeats": args.repeats, "flops_per_state_dense": flops,
              "flops_per_state_optimized_aba": 430 * args.links, "rows": rows, "cpu": cpu,
              "date": time.strftime("%Y-%m-%d"), "commit": commit.strip(), "numba": numba.__version__}
    for r in rows:
        extra = f"  x{r['over_per_state']:.2f}  diff {r['relative_difference']:.1e}" if "over_per_state" in r else ""
        print(f"{r['layout']:12s} {r['us_per_state']:7.3f} us/state (best {r['best_us_per_state']:.3f})  "
              f"{r['gflops']:.2f} GFlop/s{extra}")
    if args.json:
        args.json.write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
