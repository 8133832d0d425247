"""One state's call from CPython straight into compiled code: a builtin function (``METH_FASTCALL``) whose body is
LLVM IR, around a lanes kernel's single-state entry point (:func:`relacc.kernels.lanes._one`).

Through ctypes and a Python method, one state of gymnasium's ant spent about 3 us in Python (the input check, the
copies in and out, the state count) and 0.5 us in ctypes around a 1.7 us kernel (benchmarks/single.py). Here the
checks, the copies and the call are compiled: the builtin takes ``(q, u)``, checks that each is an
``numpy.ndarray`` (not a subclass) of float64 (the native-order singleton ``numpy.dtype``), one-dimensional of the
state's size, C-contiguous and aligned, copies them into the kernel's buffer, calls it, and returns a new read-only
``(nv,)`` array (``out.copy()`` called from the compiled code, then its writeable flag cleared, as
``PyArray_CLEARFLAGS`` does), or None for anything else: an argument that fails a check, or a state the kernel
flags (the caller's general path then says what is wrong). The GIL is held throughout, so the one buffer is never
written by two threads at once.

The IR reads ``PyObject`` and ``PyArrayObject`` fields at fixed offsets (:data:`_FIELDS`); :func:`_layout_ok` checks
them on live objects first, and where they differ (a debug or free-threaded CPython, another NumPy layout) no builtin
is made and the caller keeps its ctypes path. Every address the IR needs (the types, None, ``Py_IncRef``,
``PyObject_CallNoArgs``, the buffer, the kernel) is read from a context array at run time, so one compiled wrapper
serves every tree, and its code holds no address of this process.
"""

from __future__ import annotations

import ctypes
import functools
import sys
import sysconfig

import numpy as np

_FIELDS = {"ob_type": 8, "data": 16, "nd": 24, "dimensions": 32, "descr": 56, "flags": 64}
"""Byte offsets in a ``PyArrayObject`` (``PyObject_HEAD`` then NumPy's ``PyArrayObject_fields``) on a 64-bit
release build of CPython."""

_CONTIGUOUS_ALIGNED, _WRITEABLE = 0x0001 | 0x0100, 0x0400
"""NumPy's ``NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED`` and ``NPY_ARRAY_WRITEABLE``."""

_CTX = ("ndarray", "float64", "none", "incref", "call", "copy", "buf", "one", "nq", "nv")
"""The context array's entries, in order (int64 each: addresses, then the state's sizes)."""


def _ir() -> str:
    """LLVM IR of ``PyObject* relacc_direct(PyObject* ctx, PyObject* const* args, Py_ssize_t nargs)``."""
    at = {k: i for i, k in enumerate(_CTX)}
    L = ["define i8* @relacc_direct(i8* %self, i8** %args, i64 %nargs) {", "entry:",
         f"  %sd = getelementptr i8, i8* %self, i64 {_FIELDS['data']}", "  %sdp = bitcast i8* %sd to i64**",
         "  %ctx = load i64*, i64** %sdp"]
    for name, k in at.items():
        L += [f"  %c_{name} = getelementptr i64, i64* %ctx, i64 {k}", f"  %{name} = load i64, i64* %c_{name}"]
    L += ["  %bufp = inttoptr i64 %buf to double*", "  %two = icmp eq i64 %nargs, 2",
          "  br i1 %two, label %q0, label %no"]

    def field(a, name, ty):
        return [f"  %{a}_{name}p = getelementptr i8, i8* %{a}o, i64 {_FIELDS[name]}",
                f"  %{a}_{name}c = bitcast i8* %{a}_{name}p to {ty}*", f"  %{a}_{name} = load {ty}, {ty}* %{a}_{name}c"]

    for k, (a, n, start) in enumerate((("q", "%nq", "0"), ("u", "%nv", "%nq"))):
        nxt = "u0" if a == "q" else "run"
        L += [f"{a}0:", f"  %{a}pp = getelementptr i8*, i8** %args, i64 {k}", f"  %{a}o = load i8*, i8** %{a}pp",
              *field(a, "ob_type", "i64"), f"  %{a}_t = icmp eq i64 %{a}_ob_type, %ndarray",
              f"  br i1 %{a}_t, label %{a}1, label %no", f"{a}1:", *field(a, "nd", "i32"),
              *field(a, "dimensions", "i64*"), f"  %{a}_n = load i64, i64* %{a}_dimensions",
              *field(a, "descr", "i64"), *field(a, "flags", "i32"),
              f"  %{a}_ok1 = icmp eq i32 %{a}_nd, 1", f"  %{a}_ok2 = icmp eq i64 %{a}_n, {n}",
              f"  %{a}_ok3 = icmp eq i64 %{a}_descr, %float64",
              f"  %{a}_fl = and i32 %{a}_flags, {_CONTIGUOUS_ALIGNED}",
              f"  %{a}_ok4 = icmp eq i32 %{a}_fl, {_CONTIGUOUS_ALIGNED}",
              f"  %{a}_ok12 = and i1 %{a}_ok1, %{a}_ok2", f"  %{a}_ok34 = and i1 %{a}_ok3, %{a}_ok4",
              f"  %{a}_ok = and i1 %{a}_ok12, %{a}_ok34", f"  br i1 %{a}_ok, label %{a}c, label %no",
              f"{a}c:", *field(a, "data", "double*"), f"  %{a}_dst = getelementptr double, double* %bufp, i64 {start}",
              f"  %{a}_go = icmp sgt i64 {n}, 0", f"  br i1 %{a}_go, label %{a}l, label %{nxt}",
              f"{a}l:", f"  %{a}_i = phi i64 [0, %{a}c], [%{a}_j, %{a}l]",
              f"  %{a}_s = getelementptr double, double* %{a}_data, i64 %{a}_i",
              f"  %{a}_d = getelementptr double, double* %{a}_dst, i64 %{a}_i",
              f"  %{a}_v = load double, double* %{a}_s", f"  store double %{a}_v, double* %{a}_d",
              f"  %{a}_j = add i64 %{a}_i, 1", f"  %{a}_more = icmp slt i64 %{a}_j, {n}",
              f"  br i1 %{a}_more, label %{a}l, label %{nxt}"]
    L += ["run:", "  %onef = inttoptr i64 %one to i64 (double*)*", "  %flags = call i64 %onef(double* %bufp)",
          "  %plain = icmp eq i64 %flags, 0", "  br i1 %plain, label %copy_out, label %no",
          "copy_out:", "  %callf = inttoptr i64 %call to i8* (i8*)*", "  %copyo = inttoptr i64 %copy to i8*",
          "  %r = call i8* %callf(i8* %copyo)", "  %failed = icmp eq i8* %r, null",
          "  br i1 %failed, label %raise, label %done",
          "done:", f"  %r_fp = getelementptr i8, i8* %r, i64 {_FIELDS['flags']}", "  %r_fc = bitcast i8* %r_fp to i32*",
          "  %r_f = load i32, i32* %r_fc", f"  %r_g = and i32 %r_f, {~_WRITEABLE}", "  store i32 %r_g, i32* %r_fc",
          "  ret i8* %r",
          "raise:", "  ret i8* null",
          "no:", "  %increff = inttoptr i64 %incref to void (i8*)*", "  %noneo = inttoptr i64 %none to i8*",
          "  call void %increff(i8* %noneo)", "  ret i8* %noneo", "}"]
    return "\n".join(L) + "\n"


class _MethodDef(ctypes.Structure):
    _fields_ = [("ml_name", ctypes.c_char_p), ("ml_meth", ctypes.c_void_p), ("ml_flags", ctypes.c_int),
                ("ml_doc", ctypes.c_char_p)]


_METH_FASTCALL = 0x0080


class _Context(np.ndarray):
    """The context array (:data:`_CTX`), which also keeps alive everything its addresses point at (``keep``)."""

    keep: tuple = ()


@functools.cache
def _layout_ok() -> bool:
    """The offsets of :data:`_FIELDS` read, on live arrays, what NumPy says of them; and a CPython with a GIL."""
    if sys.maxsize != 2**63 - 1 or sysconfig.get_config_var("Py_GIL_DISABLED") or hasattr(sys, "gettotalrefcount"):
        return False
    try:
        for a in (np.zeros(3), np.zeros((2, 5))[:, 1]):
            base = id(a)

            def read(name, ty, base=base):
                return ty.from_address(base + _FIELDS[name]).value

            if (read("ob_type", ctypes.c_size_t) != id(np.ndarray) or read("data", ctypes.c_size_t) != a.ctypes.data
                    or read("nd", ctypes.c_int32) != a.ndim or read("descr", ctypes.c_size_t) != id(a.dtype)
                    or read("flags", ctypes.c_int32) != a.flags.num
                    or ctypes.c_int64.from_address(read("dimensions", ctypes.c_size_t)).value != a.shape[0]):
                return False
    except Exception:  # pragma: no cover - an unexpected layout is simply not used
        return False
    return True


@functools.cache
def _compiled():
    """``(address of relacc_direct, its engine)``, compiled once a process (``-O2``; a few milliseconds)."""
    from relacc.kernels.lanes import jit

    engine = jit(_ir())
    return engine.get_function_address("relacc_direct"), engine


def builtin(one: int, nq: int, nv: int, gravity, keep: object):
    """A builtin ``f(q, u) -> udot or None`` around the compiled single-state entry point at address ``one``
    (:func:`relacc.kernels.lanes._one`'s layout ``q (nq) | u (nv) | tau (nv) | g (3) | out (nv)``; ``tau`` zero,
    ``gravity (3,)`` m/s^2 in world components fixed here), ``udot (nv,)`` its output in the kernel's units (m/s^2,
    rad/s^2); ``keep`` (the kernel, whose engine holds the code at ``one``) is kept alive with it. None where this
    CPython's or NumPy's layout is not the one the IR reads (:func:`_layout_ok`)."""
    if not _layout_ok():
        return None
    address, engine = _compiled()
    buf = np.zeros(nq + 3 * nv + 3)
    buf[nq + 2 * nv:nq + 2 * nv + 3] = gravity
    copy = buf[nq + 2 * nv + 3:].copy  # a bound method: out.copy(), called from the compiled code
    api = ctypes.pythonapi
    ctx = np.array([id(np.ndarray), id(np.dtype(np.float64)), id(None),
                    ctypes.cast(api.Py_IncRef, ctypes.c_void_p).value,
                    ctypes.cast(api.PyObject_CallNoArgs, ctypes.c_void_p).value, id(copy), buf.ctypes.data, one,
                    nq, nv], dtype=np.int64).view(_Context)
    method = _MethodDef(b"relacc_one_state", address, _METH_FASTCALL, None)
    ctx.keep = (buf, copy, keep, method, engine)
    return _NEW(ctypes.addressof(method), ctx, None)


_NEW = ctypes.PYFUNCTYPE(ctypes.py_object, ctypes.c_void_p, ctypes.py_object, ctypes.c_void_p)(
    ("PyCFunction_NewEx", ctypes.pythonapi))
"""``PyCFunction_NewEx(PyMethodDef*, self, module)`` with its own prototype, leaving ``ctypes.pythonapi``'s shared
function object as other code finds it."""
