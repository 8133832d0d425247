"""A tree's forward dynamics over several states at once in vector lanes: the compiled kernels' own code, traced once
per tree and case into straight-line arithmetic and compiled by LLVM with ``<W x double>`` vectors.

numba's loops run one state at a time: the recursions over bodies are short loops it does not vectorize, so most of
the arithmetic stays scalar (docs/benchmarks.md, "Lanes"). Here the composite-rigid-body kernel
(:mod:`relacc.kernels.tree_spatial`'s ``forward``, :mod:`relacc.kernels.tree_crba`'s ``mass_matrix`` and
``factor_solve``, case 3's maps to and from case-2 speeds) is run once as Python on symbolic scalars (:class:`X`): the
tree's structure and constants (its parents, joint kinds, axes, anchors, masses, inertias, armature) decide every
branch and fold into the arithmetic (a product with an axis' zero component disappears), and what is left is a list
of operations on the state's coordinates, speeds, forces and gravity. Each operation is emitted as one LLVM vector
instruction on ``W`` states (:data:`LANES`: 8 where the CPU has AVX-512, else 4), a block of states the innermost
dimension, and JIT-compiled for the host CPU through llvmlite (numba's own dependency: nothing to compile at install
time). The same operations in the same order as the numba kernel, so the same rounding but for the multiply-adds
LLVM fuses (``contract``, as the numba kernels' ``fastmath={'contract'}``).

A pivot of the factorization not above :data:`relacc.core.tolerances.PIVOT_FLOOR` times its diagonal entry makes that
state's row NaN and is counted, as the numba kernel does; non-finite inputs and non-unit quaternions are counted per
state. CppADCodeGen does the same for Pinocchio with a C compiler at run time; LLVM is already in the process.
"""

from __future__ import annotations

import ctypes
import math
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

    # arithmetic ---------------------------------------------------------------------------------------------------
    def __add__(self, o):
        if not isinstance(o, X) and o == 0.0:
            return self
        return self.g.node("add", self.i, _ref(o))

    def __radd__(self, o):
        if o == 0.0:
            return self
        return self.g.node("add", _ref(o), self.i)

    def __sub__(self, o):
        if not isinstance(o, X) and o == 0.0:
            return self
        return self.g.node("sub", self.i, _ref(o))

    def __rsub__(self, o):
        if o == 0.0:
            return -self
        return self.g.node("sub", _ref(o), self.i)

    def __mul__(self, o):
        if not isinstance(o, X):
            if o == 0.0:
                return 0.0
            if o == 1.0:
                return self
            if o == -1.0:
                return -self
        return self.g.node("mul", self.i, _ref(o))

    def __rmul__(self, o):
        if o == 0.0:
            return 0.0
        if o == 1.0:
            return self
        if o == -1.0:
            return -self
        return self.g.node("mul", _ref(o), self.i)

    def __truediv__(self, o):
        if not isinstance(o, X) and o == 1.0:
            return self
        return self.g.node("div", self.i, _ref(o))

    def __rtruediv__(self, o):
        if o == 0.0:
            return 0.0
        return self.g.node("div", _ref(o), self.i)

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
    import relacc.kernels.tree_crba as crba
    import relacc.kernels.tree_spatial as spatial

    mods = [m for m in (tree_mod, so3, spatial, crba) if "math" in vars(m)]
    try:
        from numba.core.compiler_lock import global_compiler_lock as lock
    except ImportError:  # pragma: no cover - without numba nothing compiles
        lock = _TRACE_LOCK
    with lock:
        saved = [m.math for m in mods]
        for m in mods:
            m.math = _Math()
        try:
            yield
        finally:
            for m, s in zip(mods, saved):
                m.math = s


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
        quats: ``q``'s first column of each unit quaternion (cases 1, 2).
    """

    ops: tuple
    nq: int
    nv: int
    inputs: dict
    outputs: tuple
    pivots: tuple
    quats: tuple


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
    nq, nv, nb, nj = folded.nq(case), folded.nv, T.parent.shape[0], T.jtype.shape[0]
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
            Ic, cd, x2 = IA.copy(), _obj(6), _obj((1, nv))
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
    return Trace(tuple(g.ops), nq, nv, inputs, tuple(_ref(r) for r in res), tuple(g.pivots), quats)


LANES = 4


def lanes() -> int:
    """States per vector: 8 where the CPU has AVX-512 (one ``zmm`` register), else 4 (``ymm``)."""
    import llvmlite.binding as llvm

    feats = llvm.get_host_cpu_features()
    return 8 if feats.get("avx512f", False) else 4


def emit(tr: Trace, width: int, name: str = "lanes") -> str:
    """LLVM IR of ``i64 name(double* q, double* u, double* tau, double* g, double* out, i64* bad, i64 start,
    i64 stop)``: rows ``start .. stop - 1`` of C-contiguous ``q (n, nq)``, ``u``, ``tau (n, nv)`` to ``out (n, nv)``,
    ``width`` states a step; returns the number of singular states and adds the number of states with bad inputs to
    ``*bad``."""
    import llvmlite.ir as ir

    d, i64, i1 = ir.DoubleType(), ir.IntType(64), ir.IntType(1)
    vt, mt = ir.VectorType(d, width), ir.VectorType(i1, width)
    dp = d.as_pointer()
    mod = ir.Module(name)
    fn = ir.Function(mod, ir.FunctionType(i64, [dp, dp, dp, dp, dp, i64.as_pointer(), i64, i64]), name)
    qp, up, tp, gp, op, badp, start, stop = fn.args
    intr = {k: ir.Function(mod, ir.FunctionType(vt, [vt]), f"llvm.{k}.v{width}f64") for k in ("sqrt", "sin", "cos")}
    fabs = ir.Function(mod, ir.FunctionType(vt, [vt]), f"llvm.fabs.v{width}f64")
    entry, loop, done = fn.append_basic_block("entry"), fn.append_basic_block("loop"), fn.append_basic_block("done")
    b0 = ir.IRBuilder(entry)
    empty = b0.icmp_signed(">=", start, stop)
    b0.cbranch(empty, done, loop)
    bld = ir.IRBuilder(loop)
    i = bld.phi(i64)
    nsing = bld.phi(i64)
    nbad = bld.phi(i64)
    i.add_incoming(start, entry)
    nsing.add_incoming(ir.Constant(i64, 0), entry)
    nbad.add_incoming(ir.Constant(i64, 0), entry)
    last = bld.sub(stop, ir.Constant(i64, 1))
    rows, live = [], []
    for lane in range(width):
        r = bld.add(i, ir.Constant(i64, lane))
        ok = bld.icmp_signed("<", r, stop)
        live.append(ok)
        rows.append(bld.select(ok, r, last))
    sizes = {"q": tr.nq, "u": tr.nv, "tau": tr.nv}
    ptrs = {"q": qp, "u": up, "tau": tp}
    undef = ir.Constant(vt, ir.Undefined)

    def splat(c):
        return ir.Constant(vt, [c] * width)

    def load(name, c):
        if name == "g":
            s = bld.load(bld.gep(gp, [ir.Constant(i64, c)]))
            v = bld.insert_element(undef, s, ir.Constant(ir.IntType(32), 0))
            return bld.shuffle_vector(v, undef, ir.Constant(ir.VectorType(ir.IntType(32), width), [0] * width))
        v = undef
        for lane in range(width):
            at = bld.add(bld.mul(rows[lane], ir.Constant(i64, sizes[name])), ir.Constant(i64, c))
            v = bld.insert_element(v, bld.load(bld.gep(ptrs[name], [at])), ir.Constant(ir.IntType(32), lane))
        return v

    def contract(inst):
        inst.flags.append("contract")
        return inst

    vals: list = [None] * len(tr.ops)

    def val(ref):
        return splat(ref[1]) if isinstance(ref, tuple) else vals[ref]

    need = _needed(tr)
    for k, (opn, a, b) in enumerate(tr.ops):
        if not need[k]:
            continue
        if opn == "in":
            vals[k] = load(a, b)
        elif opn == "add":
            vals[k] = contract(bld.fadd(val(a), val(b)))
        elif opn == "sub":
            vals[k] = contract(bld.fsub(val(a), val(b)))
        elif opn == "mul":
            vals[k] = contract(bld.fmul(val(a), val(b)))
        elif opn == "div":
            vals[k] = bld.fdiv(val(a), val(b))
        elif opn == "neg":
            vals[k] = bld.fneg(val(a)) if hasattr(bld, "fneg") else bld.fsub(splat(-0.0), val(a))
        else:
            vals[k] = bld.call(intr[opn], [val(a)])
    ok = ir.Constant(mt, [1] * width)
    for a, b in tr.pivots:
        ok = bld.and_(ok, bld.fcmp_ordered(">", val(a), val(b)))
    # bad inputs: a non-finite q or u, or a quaternion whose squared norm is off 1 by more than the tolerance
    good = ir.Constant(mt, [1] * width)
    colv = {}
    for name in ("q", "u"):
        for c in range(sizes[name]):
            k = tr.inputs.get((name, c))
            v = vals[k] if k is not None and vals[k] is not None else load(name, c)
            colv[(name, c)] = v
            good = bld.and_(good, bld.fcmp_ordered("==", bld.fsub(v, v), splat(0.0)))
    for a in tr.quats:
        n2 = None
        for c in range(a, a + 4):
            v = colv[("q", c)]
            sq = bld.fmul(v, v)
            n2 = sq if n2 is None else bld.fadd(n2, sq)
        dev = bld.call(fabs, [bld.fsub(n2, splat(1.0))])
        good = bld.and_(good, bld.fcmp_ordered("<=", dev, splat(QUATERNION_NORM_TOLERANCE)))
    nan = splat(float("nan"))
    outs = [bld.select(ok, val(r), nan) for r in tr.outputs]
    for lane in range(width):
        li = ir.Constant(ir.IntType(32), lane)
        with bld.if_then(live[lane]):
            base = bld.mul(rows[lane], ir.Constant(i64, tr.nv))
            for c, v in enumerate(outs):
                bld.store(bld.extract_element(v, li), bld.gep(op, [bld.add(base, ir.Constant(i64, c))]))
    count_s, count_b = nsing, nbad
    for lane in range(width):
        li = ir.Constant(ir.IntType(32), lane)
        s = bld.and_(bld.not_(bld.extract_element(ok, li)), live[lane])
        t = bld.and_(bld.not_(bld.extract_element(good, li)), live[lane])
        count_s = bld.add(count_s, bld.zext(s, i64))
        count_b = bld.add(count_b, bld.zext(t, i64))
    nxt = bld.add(i, ir.Constant(i64, width))
    tail = bld.block
    i.add_incoming(nxt, tail)
    nsing.add_incoming(count_s, tail)
    nbad.add_incoming(count_b, tail)
    bld.cbranch(bld.icmp_signed("<", nxt, stop), loop, done)
    bd = ir.IRBuilder(done)
    rs = bd.phi(i64)
    rb = bd.phi(i64)
    rs.add_incoming(ir.Constant(i64, 0), entry)
    rb.add_incoming(ir.Constant(i64, 0), entry)
    rs.add_incoming(count_s, tail)
    rb.add_incoming(count_b, tail)
    bd.store(bd.add(bd.load(badp), rb), badp)
    bd.ret(rs)
    return str(mod)


def _needed(tr: Trace) -> list:
    """Which operations an output or a pivot check depends on."""
    need = [False] * len(tr.ops)
    stack = [r for r in tr.outputs if not isinstance(r, tuple)]
    for a, b in tr.pivots:
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


@dataclass(frozen=True, eq=False)
class Kernel:
    """One tree's compiled forward dynamics in one case over ``width`` states a step.

    Attributes:
        fn: the compiled function (:func:`emit`'s signature). engine: the LLVM engine holding its code (the code
            is freed with it, when the tree is). width: states a vector. ops: the traced operations (the arithmetic
            a state costs). nq, nv: the state's sizes.
    """

    fn: Callable[..., int]
    engine: object
    width: int
    ops: int
    nq: int
    nv: int

    def block(self, q, u, tau, g, out, start: int, stop: int) -> tuple:
        """Rows ``start .. stop - 1`` of C-contiguous float64 ``q (n, nq)``, ``u (n, nv)``, ``tau (n, nv)`` with
        gravity ``g (3,)`` into ``out (n, nv)``: ``(states with bad inputs, singular states)``. The compiled code
        runs without the GIL (ctypes releases it), so shares of a batch run on Python threads at once."""
        bad = np.zeros(1, np.int64)
        singular = self.fn(q.ctypes.data, u.ctypes.data, tau.ctypes.data, g.ctypes.data, out.ctypes.data,
                           bad.ctypes.data, start, stop)
        return int(bad[0]), int(singular)


_KERNELS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def kernel(tree, case: int, algorithm: str = "crba"):
    """The tree's :class:`Kernel` in ``case`` by ``algorithm`` (``"crba"`` or ``"aba"``; traced, compiled or loaded
    from the cache once per tree, case and algorithm in a process), or None where the lanes are not available: no
    llvmlite, a tree over :data:`MAX_OPS`, or one whose code branches on a state's value."""
    per = _KERNELS.get(tree)
    if per is None:
        per = _KERNELS[tree] = {}
    if (case, algorithm) not in per:
        per[(case, algorithm)] = _build(tree, case, algorithm)
    return per[(case, algorithm)]


def _build(tree, case, algorithm):
    try:
        import llvmlite.binding  # noqa: F401
    except ImportError:  # pragma: no cover - llvmlite comes with numba
        return None
    if estimate(tree, algorithm) > 2 * MAX_OPS:  # not even traced: the trace of a long chain's CRBA is itself slow
        return None
    try:
        tr = trace(tree, case, algorithm)
    except Untraceable:
        return None
    if sum(_needed(tr)) > MAX_OPS:
        return None
    width = lanes()
    name = "lanes_" + _key(tr, width)[:32]
    fn, engine = compile_cached(lambda: emit(tr, width, name), name)
    return Kernel(fn, engine, width, sum(_needed(tr)), tr.nq, tr.nv)


def _key(tr: Trace, width: int) -> str:
    """A hash of everything the compiled code depends on: the trace, the lane width, this module's source, llvmlite's
    version and the CPU."""
    import hashlib

    import llvmlite
    import llvmlite.binding as llvm

    h = hashlib.sha256()
    for part in (repr((tr.ops, tr.nq, tr.nv, sorted(tr.inputs.items()), tr.outputs, tr.pivots, tr.quats, width)),
                 _source(), llvmlite.__version__,
                 llvm.get_host_cpu_name(), llvm.get_host_cpu_features().flatten()):
        h.update(part.encode())
    return h.hexdigest()


def _source() -> str:
    """This module's source (the emitter is part of what the object code depends on), read once."""
    if not _SOURCE:
        from pathlib import Path

        _SOURCE.append(Path(__file__).read_text(encoding="utf-8"))
    return _SOURCE[0]


_SOURCE: list = []


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


def _machine():
    """A new LLVM target machine for this CPU, code generation at ``-O2``. One per kernel: the engine that runs a
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
        cpu=llvm.get_host_cpu_name(), features=llvm.get_host_cpu_features().flatten(), opt=2)


_PROTO = ctypes.CFUNCTYPE(ctypes.c_int64, *([ctypes.c_void_p] * 6), ctypes.c_int64, ctypes.c_int64)


def compile_cached(make_ir, name: str):
    """``(the compiled function name, a ctypes function; its engine, which holds the code: keep it while the function
    is called)``, code generated at ``-O2`` for this CPU: the object code from the cache directory (``name``.o)
    where an earlier process left it, else ``make_ir()`` compiled and its object code left there (written
    atomically; a cache that cannot be written is skipped)."""
    import os

    import llvmlite.binding as llvm

    machine = _machine()
    where = _cache_dir()
    path = os.path.join(where, name + ".o") if where else None
    data = None
    if path and os.path.exists(path):
        with open(path, "rb") as fh:
            data = fh.read()
    if data is None:
        data = machine.emit_object(_parsed(make_ir(), machine))
        if path:
            try:
                os.makedirs(where, exist_ok=True)
                tmp = f"{path}.{os.getpid()}.{threading.get_ident()}.tmp"
                with open(tmp, "wb") as fh:
                    fh.write(data)
                os.replace(tmp, path)
            except OSError:
                pass
    engine = llvm.create_mcjit_compiler(llvm.parse_assembly(""), machine)
    engine.add_object_file(llvm.ObjectFileRef.from_data(data))
    engine.finalize_object()
    return _PROTO(engine.get_function_address(name)), engine


def _parsed(ir_text: str, machine):
    """``ir_text`` parsed and verified for ``machine``. No optimization passes: the trace is already straight-line
    code with every repeated operation recorded once, and LLVM's ``-O3`` pipeline changed nothing measurable on it
    (gymnasium's ant: 0.333 us a state with it, 0.330 without) for 0.2 s of compilation; the code generator's own
    ``-O2`` (instruction selection, scheduling, registers) is what the speed comes from (0.42 us at ``-O0``)."""
    import llvmlite.binding as llvm

    mod = llvm.parse_assembly(ir_text)
    mod.triple = llvm.get_process_triple()
    mod.data_layout = str(machine.target_data)
    mod.verify()
    return mod
