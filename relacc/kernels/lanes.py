"""A tree's forward dynamics over several states at once in vector lanes: the compiled kernels' own code, traced once
per tree and case into straight-line arithmetic and compiled by LLVM with ``<W x double>`` vectors.

numba's loops run one state at a time: the recursions over bodies are short loops it does not vectorize, so most of
the arithmetic stays scalar (benchmarks/history.md, "Lanes"). Here the composite-rigid-body kernel
(:mod:`relacc.kernels.tree_spatial`'s ``forward``, :mod:`relacc.kernels.tree_crba`'s ``mass_matrix`` and
``factor_solve``, case 3's maps to and from case-2 speeds), or the articulated-body one
(:mod:`relacc.kernels.tree_aba`) for the trees the plan gives it, is run once as Python on symbolic scalars
(:class:`X`): the
tree's structure and constants (its parents, joint kinds, axes, anchors, masses, inertias, armature) decide every
branch and fold into the arithmetic (a product with an axis' zero component disappears), and what is left is a list
of operations on the state's coordinates, speeds, forces and gravity. Each operation is emitted as one LLVM vector
instruction on ``W`` states (:func:`lanes`: 8 where the CPU has AVX-512, else 4), a block of states the innermost
dimension, and JIT-compiled for the host CPU through llvmlite (numba's own dependency: nothing to compile at install
time), at ``-O0`` first and at ``-O2`` once the kernel has run :data:`UPGRADE_STATES` states, the object code cached
beside numba's (:func:`compile_cached`). The same operations in the same order as the numba kernel, so the same
rounding but for the multiply-adds: a product used only by one sum is fused with it (:func:`_fused`, ``llvm.fma``:
one rounding), where numba's kernels let LLVM fuse what it chooses (``fastmath={'contract'}``).

Each angle's sine and cosine are written into the IR as vector code (:func:`_trig`: fdlibm's algorithm, the bits of
:func:`relacc.kernels.trig.sincos`, within :data:`relacc.core.tolerances.TRIG_ULPS` of libm), not left to LLVM's
``llvm.sin``/``llvm.cos``, which it lowers to one libm call per lane (about 40% of the kernel's time); an angle beyond
:data:`relacc.kernels.trig.LIMIT` takes libm's in its own lane. Each kernel also has a single-state entry point
(:func:`_one`) that :func:`relacc.tree_accelerations` calls for one state, compiled over one lane, from CPython
directly once at ``-O2`` (:mod:`relacc.kernels.direct`).

A pivot of the factorization not above :data:`relacc.core.tolerances.PIVOT_FLOOR` times its diagonal entry makes that
state's row NaN and is counted, as the numba kernel does; non-finite inputs and non-unit quaternions are counted per
state. CppADCodeGen does the same for Pinocchio with a C compiler at run time; LLVM is already in the process.
"""

from __future__ import annotations

import ctypes
import functools
import math
import struct
import threading
import weakref
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Callable

import numpy as np

from relacc.core.tolerances import PIVOT_FLOOR, QUATERNION_NORM_TOLERANCE


class Untraceable(Exception):
    """The kernel's code took a branch on a state's value: this tree is left to the numba kernels."""


class _Graph:
    """The operations recorded while tracing: ``ops[k] = (op, a, b)``, ``a``/``b`` an operation's index (int) or a
    constant (float); identical operations recorded once."""

    def __init__(self) -> None:
        self.ops: list = []
        self.seen: dict = {}
        self.pivots: list = []  # (a, b): a pivot check ``a > b``
        self.warns: list = []  # (a, b): an ill-conditioning check, ``a > b`` or the state is flagged
        self.pivots_allowed = False

    def node(self, op, a, b=None):
        key = (op, a, b)
        k = self.seen.get(key)
        if k is None:
            k = self.seen[key] = len(self.ops)
            self.ops.append(key)
        return X(self, k)


def _ref(x):
    """An operand: an :class:`X`'s index, or a float constant (``("c", value)``)."""
    return x.i if isinstance(x, X) else ("c", float(x))


class X:
    """A symbolic float64 of the trace: arithmetic records an operation, constants fold, identities vanish
    (``x + 0``, ``x * 1``, ``x * 0``: exact in floating point for the finite values a state's inputs are checked to
    be)."""

    __slots__ = ("g", "i")

    def __init__(self, g, i):
        self.g, self.i = g, i

    # arithmetic: one rule for both operand orders (_arith) -------------------------------------------------------
    def __add__(self, o):
        return _arith("add", self, o)

    def __radd__(self, o):
        return _arith("add", o, self)

    def __sub__(self, o):
        return _arith("sub", self, o)

    def __rsub__(self, o):
        return _arith("sub", o, self)

    def __mul__(self, o):
        return _arith("mul", self, o)

    def __rmul__(self, o):
        return _arith("mul", o, self)

    def __truediv__(self, o):
        return _arith("div", self, o)

    def __rtruediv__(self, o):
        return _arith("div", o, self)

    def __neg__(self):
        return self.g.node("neg", self.i)

    def __pos__(self):
        return self

    def sqrt(self):
        return self.g.node("sqrt", self.i)

    def cos(self):
        return self.g.node("cos", self.i)

    def sin(self):
        return self.g.node("sin", self.i)

    # branches -----------------------------------------------------------------------------------------------------
    def __gt__(self, o):
        if not self.g.pivots_allowed:
            raise Untraceable("a comparison of a state's value")
        self.g.pivots.append((self.i, _ref(o)))
        return True

    def _refuse(self, *_):
        raise Untraceable("a branch on a state's value")

    __lt__ = __le__ = __ge__ = __eq__ = __ne__ = __bool__ = __float__ = __int__ = __index__ = _refuse
    __hash__ = object.__hash__


def _arith(op: str, a, b):
    """``a op b`` with one of them an :class:`X` and the other an ``X`` or a number, the exact identities folded:
    ``x + 0``, ``0 + x``, ``x - 0`` are ``x``, ``0 - x`` is ``-x``; ``x * 0`` and ``0 * x`` are 0, ``x * 1`` is ``x``,
    ``x * -1`` is ``-x``; ``x / 1`` is ``x``, ``0 / x`` is 0 (exact for the finite values a state's inputs are checked
    to be)."""
    g = a.g if isinstance(a, X) else b.g
    ca = None if isinstance(a, X) else float(a)
    cb = None if isinstance(b, X) else float(b)
    if op == "add" and (ca == 0.0 or cb == 0.0):
        return b if ca == 0.0 else a
    if op == "sub" and cb == 0.0:
        return a
    if op == "sub" and ca == 0.0:
        return -b
    if op == "mul" and (ca is not None or cb is not None):
        c, x = (ca, b) if ca is not None else (cb, a)
        if c == 0.0:
            return 0.0
        if c in (1.0, -1.0):
            return x if c == 1.0 else -x
    if op == "div" and (cb == 1.0 or ca == 0.0):
        return a if cb == 1.0 else 0.0
    return g.node(op, _ref(a), _ref(b))


def _ill(pivot, bound):
    """:func:`relacc.kernels.tree_spatial.ill` while a trace runs: a pivot's ill-conditioning test recorded as the
    state's warning flag (never a branch of the trace: the traced code goes on as if it passed)."""
    if isinstance(pivot, X) or isinstance(bound, X):
        (pivot if isinstance(pivot, X) else bound).g.warns.append((_ref(pivot), _ref(bound)))
        return False
    return not pivot > bound


class _Math:
    """``math`` for the traced functions' module globals: symbolic on :class:`X`, the real one on floats."""

    @staticmethod
    def cos(x):
        return x.cos() if isinstance(x, X) else math.cos(x)

    @staticmethod
    def sin(x):
        return x.sin() if isinstance(x, X) else math.sin(x)

    @staticmethod
    def sqrt(x):
        return x.sqrt() if isinstance(x, X) else math.sqrt(x)

    def __getattr__(self, name):
        return getattr(math, name)


_TRACE_LOCK = threading.Lock()


@contextmanager
def _symbolic_math():
    """The kernels' modules see :class:`_Math` as ``math`` while a trace runs (under numba's compiler lock, so no
    compilation reads the swapped global meanwhile)."""
    import relacc.kernels.so3 as so3
    import relacc.kernels.tree as tree_mod
    import relacc.kernels.tree_aba as aba
    import relacc.kernels.tree_crba as crba
    import relacc.kernels.tree_spatial as spatial

    mods = [m for m in (tree_mod, so3, spatial, crba) if "math" in vars(m)]
    warned = [m for m in (spatial, crba, aba) if "ill" in vars(m)]
    try:
        from numba.core.compiler_lock import global_compiler_lock as lock
    except ImportError:  # pragma: no cover - without numba nothing compiles
        lock = _TRACE_LOCK
    with lock:
        saved = [m.math for m in mods]
        saved_ill = [m.ill for m in warned]
        for m in mods:
            m.math = _Math()
        for m in warned:
            m.ill = _ill
        try:
            yield
        finally:
            for m, s in zip(mods, saved):
                m.math = s
            for m, f in zip(warned, saved_ill):
                m.ill = f


def _py(fn):
    """The Python function behind a numba dispatcher (or the function itself)."""
    return getattr(fn, "py_func", fn)


def _obj(shape, fill=None):
    a = np.empty(shape, dtype=object)
    if fill is not None:
        a.fill(fill)
    return a


@dataclass(frozen=True)
class Trace:
    """One tree's forward dynamics in one case as straight-line operations.

    Attributes:
        ops: the operations (:class:`_Graph`'s ``ops``). nq, nv: the state's sizes.
        inputs: ``{("q"|"u"|"tau"|"g", column): op index}``. outputs: ``(nv,)`` each acceleration's op index or
            constant. pivots: the factorization's checks ``(a, b)``: ``a > b`` or the state is singular.
            warns: its ill-conditioning checks ``(a, b)``: ``a > b`` or the state is ill-conditioned
            (:data:`relacc.core.tolerances.MASS_CONDITION_WARNING`).
        quats: ``q``'s first column of each unit quaternion (cases 1, 2).
    """

    ops: tuple
    nq: int
    nv: int
    inputs: dict
    outputs: tuple
    pivots: tuple
    quats: tuple
    warns: tuple = ()


def trace(tree, case: int, algorithm: str = "crba") -> Trace:
    """Run the numba kernel's Python for ``tree`` (welded bodies folded, as the kernels do) in ``case`` on symbolic
    inputs: the composite-rigid-body algorithm (``"crba"``) or the articulated-body algorithm (``"aba"``), as
    :func:`relacc.kernels.tree_dynamics.accelerations` runs them. Raises :class:`Untraceable` where the code
    branches on a state's value."""
    from relacc.core.tree.model import welded_folded
    from relacc.kernels.tree import ANGLES_CASE2, BALL, FREE, arrays_of
    from relacc.kernels.tree_aba import accelerate, backward
    from relacc.kernels.tree_crba import dof_paths, factor_solve, mass_matrix
    from relacc.kernels.tree_spatial import forward, inertia_arrays, row_to_rates, row_to_speeds

    folded = welded_folded(tree)
    T, (anc, depth), (mass, com, inertia, arm, free) = arrays_of(folded), dof_paths(folded), inertia_arrays(folded)
    qadr = T.qadr3 if case >= 3 else T.qadr
    nq, nv, nb, nj = folded.nq_in(case), folded.nv, T.parent.shape[0], T.jtype.shape[0]
    g = _Graph()
    inputs = {}

    def row(name, n):
        a = _obj((1, n))
        for c in range(n):
            a[0, c] = g.node("in", name, c)
            inputs[(name, c)] = a[0, c].i
        return a

    q, u, tau = row("q", nq), row("u", nv), row("tau", nv)
    grav = row("g", 3)[0]
    S, C, o, R = _obj((nv, 6)), _obj((max(nj, 1), 6)), _obj((nb, 3)), _obj((nb, 9))
    V, IA, pA, A, f = _obj((nb, 6)), _obj((nb, 21)), _obj((nb, 6)), _obj((nb, 6)), _obj((nb, 6))
    M, x, tmp, diag = _obj((nv, anc.shape[1] + 1), 0.0), _obj(nv), _obj(18), _obj(nv)
    mode = ANGLES_CASE2 if case == 3 else case
    with _symbolic_math():
        if mode == ANGLES_CASE2:
            U1, F1, trig = _obj((1, nv)), _obj((1, nv)), _obj((max(nj, 1), 6))
            _py(row_to_speeds)(q, u, tau, 0, T, U1, F1, 0, trig)
            qq, uu, tt = q, U1, F1
        else:
            qq, uu, tt = q, u, tau
        _py(forward)(mode, qq, uu, 0, T, qadr, mass, com, inertia, S, C, o, R, V, IA, pA)
        if algorithm == "aba":
            Ua, ua, Dinv, tmp60 = _obj((nv, 6)), _obj(nv), _obj((max(nj, 1), 36)), _obj(60)
            Ic, cd, x2 = IA.copy(), _obj(8), _obj((1, nv))
            g.pivots_allowed = True
            failed = _py(backward)(mode, qq, uu, tt, 0, T, qadr, arm, free, S, C, R, V, IA, pA, Ua, ua, Dinv, tmp60,
                                   Ic, cd, PIVOT_FLOOR)
            g.pivots_allowed = False
            if not failed:
                _py(accelerate)(T, grav, free, S, C, Ua, ua, Dinv, A, 0, x2)
            x = x2[0]
        else:
            _py(mass_matrix)(mode, qq, uu, tt, 0, T, qadr, anc, depth, arm, free, grav, S, C, R, V, IA, pA, A, f, M,
                             x, tmp)
            g.pivots_allowed = True
            failed = _py(factor_solve)(M, x, anc, depth, diag, PIVOT_FLOOR)
            g.pivots_allowed = False
        if failed:  # a pivot that fails whatever the state: every state singular
            g.pivots.append((("c", 0.0), ("c", 0.0)))
            x = np.zeros(nv)
        if mode == ANGLES_CASE2:
            out = _obj((1, nv))
            for c in range(nv):
                U1[0, c] = x[c]
            _py(row_to_rates)(q, u, 0, U1, 0, T, out, trig)
            res = list(out[0])
        else:
            res = list(x)
    quats = tuple(int(qadr[k] + (3 if T.jtype[k] == FREE else 0)) for k in range(nj)
                  if case < 3 and T.jtype[k] in (BALL, FREE))
    return Trace(tuple(g.ops), nq, nv, inputs, tuple(_ref(r) for r in res), tuple(g.pivots), quats,
                 tuple(g.warns))


@functools.cache
def lanes() -> int:
    """States per vector: 8 where the CPU has AVX-512 (one ``zmm`` register), else 4 (``ymm``). Read once per process:
    asking LLVM for the CPU's features takes about 180 us, and :func:`kernel` is asked at every batch."""
    import llvmlite.binding as llvm

    feats = llvm.get_host_cpu_features()
    return 8 if feats.get("avx512f", False) else 4


def _sincos(x: str, tag: str, vt: str, const) -> tuple[list, str, str]:
    """IR lines of ``(sin x, cos x)`` of the ``vt`` vector ``x`` by :func:`relacc.kernels.trig.sincos`'s algorithm
    (fdlibm's reduction in three Cody-Waite rounds and its minimax polynomials), the same operations in the same
    order, no fused multiply-add; the quadrant picks and signs the pair by ``select`` (so ``sin(-0.0)`` is ``-0.0``, as
    libm's). Valid for ``|x| <= LIMIT``: the caller replaces the lanes beyond (:func:`_trig`). Returns
    ``(lines, sin's name, cos's name)``; every name starts with ``%{tag}``."""
    from relacc.kernels import trig

    lines: list = []
    count = [0]

    def op(kind, a, b):
        name = f"%{tag}_{count[0]}"
        count[0] += 1
        a = const(a) if isinstance(a, float) else a
        b = const(b) if isinstance(b, float) else b
        lines.append(f"  {name} = f{kind} {vt} {a}, {b}")
        return name

    t = op("add", op("mul", x, trig.INVPIO2), 0.5)
    n = f"%{tag}_n"
    lines.append(f"  {n} = call {vt} @llvm.floor.{vt_suffix(vt)}({vt} {t})")
    r = op("sub", x, op("mul", n, trig.PIO2_1))  # exact
    w = op("mul", n, trig.PIO2_2)
    r2 = op("sub", r, w)
    w = op("sub", op("mul", n, trig.PIO2_2T), op("sub", op("sub", r, r2), w))  # superseded below, as in fdlibm
    w = op("mul", n, trig.PIO2_3)
    r3 = op("sub", r2, w)
    w = op("sub", op("mul", n, trig.PIO2_3T), op("sub", op("sub", r2, r3), w))
    y0 = op("sub", r3, w)
    y1 = op("sub", op("sub", r3, y0), w)
    z = op("mul", y0, y0)
    ww = op("mul", z, z)
    rs = op("add", op("add", trig.S2, op("mul", z, op("add", trig.S3, op("mul", z, trig.S4)))),
            op("mul", op("mul", z, ww), op("add", trig.S5, op("mul", z, trig.S6))))
    v = op("mul", z, y0)
    sn = op("sub", y0, op("sub", op("sub", op("mul", z, op("sub", op("mul", 0.5, y1), op("mul", v, rs))), y1),
                          op("mul", v, trig.S1)))
    rc = op("add", op("mul", z, op("add", trig.C1, op("mul", z, op("add", trig.C2, op("mul", z, trig.C3))))),
            op("mul", op("mul", ww, ww), op("add", trig.C4, op("mul", z, op("add", trig.C5, op("mul", z, trig.C6))))))
    hz = op("mul", 0.5, z)
    w1 = op("sub", 1.0, hz)
    cs = op("add", w1, op("add", op("sub", op("sub", 1.0, w1), hz), op("sub", op("mul", z, rc), op("mul", y0, y1))))
    q = f"%{tag}_q"
    lines.append(f"  {q}f = call {vt} @llvm.floor.{vt_suffix(vt)}({vt} {op('mul', n, 0.25)})")
    k = op("sub", n, op("mul", 4.0, f"{q}f"))  # the quadrant: 0, 1, 2, 3
    mt = vt.replace("double", "i1")
    for j in (1, 2, 3):
        lines.append(f"  %{tag}_k{j} = fcmp oeq {vt} {k}, {const(float(j))}")
    lines += [f"  %{tag}_odd = or {mt} %{tag}_k1, %{tag}_k3", f"  %{tag}_ns = or {mt} %{tag}_k2, %{tag}_k3",
              f"  %{tag}_nc = or {mt} %{tag}_k1, %{tag}_k2",
              f"  %{tag}_ps = select {mt} %{tag}_odd, {vt} {cs}, {vt} {sn}",
              f"  %{tag}_pc = select {mt} %{tag}_odd, {vt} {sn}, {vt} {cs}",
              f"  %{tag}_ms = fneg {vt} %{tag}_ps", f"  %{tag}_mc = fneg {vt} %{tag}_pc",
              f"  %{tag}_sin = select {mt} %{tag}_ns, {vt} %{tag}_ms, {vt} %{tag}_ps",
              f"  %{tag}_cos = select {mt} %{tag}_nc, {vt} %{tag}_mc, {vt} %{tag}_pc"]
    return lines, f"%{tag}_sin", f"%{tag}_cos"


def _trig(vt: str, const, angles: list) -> list:
    """IR of every angle's ``(sin x, cos x)``, ``angles`` a list of ``(x, (sin's name, cos's name))``: :func:`_sincos`
    in every lane, and libm's ``sin`` and ``cos`` in the lanes where ``|x| > LIMIT`` (fdlibm's Payne-Hanek reduction,
    which the three rounds do not replace), called only when some lane of some angle needs them: one branch for all
    the angles, so that the rest of the body stays one block for the code generator to schedule (a branch per angle
    cost a quarter of the kernel's time). A lane's bits depend on its own angle alone, never on its neighbours'.
    The code after these lines is in block ``trig_join``."""
    from relacc.kernels.trig import LIMIT

    if not angles:
        return []
    mt, sfx = vt.replace("double", "i1"), vt_suffix(vt)
    width = sfx[1:-3]
    lines, fast, anyb = [], [], "false"
    for j, (x, _) in enumerate(angles):
        body, sn, cs = _sincos(x, f"t{j}", vt, const)
        fast.append((sn, cs))
        lines += body + [f"  %t{j}_ax = call {vt} @llvm.fabs.{sfx}({vt} {x})",
                         f"  %t{j}_big = fcmp ogt {vt} %t{j}_ax, {const(LIMIT)}",
                         f"  %t{j}_any = call i1 @llvm.vector.reduce.or.v{width}i1({mt} %t{j}_big)",
                         f"  %t{j}_acc = or i1 {anyb}, %t{j}_any"]
        anyb = f"%t{j}_acc"
    lines += [f"  br i1 {anyb}, label %trig_libm, label %trig_join", "trig_libm:"]
    for j, (x, _) in enumerate(angles):
        lines += [f"  %t{j}_ls = call {vt} @llvm.sin.{sfx}({vt} {x})",
                  f"  %t{j}_lc = call {vt} @llvm.cos.{sfx}({vt} {x})"]
    lines += ["  br label %trig_join", "trig_join:"]
    for j, (sn, cs) in enumerate(fast):  # a block's phis come first
        lines += [f"  %t{j}_bs = phi {vt} [{sn}, %loop], [%t{j}_ls, %trig_libm]",
                  f"  %t{j}_bc = phi {vt} [{cs}, %loop], [%t{j}_lc, %trig_libm]"]
    for j, ((_, (s_name, c_name)), (sn, cs)) in enumerate(zip(angles, fast)):
        lines += [f"  {s_name} = select {mt} %t{j}_big, {vt} %t{j}_bs, {vt} {sn}",
                  f"  {c_name} = select {mt} %t{j}_big, {vt} %t{j}_bc, {vt} {cs}"]
    return lines


def vt_suffix(vt: str) -> str:
    """LLVM's intrinsic suffix of a vector type: ``<4 x double>`` -> ``v4f64``."""
    return "v" + vt.strip("<>").split(" x ")[0] + "f64"


def splat(c: float, width: int) -> str:
    """The IR constant of ``width`` lanes all ``c``, written by its bits (exact, ``-0.0`` and NaN included)."""
    bits = struct.unpack("<Q", struct.pack("<d", c))[0]
    return f"<{', '.join([f'double 0x{bits:016X}'] * width)}>"


def emit(tr: Trace, width: int, name: str = "lanes") -> str:
    """LLVM IR (text) of ``i64 name(double* q, double* u, double* tau, double* g, double* out, i64* bad, i64 start,
    i64 stop)``: rows ``start .. stop - 1`` of C-contiguous ``q (n, nq)``, ``u``, ``tau (n, nv)`` to ``out (n, nv)``,
    ``width`` states a step; returns the number of singular states and adds the number of states with bad inputs to
    ``bad[0]`` and of ill-conditioned ones (:attr:`Trace.warns`) to ``bad[1]``. A last step with fewer than ``width``
    rows left repeats the last row in its other lanes (the same state, so the same bits written twice) and counts
    only its own rows. Written as text: llvmlite's IR builder took half of
    a small tree's compilation."""
    W = width
    vt, mt = f"<{W} x double>", f"<{W} x i1>"
    lines = [f"define i64 @{name}(double* %q, double* %u, double* %tau, double* %g, double* %out, i64* %bad, "
             "i64 %start, i64 %stop) {", "entry:", "  %empty = icmp sge i64 %start, %stop",
             "  br i1 %empty, label %done, label %loop", "loop:",
             "  %i = phi i64 [%start, %entry], [%next, %LATCH]", "  %ns = phi i64 [0, %entry], [%cs, %LATCH]",
             "  %nb = phi i64 [0, %entry], [%cb, %LATCH]", "  %nw = phi i64 [0, %entry], [%cw, %LATCH]",
             "  %last = sub i64 %stop, 1"]
    add = lines.append
    for lane in range(W):
        add(f"  %r{lane}a = add i64 %i, {lane}")
        add(f"  %live{lane} = icmp slt i64 %r{lane}a, %stop")
        add(f"  %r{lane} = select i1 %live{lane}, i64 %r{lane}a, i64 %last")
    sizes = {"q": tr.nq, "u": tr.nv, "tau": tr.nv}
    consts: dict = {}

    def const(c):
        name_ = consts.get(c)
        if name_ is None:
            name_ = consts[c] = splat(c, W)
        return name_

    def load(var, arr, c):
        if arr == "g":
            add(f"  %{var}p = getelementptr double, double* %g, i64 {c}")
            add(f"  %{var}s = load double, double* %{var}p")
            add(f"  %{var}i = insertelement {vt} undef, double %{var}s, i32 0")
            add(f"  %{var} = shufflevector {vt} %{var}i, {vt} undef, <{W} x i32> zeroinitializer")
            return
        prev = "undef"
        for lane in range(W):
            add(f"  %{var}o{lane} = mul i64 %r{lane}, {sizes[arr]}")
            add(f"  %{var}a{lane} = add i64 %{var}o{lane}, {c}")
            add(f"  %{var}p{lane} = getelementptr double, double* %{arr}, i64 %{var}a{lane}")
            add(f"  %{var}s{lane} = load double, double* %{var}p{lane}")
            cur = f"%{var}e{lane}" if lane < W - 1 else f"%{var}"
            add(f"  {cur} = insertelement {vt} {prev}, double %{var}s{lane}, i32 {lane}")
            prev = cur

    def val(ref):
        return const(ref[1]) if isinstance(ref, tuple) else f"%v{ref}"

    need = _needed(tr)
    fused = _fused(tr, need)
    products = set(fused.values())
    fma = f"@llvm.fma.v{W}f64"
    trig: dict = {}  # an angle's op -> {"sin": op, "cos": op}
    for k, (opn, a, b) in enumerate(tr.ops):
        if need[k] and opn in ("sin", "cos"):
            trig.setdefault(a, {}).setdefault(opn, k)
    early: set = set()  # the angles and what they are made of (a coordinate, half of it): emitted first
    stack = list(trig)
    while stack:
        k = stack.pop()
        if k not in early:
            early.add(k)
            stack += [r for r in tr.ops[k][1:] if isinstance(r, int) and tr.ops[k][0] != "in"]

    def op(k):
        opn, a, b = tr.ops[k]
        m = fused.get(k)
        if opn in ("sin", "cos"):
            if trig[a][opn] != k:  # a repeated sine or cosine of one angle: the first's bits
                add(f"  %v{k} = fmul {vt} %v{trig[a][opn]}, {const(1.0)}")
        elif m is not None:  # a product used only here, rounded once with the sum: a b + c, a b - c, c - a b
            x, y = val(tr.ops[m][1]), val(tr.ops[m][2])
            if opn == "add":
                c3 = val(b if m == a else a)
            elif m == a:
                add(f"  %n{k} = fneg {vt} {val(b)}")
                c3 = f"%n{k}"
            else:
                add(f"  %n{k} = fneg {vt} {x}")
                x, c3 = f"%n{k}", val(a)
            add(f"  %v{k} = call {vt} {fma}({vt} {x}, {vt} {y}, {vt} {c3})")
        elif opn == "in":
            load(f"v{k}", a, b)
        elif opn in ("add", "sub", "mul", "div"):
            add(f"  %v{k} = f{opn} {vt} {val(a)}, {val(b)}")
        elif opn == "neg":
            add(f"  %v{k} = fneg {vt} {val(a)}")
        else:
            add(f"  %v{k} = call {vt} @llvm.{opn}.v{W}f64({vt} {val(a)})")

    for k in sorted(early):
        if need[k] and k not in products:
            op(k)
    lines.extend(_trig(vt, const, [(val(a), tuple(f"%v{pair[f]}" if f in pair else f"%t{a}_{f}"
                                                  for f in ("sin", "cos"))) for a, pair in trig.items()]))
    latch = "trig_join" if trig else "loop"  # the block the loop's body ends in
    lines[:9] = [line.replace("%LATCH]", f"%{latch}]") for line in lines[:9]]
    for k in range(len(tr.ops)):
        if need[k] and k not in products and k not in early:
            op(k)
    ok = f"<{', '.join(['i1 true'] * W)}>"
    for n, (a, b) in enumerate(tr.pivots):
        add(f"  %pc{n} = fcmp ogt {vt} {val(a)}, {val(b)}")
        add(f"  %pk{n} = and {mt} {ok}, %pc{n}")
        ok = f"%pk{n}"
    clear = f"<{', '.join(['i1 true'] * W)}>"
    for n, (a, b) in enumerate(tr.warns):
        add(f"  %wc{n} = fcmp ogt {vt} {val(a)}, {val(b)}")
        add(f"  %wk{n} = and {mt} {clear}, %wc{n}")
        clear = f"%wk{n}"
    add(f"  %wm = and {mt} {clear}, {ok}")  # a singular state is counted singular, not ill-conditioned too
    add(f"  %wn = xor {mt} {ok}, <{', '.join(['i1 true'] * W)}>")
    add(f"  %wok = or {mt} %wm, %wn")
    clear = "%wok"
    # bad inputs: a non-finite q or u, or a quaternion whose squared norm is off 1 by more than the tolerance
    good, col, n = f"<{', '.join(['i1 true'] * W)}>", {}, 0
    for arr in ("q", "u"):
        for c in range(sizes[arr]):
            k = tr.inputs.get((arr, c))
            if k is not None and need[k]:
                col[(arr, c)] = f"%v{k}"
            else:
                load(f"x{arr}{c}", arr, c)
                col[(arr, c)] = f"%x{arr}{c}"
            v = col[(arr, c)]
            add(f"  %fd{n} = fsub {vt} {v}, {v}")
            add(f"  %fe{n} = fcmp oeq {vt} %fd{n}, {const(0.0)}")
            add(f"  %fg{n} = and {mt} {good}, %fe{n}")
            good, n = f"%fg{n}", n + 1
    for a in tr.quats:
        terms = []
        for c in range(a, a + 4):
            add(f"  %qs{a}_{c} = fmul {vt} {col[('q', c)]}, {col[('q', c)]}")
            terms.append(f"%qs{a}_{c}")
        add(f"  %qn{a}a = fadd {vt} {terms[0]}, {terms[1]}")
        add(f"  %qn{a}b = fadd {vt} %qn{a}a, {terms[2]}")
        add(f"  %qn{a} = fadd {vt} %qn{a}b, {terms[3]}")
        add(f"  %qd{a} = fsub {vt} %qn{a}, {const(1.0)}")
        add(f"  %qa{a} = call {vt} @llvm.fabs.v{W}f64({vt} %qd{a})")
        add(f"  %qo{a} = fcmp ole {vt} %qa{a}, {const(QUATERNION_NORM_TOLERANCE)}")
        add(f"  %qg{a} = and {mt} {good}, %qo{a}")
        good = f"%qg{a}"
    for c, r in enumerate(tr.outputs):
        add(f"  %o{c} = select {mt} {ok}, {vt} {val(r)}, {vt} {const(float('nan'))}")
    for lane in range(W):  # a repeated last row's lanes write its own bits again
        add(f"  %ob{lane} = mul i64 %r{lane}, {tr.nv}")
        for c in range(tr.nv):
            add(f"  %oe{lane}_{c} = extractelement {vt} %o{c}, i32 {lane}")
            add(f"  %oa{lane}_{c} = add i64 %ob{lane}, {c}")
            add(f"  %op{lane}_{c} = getelementptr double, double* %out, i64 %oa{lane}_{c}")
            add(f"  store double %oe{lane}_{c}, double* %op{lane}_{c}")
    cs, cb, cw = "%ns", "%nb", "%nw"
    for lane in range(W):
        for tag, mask, acc in (("s", ok, cs), ("b", good, cb), ("i", clear, cw)):
            add(f"  %{tag}x{lane} = extractelement {mt} {mask}, i32 {lane}")
            add(f"  %{tag}n{lane} = xor i1 %{tag}x{lane}, true")
            add(f"  %{tag}l{lane} = and i1 %{tag}n{lane}, %live{lane}")
            add(f"  %{tag}z{lane} = zext i1 %{tag}l{lane} to i64")
            add(f"  %{tag}c{lane} = add i64 {acc}, %{tag}z{lane}")
        cs, cb, cw = f"%sc{lane}", f"%bc{lane}", f"%ic{lane}"
    lines += [f"  %cs = add i64 {cs}, 0", f"  %cb = add i64 {cb}, 0", f"  %cw = add i64 {cw}, 0",
              f"  %next = add i64 %i, {W}",
              "  %more = icmp slt i64 %next, %stop", "  br i1 %more, label %loop, label %done", "done:",
              f"  %rs = phi i64 [0, %entry], [%cs, %{latch}]", f"  %rb = phi i64 [0, %entry], [%cb, %{latch}]",
              f"  %rw = phi i64 [0, %entry], [%cw, %{latch}]",
              "  %b0 = load i64, i64* %bad", "  %b1 = add i64 %b0, %rb", "  store i64 %b1, i64* %bad",
              "  %bw = getelementptr i64, i64* %bad, i64 1", "  %w0 = load i64, i64* %bw",
              "  %w1 = add i64 %w0, %rw", "  store i64 %w1, i64* %bw",
              "  ret i64 %rs", "}"]
    decl = [f"declare {vt} @llvm.{f}.v{W}f64({vt})" for f in ("sqrt", "sin", "cos", "fabs", "floor")]
    decl.append(f"declare i1 @llvm.vector.reduce.or.v{W}i1({mt})")
    decl.append(f"declare {vt} @llvm.fma.v{W}f64({vt}, {vt}, {vt})")
    return "\n".join(decl + lines + _one(name, tr.nq, tr.nv)) + "\n"


ONE_SINGULAR, ONE_BAD_INPUT, ONE_ILL, ONE_NOT_FINITE = 1, 2, 4, 8
"""The flags :func:`emit`'s single-state entry point ``name_one`` returns (or-ed; 0: a plain answer)."""


def _one(name: str, nq: int, nv: int) -> list:
    """IR of ``i64 name_one(double* buf)``: the kernel on the one state laid out in ``buf`` as ``q (nq) | u (nv) |
    tau (nv) | g (3) | out (nv)``, returning :data:`ONE_SINGULAR` and the other flags or-ed, with
    :data:`ONE_NOT_FINITE` where an output is not finite. One pointer rather than eight arguments: ctypes converts
    each argument, and eight cost 2.2 us of a call against 0.55 for one (measured on this project's AMD VM), more
    than the kernel's own work on one state."""
    at = {"u": nq, "tau": nq + nv, "g": nq + 2 * nv, "out": nq + 2 * nv + 3}
    body = [f"define i64 @{name}_one(double* %buf) {{", "entry:", "  %bad = alloca [2 x i64]",
            "  %b0p = getelementptr [2 x i64], [2 x i64]* %bad, i64 0, i64 0",
            "  %b1p = getelementptr [2 x i64], [2 x i64]* %bad, i64 0, i64 1",
            "  store i64 0, i64* %b0p", "  store i64 0, i64* %b1p"]
    for arr, off in at.items():
        body.append(f"  %{arr} = getelementptr double, double* %buf, i64 {off}")
    body += [f"  %s = call i64 @{name}(double* %buf, double* %u, double* %tau, double* %g, double* %out, "
             "i64* %b0p, i64 0, i64 1)",
             "  %b0 = load i64, i64* %b0p", "  %b1 = load i64, i64* %b1p",
             "  %fs = icmp ne i64 %s, 0", "  %fb = icmp ne i64 %b0, 0", "  %fi = icmp ne i64 %b1, 0"]
    fin = "true"
    for c in range(nv):  # x - x is 0 for a finite x and NaN for an infinite or NaN one
        body += [f"  %op{c} = getelementptr double, double* %out, i64 {c}", f"  %ov{c} = load double, double* %op{c}",
                 f"  %od{c} = fsub double %ov{c}, %ov{c}", f"  %oq{c} = fcmp oeq double %od{c}, 0.0",
                 f"  %of{c} = and i1 {fin}, %oq{c}"]
        fin = f"%of{c}"
    body += [f"  %fn = xor i1 {fin}, true"]
    acc = "0"
    for k, (flag, bit) in enumerate((("fs", ONE_SINGULAR), ("fb", ONE_BAD_INPUT), ("fi", ONE_ILL),
                                     ("fn", ONE_NOT_FINITE))):
        body += [f"  %z{k} = select i1 %{flag}, i64 {bit}, i64 0", f"  %a{k} = or i64 {acc}, %z{k}"]
        acc = f"%a{k}"
    return body + [f"  ret i64 {acc}", "}"]


def _fused(tr: Trace, need: list) -> dict:
    """``{sum: product}``: each sum or difference whose first (else second) operand is a product used nowhere else,
    to be emitted as one fused multiply-add (``llvm.fma``: rounded once). Written into the IR rather than left to
    LLVM's ``contract`` flag, so the bits do not depend on the code generator's optimization level."""
    uses = [0] * len(tr.ops)
    for k, (opn, a, b) in enumerate(tr.ops):
        if need[k] and opn != "in":
            for r in (a, b):
                if isinstance(r, int):
                    uses[r] += 1
    for r in tr.outputs:
        if isinstance(r, int):
            uses[r] += 1
    for pair in tr.pivots:
        for r in pair:
            if isinstance(r, int):
                uses[r] += 1
    fused: dict = {}
    for k, (opn, a, b) in enumerate(tr.ops):
        if need[k] and opn in ("add", "sub"):
            for r in (a, b):
                if isinstance(r, int) and tr.ops[r][0] == "mul" and uses[r] == 1:
                    fused[k] = r
                    break
    return fused


def _needed(tr: Trace) -> list:
    """Which operations an output, a pivot check or an ill-conditioning check depends on."""
    need = [False] * len(tr.ops)
    stack = [r for r in tr.outputs if not isinstance(r, tuple)]
    for a, b in tr.pivots + tr.warns:
        stack += [r for r in (a, b) if not isinstance(r, tuple)]
    while stack:
        k = stack.pop()
        if need[k]:
            continue
        need[k] = True
        opn, a, b = tr.ops[k]
        if opn != "in":
            stack += [r for r in (a, b) if isinstance(r, int)]
    return need


MAX_OPS = 40000
"""The most operations a traced tree may have: LLVM's time grows with the function, a little faster than linearly
(gymnasium's ant's 4,900 operations in 0.3 s, humanoid's 9,300 in 0.9 s, a 60-link chain's 35,000 in 3.6 s, a
40-ball chain's 53,000 in 5.7 s and 360 MB); a larger tree stays with the numba kernels. A tree whose
:func:`estimate` is over twice this is not traced at all."""


def estimate(tree, algorithm: str = "crba") -> int:
    """An upper estimate of a tree's traced operations before tracing it: for ``"crba"`` about 350 a speed for the
    spatial pass and the mass matrix and the factorization's ``sum_k d_k^2`` (``d_k`` the speeds on speed ``k``'s
    path); for ``"aba"`` about 600 a speed (linear in the tree)."""
    from relacc.core.tree.model import welded_folded
    from relacc.kernels.tree_crba import dof_paths

    folded = welded_folded(tree)
    if algorithm == "aba":
        return 600 * folded.nv
    return 350 * folded.nv + int(np.sum(dof_paths(folded)[1].astype(np.int64) ** 2))


UPGRADE_STATES = 100_000
"""States a kernel compiled at ``-O0`` runs in a process before it is compiled again at ``-O2``. A kernel is first
compiled at ``-O0`` (LLVM's fast instruction selection: gymnasium's humanoid in 0.16 s against 0.58 s at ``-O2``)
and runs 25-55% slower than at ``-O2`` (ant 0.42 against 0.33 us a state, humanoid 0.88-0.99 against 0.64); the
fused multiply-adds are written into the IR (:func:`_fused`) and no fast-math flag is set, so both give the same bits
and the switch changes no number. The ``-O2`` object code is cached: a later process starts with it."""


class Kernel:
    """One tree's compiled forward dynamics in one case over ``width`` states a step.

    Attributes:
        fn: the compiled function (:func:`emit`'s signature), at the optimization ``level`` (0 or 2) reached so far.
        one: its single-state entry point (``name_one``, :func:`_one`), at the same level.
        width: states a vector. nq, nv: the state's sizes.
        states: the states run so far in this process (what :meth:`will_run` weighs).
    """

    def __init__(self, fns, engine, level: int, width: int, nq: int, nv: int, upgrade=None):
        self.fn: Callable[..., int] = fns[0]
        self.one: Callable[[int], int] = fns[1]
        self.level, self.width, self.nq, self.nv = level, width, nq, nv
        self.states = 0  # counted without a lock: threads may lose a few, and the count only times the switch
        self._engines = [engine]  # every engine whose code may still run on another thread: kept with the kernel
        self._upgrade = upgrade  # () -> (fn, engine): the -O2 code; None once at -O2
        self._lock = threading.Lock()

    def will_run(self, n: int) -> None:
        """Count ``n`` states about to run; past :data:`UPGRADE_STATES` compile the ``-O2`` code (on the calling
        thread, before the batch: the same bits, faster) and run that from now on."""
        self.states += n
        if self._upgrade is not None and self.states >= UPGRADE_STATES:
            self.optimize()

    def optimize(self) -> None:
        """Compile the ``-O2`` code now (or load it from the cache) and run it from now on."""
        with self._lock:
            if self._upgrade is not None:
                (fn, one), engine = self._upgrade()
                self._engines.append(engine)
                self.fn, self.one, self.level, self._upgrade = fn, one, 2, None

    def block(self, q, u, tau, g, out, start: int, stop: int) -> tuple:
        """Rows ``start .. stop - 1`` of C-contiguous float64 ``q (n, nq)`` and ``u (n, nv)`` (the case's
        coordinates and speeds), ``tau (n, nv)`` (generalized forces on those speeds, N or N m) with gravity
        ``g (3,)`` (m/s^2, world components) into ``out (n, nv)``, the speeds' time derivatives (m/s^2 for a
        translation's speed, rad/s^2 for a rotation's; case 3 the 1-2-3 angles' second derivatives): ``(states with
        bad inputs, singular states, ill-conditioned states)``, a singular state's row NaN. The compiled code
        runs without the GIL (ctypes releases it), so shares of a batch run on Python threads at once."""
        bad = np.zeros(2, np.int64)
        singular = self.fn(q.ctypes.data, u.ctypes.data, tau.ctypes.data, g.ctypes.data, out.ctypes.data,
                           bad.ctypes.data, start, stop)
        return int(bad[0]), int(singular), int(bad[1])

    def run_one(self, at: int) -> int:
        """The state in the buffer at address ``at`` (:func:`_one`'s layout): its flags, 0 for a plain answer."""
        self.will_run(1)
        return self.one(at)


_KERNELS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def kernel(tree, case: int, algorithm: str = "crba", width: int | None = None):
    """The tree's :class:`Kernel` in ``case`` by ``algorithm`` (``"crba"`` or ``"aba"``) over ``width`` states a step
    (default :func:`lanes`; 1 for the single-state lane: one state in a vector of four or eight costs the vector's
    scalar ``sin`` and ``cos`` calls four or eight times), loaded from the cache or traced and compiled once per
    width, in a process; or None where the lanes are not available: no llvmlite, a tree over :data:`MAX_OPS`, or one
    whose code branches on a state's value."""
    per = _KERNELS.get(tree)
    if per is None:
        per = _KERNELS[tree] = {}
    key = (case, algorithm, width or lanes())
    if key not in per:
        per[key] = _build(tree, case, algorithm, key[2], per)
    return per[key]


def _traced(tree, case, algorithm):
    """The tree's :class:`Trace`, or None where it is not to be compiled (too large, untraceable)."""
    if estimate(tree, algorithm) > 2 * MAX_OPS:  # not even traced: the trace of a long chain's CRBA is itself slow
        return None
    try:
        tr = trace(tree, case, algorithm)
    except Untraceable:
        return None
    return None if sum(_needed(tr)) > MAX_OPS else tr


def _build(tree, case, algorithm, width, per):
    """The :class:`Kernel` of :func:`kernel`: the cached ``-O2`` code, else the cached ``-O0`` code, else the trace
    (kept in ``per``, once per case and algorithm) compiled at ``-O0``; the trace is made only where code is
    compiled (tracing gymnasium's humanoid takes about half a second)."""
    try:
        import llvmlite.binding  # noqa: F401
    except ImportError:  # pragma: no cover - llvmlite comes with numba
        return None
    from relacc.core.tree.model import welded_folded

    folded = welded_folded(tree)
    name = "lanes_" + _key(folded, case, algorithm, width)[:32]
    sizes = (folded.nq_in(case), folded.nv)

    def traced():
        if (case, algorithm) not in per:
            per[(case, algorithm)] = _traced(tree, case, algorithm)
        return per[(case, algorithm)]

    def make_ir():
        return emit(traced(), width, name)

    best = compile_cached(make_ir, name, 2, cached_only=True)
    if best is not None:
        return Kernel(*best, 2, width, *sizes)
    start = compile_cached(make_ir, name, 0, cached_only=True)
    if start is None:
        if traced() is None:
            return None
        start = compile_cached(make_ir, name, 0)
    return Kernel(*start, 0, width, *sizes, upgrade=lambda: compile_cached(make_ir, name, 2))


def _key(folded, case: int, algorithm: str, width: int) -> str:
    """A hash of everything the compiled code depends on, without tracing: the folded tree's arrays that
    :func:`trace` reads (:func:`relacc.kernels.tree.arrays_of`, ``dof_paths``, ``inertia_arrays``), the case,
    algorithm and lane width, the source of every module the trace runs or the code is emitted by
    (:func:`_sources`), and NumPy's, llvmlite's and the CPU's identities."""
    import hashlib

    import llvmlite
    import llvmlite.binding as llvm

    from relacc.kernels.tree import arrays_of
    from relacc.kernels.tree_crba import dof_paths
    from relacc.kernels.tree_spatial import inertia_arrays

    h = hashlib.sha256()
    for part in (*arrays_of(folded), *dof_paths(folded), *inertia_arrays(folded)):
        a = np.ascontiguousarray(part)
        if a.dtype.hasobject:  # pragma: no cover - its bytes would be addresses: a key that never matches
            raise TypeError("the lanes' cache key takes numeric arrays only")
        h.update(repr((a.dtype.str, a.shape)).encode())
        h.update(a.tobytes())
    for part in (repr((case, algorithm, width, folded.nq_in(case), folded.nv)), _sources(), np.__version__,
                 llvmlite.__version__, llvm.get_host_cpu_name(), llvm.get_host_cpu_features().flatten()):
        h.update(part.encode())
    return h.hexdigest()


@functools.cache
def _sources() -> str:
    """The source of this package's modules (the emitter and every kernel the trace runs) and of
    :mod:`relacc.core.tolerances` (the pivot floor, the quaternion tolerance), read once."""
    from pathlib import Path

    here = Path(__file__).parent
    files = sorted(here.glob("*.py")) + [here.parent / "core" / "tolerances.py"]
    return "".join(f"{f.name}\n{f.read_text(encoding='utf-8')}" for f in files)


def _cache_dir():
    """Where numba caches relacc's kernels (beside the package, or numba's user-wide or ``NUMBA_CACHE_DIR``
    directory): the object code of traced trees goes with them; None where it cannot be found."""
    try:
        from numba.core.caching import FunctionCache

        from relacc.kernels.tree_crba import crba_block

        return FunctionCache(crba_block.py_func)._cache_path
    except Exception:  # pragma: no cover - numba's internals moved: compile every process
        return None


_INITIALIZED: list = []


def _machine(level: int = 2):
    """A new LLVM target machine for this CPU, code generation at ``-O<level>``. One per kernel: the engine that runs a
    kernel's code takes its machine with it when it is freed (llvmlite marks the machine owned by the engine; a
    machine shared between engines is used after it is freed)."""
    import llvmlite.binding as llvm

    with _TRACE_LOCK:
        if not _INITIALIZED:
            try:
                llvm.initialize()
            except RuntimeError:  # llvmlite >= 0.45 initializes itself
                pass
            llvm.initialize_native_target()
            llvm.initialize_native_asmprinter()
            _INITIALIZED.append(True)
    return llvm.Target.from_default_triple().create_target_machine(
        cpu=llvm.get_host_cpu_name(), features=llvm.get_host_cpu_features().flatten(), opt=level)


def jit(ir_text: str, level: int = 2):
    """An LLVM execution engine holding ``ir_text`` compiled for this CPU at ``-O<level>`` (not cached: for small
    modules; the kernels go through :func:`compile_cached`). Keep the engine while its functions are called."""
    import llvmlite.binding as llvm

    machine = _machine(level)
    engine = llvm.create_mcjit_compiler(llvm.parse_assembly(""), machine)
    engine.add_module(_parsed(ir_text, machine))
    engine.finalize_object()
    return engine


_PROTO = ctypes.CFUNCTYPE(ctypes.c_int64, *([ctypes.c_void_p] * 6), ctypes.c_int64, ctypes.c_int64)
_ONE_PROTO = ctypes.CFUNCTYPE(ctypes.c_int64, ctypes.c_void_p)


CACHE_MAGIC = b"relacc-lanes-object 1\n"
"""The first line of a cached object file; then the kernel's name, the SHA-256 of the object code, and the code."""


def compile_cached(make_ir, name: str, level: int = 2, cached_only: bool = False):
    """``((the compiled function name, its single-state entry point name_one), as ctypes functions; their engine,
    which holds the code: keep it while the functions are called)``, code generated at ``-O<level>`` for this CPU:
    the object code from the cache directory (``name_O<level>.lobj``) where an earlier process left it whole, else
    ``make_ir()`` compiled and its object code left there (:func:`_write_object`; a cache that cannot be written is
    skipped); None with ``cached_only`` and nothing cached.

    What is loaded is verified before it runs (:func:`_read_object`): a cached file that is truncated, empty, edited
    or another kernel's, or whose code lacks the function, is compiled again and written anew, and said once on
    stderr; it never reaches the processor.
    """
    import os

    import llvmlite.binding as llvm

    machine = _machine(level)
    where = _cache_dir()
    path = os.path.join(where, f"{name}_O{level}.lobj") if where else None
    data = _read_object(path, name) if path else None
    if data is None and cached_only:
        return None
    for attempt in range(2):
        if data is None:
            data = machine.emit_object(_parsed(make_ir(), machine))
            if path:
                _write_object(path, name, data)
        engine = llvm.create_mcjit_compiler(llvm.parse_assembly(""), machine)
        engine.add_object_file(llvm.ObjectFileRef.from_data(data))
        engine.finalize_object()
        address, one = engine.get_function_address(name), engine.get_function_address(f"{name}_one")
        if address and one:
            return (_PROTO(address), _ONE_PROTO(one)), engine
        if attempt:  # pragma: no cover - freshly compiled code always has its function
            raise RuntimeError(f"the compiled lanes kernel {name} lacks its function")
        _damaged(path, "its code lacks the kernel's function")
        data, machine = None, _machine(level)  # the engine took the machine with it
    raise AssertionError("unreachable")  # pragma: no cover


def _read_object(path, name: str) -> bytes | None:
    """The object code cached at ``path`` for the kernel ``name``, or None: no file, or a damaged one (said once,
    :func:`_damaged`). Whole means: the magic line, the kernel's own name, and the SHA-256 of the code that
    follows."""
    import hashlib
    import os

    if not os.path.exists(path):
        return None
    try:
        with open(path, "rb") as fh:
            raw = fh.read()
    except OSError:
        return None
    head, sep, rest = raw.partition(b"\n")
    fields = rest.split(b"\n", 2) if sep else []
    if head + b"\n" != CACHE_MAGIC or len(fields) != 3:
        _damaged(path, "not a relacc object file (truncated, empty or overwritten)")
        return None
    owner, digest, code = fields
    if owner.decode("utf-8", "replace") != name:
        _damaged(path, f"it holds another kernel's code ({owner[:40].decode('utf-8', 'replace')})")
        return None
    if hashlib.sha256(code).hexdigest().encode() != digest:
        _damaged(path, "its code does not match its checksum (edited or partly written)")
        return None
    return code


def _write_object(path, name: str, data: bytes) -> None:
    """``data`` cached at ``path`` with its name and checksum (:data:`CACHE_MAGIC`): a temporary file beside it,
    flushed and synced, then renamed over it, so that a crash leaves the previous file or the new one whole; the
    temporary file is removed when the write fails (a full disk) and the cache skipped."""
    import hashlib
    import os

    tmp = f"{path}.{os.getpid()}.{threading.get_ident()}.tmp"
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(tmp, "wb") as fh:
            fh.write(CACHE_MAGIC + name.encode() + b"\n" + hashlib.sha256(data).hexdigest().encode() + b"\n" + data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except OSError:
        try:
            os.unlink(tmp)
        except OSError:
            pass


_SAID: set = set()


def _damaged(path, why: str) -> None:
    """One line on stderr, once per file in a process: a cached kernel was damaged and is compiled again."""
    import sys

    if path not in _SAID:
        _SAID.add(path)
        print(f"relacc: the cached kernel {path} is damaged ({why}); compiling it again", file=sys.stderr)


def _parsed(ir_text: str, machine):
    """``ir_text`` parsed and verified for ``machine``. No optimization passes: the trace is already straight-line
    code with every repeated operation recorded once, and LLVM's ``-O3`` pipeline changed nothing measurable on it
    (gymnasium's ant: 0.333 us a state with it, 0.330 without) for 0.2 s of compilation; the code generator's own
    level (instruction selection, scheduling, registers) is what the speed comes from (:data:`UPGRADE_STATES`)."""
    import llvmlite.binding as llvm

    mod = llvm.parse_assembly(ir_text)
    mod.triple = llvm.get_process_triple()
    mod.data_layout = str(machine.target_data)
    mod.verify()
    return mod
