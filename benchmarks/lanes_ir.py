"""Vector lanes without a compiler at install time: llvmlite (installed with numba) compiling LLVM IR written with
``<4 x double>`` vectors at run time, issue 35's route to the 2x over ``pin.abaInParallel`` (benchmarks/history.md,
"Lanes").

A probe, not the kernel: it builds a function ``lanes(a, b, out, n)`` that runs eight fused multiply-adds on four
states at a time (``out = ((a b + out) b + a) ...``, each statement one ``llvm.fma.v4f64``), JIT-compiles it for the
host CPU at ``-O3``, counts the AVX ``vfmadd`` instructions on ``ymm`` registers in its assembly, runs it through
ctypes on numpy arrays, and compares it with numpy's unfused arithmetic (one rounding per FMA apart: about eps) and
times both. What numba's loops over lanes did not give (the "Lanes" table: most arithmetic stayed scalar), IR with
vector types gives by construction; a tree's forward dynamics written that way (a generator emitting the recursion
per tree, as CppADCodeGen does for Pinocchio) is the kernel this would take.

Run:  python benchmarks/lanes_ir.py [--n 65536]
"""

import argparse
import ctypes
import sys
import time

import numpy as np


def build():
    """``(callable, assembly)`` of the probe's function, compiled for this CPU."""
    import llvmlite.binding as llvm
    import llvmlite.ir as ir

    llvm.initialize_native_target()
    llvm.initialize_native_asmprinter()
    d, i64 = ir.DoubleType(), ir.IntType(64)
    v4 = ir.VectorType(d, 4)
    mod = ir.Module("lanes")
    mod.triple = llvm.get_process_triple()
    fn = ir.Function(mod, ir.FunctionType(ir.VoidType(), [d.as_pointer()] * 3 + [i64]), "lanes")
    fma = ir.Function(mod, ir.FunctionType(v4, [v4, v4, v4]), "llvm.fma.v4f64")
    a, b, o, n = fn.args
    entry, loop, done = fn.append_basic_block("entry"), fn.append_basic_block("loop"), fn.append_basic_block("done")
    ir.IRBuilder(entry).branch(loop)
    bld = ir.IRBuilder(loop)
    k = bld.phi(i64)
    k.add_incoming(ir.Constant(i64, 0), entry)
    x, y, z = (bld.load(bld.bitcast(bld.gep(p, [k]), v4.as_pointer()), align=8) for p in (a, b, o))
    r = bld.call(fma, [x, y, z])
    for _ in range(7):
        r = bld.call(fma, [r, y, x])
    bld.store(r, bld.bitcast(bld.gep(o, [k]), v4.as_pointer()), align=8)
    nxt = bld.add(k, ir.Constant(i64, 4))
    k.add_incoming(nxt, loop)
    bld.cbranch(bld.icmp_signed("<", nxt, n), loop, done)
    ir.IRBuilder(done).ret_void()
    machine = llvm.Target.from_default_triple().create_target_machine(
        cpu=llvm.get_host_cpu_name(), features=llvm.get_host_cpu_features().flatten(), opt=3)
    parsed = llvm.parse_assembly(str(mod))
    parsed.verify()
    engine = llvm.create_mcjit_compiler(parsed, machine)
    engine.finalize_object()
    call = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int64)(
        engine.get_function_address("lanes"))
    return (lambda A, B, O: call(A.ctypes.data, B.ctypes.data, O.ctypes.data, len(O))), engine, \
        machine.emit_assembly(parsed)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1 << 16, help="states (a multiple of 4)")
    args = parser.parse_args(argv)
    lanes, _engine, asm = build()
    rng = np.random.default_rng(0)
    A, B = rng.random(args.n) * 0.5, rng.random(args.n) * 0.5
    O = np.zeros(args.n)
    lanes(A, B, O)
    ref = A * B
    for _ in range(7):
        ref = ref * B + A
    ymm = sum(1 for line in asm.splitlines() if "vfmadd" in line and "ymm" in line)
    best = min(_timed(lambda: lanes(A, B, np.zeros(args.n))) for _ in range(7))
    print(f"vfmadd on ymm registers in the compiled loop: {ymm} (of 8 FMAs a block of four states)")
    print(f"largest difference from numpy's unfused arithmetic: {np.abs(O - ref).max():.2e} (values below 1)")
    print(f"{best / args.n * 1e9:.2f} ns a state for 8 FMAs (best of 7, {args.n} states)")
    return 0


def _timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


if __name__ == "__main__":
    sys.exit(main())
