"""The lanes kernel against the machine's limit: flops a state, GFlop/s on one thread, and the measured FMA peak.

* **Flops a state** are counted on the traced kernel itself (:func:`relacc.kernels.lanes.trace`, the operations an
  output or a check needs): an addition, subtraction, multiplication, division or negation 1, a multiply-add 2, and
  each angle's sine and cosine the 54 operations of the fdlibm pair written into the IR (one angle's share of
  :func:`relacc.kernels.lanes._trig`, counted from the IR it emits).
* **GFlop/s**: those flops over the time a state takes in a batch of ``--states`` states on one thread (the kernel's
  ``-O2`` code, :func:`relacc.kernels.tree_dynamics.optimize`; median of ``--repeats``).
* **Peak**: a probe compiled the same way (llvmlite, this CPU, ``-O2``): ``--chains`` independent ``llvm.fma`` chains
  on the kernel's vector width, 2 flops a lane each; what one core can reach with that vector width.

One state at a time (against ``pin.aba``) is ``benchmarks/single.py``'s.

Models: gymnasium's ant and humanoid. Run it in a fresh process, on a quiet machine.

Run:  python benchmarks/flops.py [--states 8192] [--repeats 7] [--json PATH]
"""

import argparse
import ctypes
import json
import statistics
import sys
import time
from importlib.util import find_spec
from pathlib import Path

import numpy as np

from relacc.files import write_text

MODELS = ("ant", "humanoid")
COST = {"add": 1, "sub": 1, "mul": 1, "div": 1, "neg": 1}


def trig_flops() -> int:
    """Floating-point operations of one angle's sine and cosine as the lanes emit them (their ``f``-instructions)."""
    from relacc.kernels import lanes

    lines = lanes._trig("<1 x double>", lambda c: "<double 0.0>", [("%x", ("%s", "%c"))])
    return sum(1 for line in lines if " = f" in line and " fcmp " not in line) + sum(
        1 for line in lines if "@llvm.floor" in line)


def kernel_flops(tree, case: int = 2) -> dict:
    """The traced kernel's flops a state (module docstring), and how many of them are divisions and angles."""
    from relacc.core.tree.model import welded_folded
    from relacc.kernels import lanes
    from relacc.kernels.tree_dynamics import plan

    folded = welded_folded(tree)
    tr = lanes.trace(folded, case, plan(folded).method)
    need = lanes._needed(tr)
    fused = lanes._fused(tr, need)
    flops = divs = 0
    angles = set()
    for k, (opn, a, _) in enumerate(tr.ops):
        if not need[k]:
            continue
        if opn in ("sin", "cos"):
            angles.add(a)
        else:
            flops += COST.get(opn, 0)
            divs += opn == "div"
    return {"flops": flops + len(angles) * trig_flops(), "angles": len(angles), "divisions": divs,
            "fused_multiply_adds": len(fused)}


def peak(width: int, chains: int = 12, n: int = 20_000_000) -> float:
    """GFlop/s of ``chains`` independent ``llvm.fma`` chains over ``width`` lanes on one core (-O2, this CPU)."""
    from relacc.kernels import lanes

    vt = f"<{width} x double>"
    one = f"<{', '.join(['double 1.0000001'] * width)}>"
    small = f"<{', '.join(['double 1.0e-9'] * width)}>"
    body = [f"declare {vt} @llvm.fma.v{width}f64({vt}, {vt}, {vt})",
            f"define void @probe(i64 %n, {vt}* %out) {{", "entry:", "  br label %loop", "loop:",
            "  %i = phi i64 [0, %entry], [%next, %loop]"]
    for c in range(chains):
        body.append(f"  %a{c} = phi {vt} [{small}, %entry], [%b{c}, %loop]")
    for c in range(chains):
        body.append(f"  %b{c} = call {vt} @llvm.fma.v{width}f64({vt} %a{c}, {vt} {one}, {vt} {small})")
    body += ["  %next = add i64 %i, 1", "  %more = icmp slt i64 %next, %n", "  br i1 %more, label %loop, label %done",
             "done:"]
    acc = "%b0"
    for c in range(1, chains):
        body.append(f"  %s{c} = fadd {vt} {acc}, %b{c}")
        acc = f"%s{c}"
    body += [f"  store {vt} {acc}, {vt}* %out, align 8", "  ret void", "}"]
    engine = lanes.jit("\n".join(body) + "\n")
    fn = ctypes.CFUNCTYPE(None, ctypes.c_int64, ctypes.c_void_p)(engine.get_function_address("probe"))
    out = np.zeros(width)
    fn(1000, out.ctypes.data)
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        fn(n, out.ctypes.data)
        best = min(best, time.perf_counter() - start)
    return 2.0 * width * chains * n / best / 1e9


def model_row(name: str, states: int, repeats: int, width: int) -> dict:
    import relacc
    from relacc.core.tree import random_states
    from relacc.kernels.jit import threads
    from relacc.kernels.tree_dynamics import accelerations, optimize

    path = Path(find_spec("gymnasium").origin).parent / "envs" / "mujoco" / "assets" / f"{name}.xml"
    tree = relacc.Tree.from_file(path)
    optimize(tree, 2)
    s = random_states(tree, 2, states, 0)
    q, u = np.ascontiguousarray(s.q), np.ascontiguousarray(s.u)
    tau, out = np.zeros_like(u), np.empty_like(u)
    with threads(1):
        accelerations(tree, 2, q, u, tau, tree.gravity, out)
        per = []
        for _ in range(repeats):
            start = time.perf_counter()
            accelerations(tree, 2, q, u, tau, tree.gravity, out)
            per.append((time.perf_counter() - start) / states * 1e6)
    row = {"model": name, "nv": tree.nv, **kernel_flops(tree), "us_per_state": statistics.median(per),
           "us_per_state_best": min(per), "width": width}
    row["gflops"] = row["flops"] / (row["us_per_state"] * 1e-6) / 1e9
    return row


def main(argv=None) -> int:
    from relacc.kernels.lanes import lanes
    from relacc.tradeoff.throughput import machine

    parser = argparse.ArgumentParser(description="the lanes kernel's flops, GFlop/s and the FMA peak")
    parser.add_argument("--states", type=int, default=8192)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args(argv)
    width = lanes()
    top = peak(width)
    rows = [model_row(name, args.states, args.repeats, width) for name in MODELS]
    for r in rows:
        r["fraction_of_peak"] = r["gflops"] / top
        print(f"{r['model']}: {r['flops']} flops a state ({r['angles']} angles, {r['divisions']} divisions), "
              f"{r['us_per_state']:.3f} us a state, {r['gflops']:.1f} GFlop/s = {r['fraction_of_peak']:.2f} of the "
              f"{top:.1f} GFlop/s FMA peak")
    result = {"machine": machine(), "states": args.states, "repeats": args.repeats,
              "width": width, "peak_gflops": top, "trig_flops_per_angle": trig_flops(), "rows": rows}
    if args.json:
        write_text(args.json, json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
