"""numba, when importable, and the decorator that makes a function both Python and compilable.

The fused kernels (:mod:`relacc.kernels.perstate`, :mod:`relacc.kernels.trig`) are plain
arithmetic on scalars or tuples: :func:`jitable` leaves them runnable as
Python on whole numpy columns (the numpy backend) and lets numba compile them
when called from jitted code (``numba.extending.register_jitable``).
"""

from __future__ import annotations

import contextlib
import os
import threading
import types
from typing import Any

try:  # numba is a dependency; without it the functions stay plain Python
    import numba
    import numba.extending

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised only without numba
    numba = None
    HAVE_NUMBA = False

THREADING_LAYER = "workqueue"
"""numba's threading layer for relacc's ``prange`` kernels (the chain's, the tree stepper's ensembles; the tree's
forward dynamics, kinematics and loads split their batches over Python threads instead: :func:`split`), unless
``NUMBA_THREADING_LAYER`` says otherwise: numba's own pool. It survives ``fork`` (``relacc grade`` runs a user's
function, which may call relacc, in a forked child; GNU OpenMP, numba's first choice where it is installed, ends such
a child: "fork() called from a process already using GNU OpenMP"), and it does not spin while waiting for work, which
costs a loaded machine's other processes."""

if HAVE_NUMBA and "NUMBA_THREADING_LAYER" not in os.environ:
    numba.config.THREADING_LAYER = THREADING_LAYER


def _tolerate_damaged_caches() -> None:
    """numba's cache read as a miss where one of its files is damaged, rather than the call failing.

    numba reads a kernel's cache index and data with ``pickle`` and lets any error through: a truncated or
    overwritten ``.nbi`` or ``.nbc`` file (a full disk, an interrupted copy, two machines sharing a directory) made
    every later call of that kernel an internal error (``UnpicklingError``). Now such a kernel is compiled again, its
    damaged index removed so that the new code is saved in its place, and this is said once per file on stderr, as a
    damaged lanes kernel is (:func:`relacc.kernels.lanes.compile_cached`)."""
    import sys

    from numba.core import caching

    load = caching.Cache._load_overload
    if getattr(load, "relacc_tolerant", False):
        return

    def _load_overload(self, sig, target_context):
        try:
            return load(self, sig, target_context)
        except Exception as exc:  # noqa: BLE001 - whatever an unreadable file raises: pickle, EOF, llvmlite
            index = self._cache_file._index_path
            with contextlib.suppress(OSError):
                os.remove(index)
            if index not in _SAID:
                _SAID.add(index)
                print(f"relacc: the cached kernel {index} is damaged ({type(exc).__name__}: {exc}); compiling it "
                      "again", file=sys.stderr)
            return None

    _load_overload.relacc_tolerant = True  # type: ignore[attr-defined]
    caching.Cache._load_overload = _load_overload


_SAID: set[str] = set()
"""The damaged cache files said in this process (each once)."""

COMPILING: dict = {"depth": 0, "since": 0.0, "spent": 0.0, "clock": None}
"""Numba compiling relacc's kernels in this process: how deep in nested compilations, when the outermost began,
and the seconds spent in those that ended (``clock``: ``time.perf_counter`` unless a test sets one)."""


def compiling_seconds() -> float:
    """Seconds this process has spent with numba compiling relacc's kernels (the current compilation included): a
    progress estimate subtracts them from the time so far, a first run's compiling being no measure of the rest."""
    now = COMPILING["clock"]() - COMPILING["since"] if COMPILING["depth"] else 0.0
    return COMPILING["spent"] + now


def kernel_name(ev) -> str:
    """``module.qualname`` of the function a numba compile event is about."""
    fn = getattr((ev.data or {}).get("dispatcher"), "py_func", None)
    return f"{getattr(fn, '__module__', '') or ''}.{getattr(fn, '__qualname__', '')}"


def _count_compiling() -> None:
    """Keep :data:`COMPILING` from numba's compile events for relacc's kernels (a cached kernel is loaded: no event)."""
    import time

    from numba.core import event

    COMPILING["clock"] = time.perf_counter

    def ours(ev) -> bool:
        return kernel_name(ev).startswith("relacc.")

    class Count(event.Listener):  # registered at this module's import: before any listener that reads COMPILING
        def on_start(self, ev) -> None:
            if ours(ev):
                if COMPILING["depth"] == 0:
                    COMPILING["since"] = COMPILING["clock"]()
                COMPILING["depth"] += 1

        def on_end(self, ev) -> None:
            if ours(ev):
                COMPILING["depth"] -= 1
                if COMPILING["depth"] == 0:
                    COMPILING["spent"] += COMPILING["clock"]() - COMPILING["since"]

    event.register("numba:compile", Count())


LOCK_WAIT_S = 900.0
"""Seconds a process waits for another one compiling the same kernel before it compiles the kernel itself: longer
than the longest first compilation seen (the tree stepper, 444 s at load 12, issue 49), so that only a process that
holds the lock and does not run (stopped with Ctrl-Z) makes the others compile on their own."""


def _compile_once_across_processes() -> None:
    """A kernel numba is about to compile, while another process compiles it into the same cache, is waited for and
    loaded from the cache, not compiled a second time.

    numba's cache is shared by every process of one installation, but each compiles what it lacks on its own: three
    commands started together, or pytest's workers, compiled the same kernels side by side (the tree stepper takes
    27 s on a cold cache, ``benchmarks/results/compile-seconds-*``). Each of relacc's cached kernels now compiles
    under an exclusive ``flock`` on ``<its cache index>.lock`` beside numba's index. Lock order follows the call
    graph (a kernel's callees are compiled inside it), which has no cycles, so two processes cannot wait on each
    other. The lock is taken under numba's own compiler lock, so that threads of one process never wait on a lock
    their process holds. Where the cache directory or ``flock`` is unavailable, a kernel compiles as before. While
    a process waits, numba's compile event is open for the kernel (its data's ``waiting`` set), so the compile
    bar shows it (:func:`relacc.cli.progress.compile_bar`)."""
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX: each process compiles on its own, as numba does
        return
    import time

    from numba.core import caching, dispatcher, event, sigutils
    from numba.core.compiler_lock import global_compiler_lock

    compile_ = dispatcher.Dispatcher.compile
    if getattr(compile_, "relacc_locked", False):
        return

    def compile(self, sig):
        cache = self._cache
        if (isinstance(cache, caching.NullCache)
                or not (getattr(self.py_func, "__module__", "") or "").startswith("relacc.")):
            return compile_(self, sig)
        with global_compiler_lock:
            args, return_type = sigutils.normalize_signature(sig)
            if self.overloads.get(tuple(args)) is not None:
                return compile_(self, sig)
            try:
                fd = os.open(os.path.join(cache._cache_path, cache._cache_file._index_name + ".lock"),
                             os.O_RDWR | os.O_CREAT, 0o666)
            except OSError:
                return compile_(self, sig)
            try:
                if not _try_lock(fcntl, fd):
                    with event.trigger_event("numba:compile", data=dict(dispatcher=self, args=args,
                                                                        return_type=return_type, waiting=True)):
                        until = time.monotonic() + LOCK_WAIT_S
                        while not _try_lock(fcntl, fd) and time.monotonic() < until:
                            time.sleep(0.05)
                return compile_(self, sig)
            finally:
                os.close(fd)  # releases the lock

    compile.relacc_locked = True  # type: ignore[attr-defined]
    dispatcher.Dispatcher.compile = compile  # type: ignore[method-assign]


def _try_lock(fcntl, fd: int) -> bool:
    """Whether the exclusive ``flock`` on ``fd`` was taken without waiting: False while another process holds it; True
    also where the file system has no locks (the kernel then compiles as numba does, without waiting)."""
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return True
    except BlockingIOError:
        return False
    except OSError:
        return True  # no locking here: compile as numba does


if HAVE_NUMBA:
    _tolerate_damaged_caches()
    _count_compiling()
    _compile_once_across_processes()


def read_only(*arrays):
    """Read-only views of ``arrays`` (no copy), for a compiled kernel's inputs: numba compiles a kernel once per
    signature, and a writable and a read-only array are two (a frozen :class:`relacc.core.states.States` hands out
    read-only ones). Every input passed as read-only is one signature, one compilation, one cache file."""
    views = []
    for a in arrays:
        v = a.view()
        v.flags.writeable = False
        views.append(v)
    return views


def jitable(fn=None, *, inline=False):
    """Plain Python when called from Python (the numpy backend); compiled when called from numba code.

    ``inline=True`` inlines the function into its callers at numba's level (``inline='always'``),
    for row helpers called in hot loops, where constants like the case then propagate into the body.
    """
    if fn is None:
        return lambda f: jitable(f, inline=inline)
    if not HAVE_NUMBA:
        return fn
    return numba.extending.register_jitable(inline="always")(fn) if inline else numba.extending.register_jitable(fn)


def leaf(fn):
    """A compiled per-state function that allocates nothing, compiled on its own without numba's reference counting
    (``_nrt=False``) and with multiply-adds fused where the CPU has FMA (``fastmath={'contract'}`` alone: ``a b + c``
    rounded once instead of twice, never less accurate; no reassociation, and NaN and infinities keep their meaning,
    so the kernels' finiteness checks hold); plain Python without numba.

    The fusion made the tree's forward dynamics 5-7% faster (gymnasium's ant and humanoid, docs/benchmarks.md); its
    price is that the leaves' last bits depend on whether the CPU fuses (every modern x86-64 and ARM64 does), which
    the error model's tolerances, bounds on rounding of either kind, do not see.

    A numba function increfs each array it is handed on entry and decrefs it on return (an atomic operation and a call
    each): a kernel's per-state helpers take 20 to 35 arrays (the tree's, the scratch), so a call cost 0.4-0.5 us
    whatever the work, 40% of gymnasium's ant's forward dynamics and 70% of a two-body model's (benchmarks/history.md,
    "What a call costs"). A leaf is handed arrays its caller owns for the whole call, so nothing is lost by not
    counting; it must not allocate (numba refuses to compile it if it does) nor keep an array past its return.
    """
    if not HAVE_NUMBA:
        return fn
    return numba.njit(_nrt=False, cache=True, fastmath={'contract'})(fn)  # type: ignore[call-overload]


def unfused(fn):
    """A :func:`leaf` without fused multiply-adds, and without the GIL: a batch loop whose every operation rounds as
    numpy's does, for the kernels whose numpy backend must give the same bits (the chain's G2 kernels and its
    forward dynamics). Without reference counting, a row's views cost nothing: the acceleration alone took 216 ns a
    state with them, 65 without. Plain Python without numba."""
    if not HAVE_NUMBA:
        return fn
    return numba.njit(_nrt=False, nogil=True, cache=True)(fn)  # type: ignore[call-overload]


def inline_twin(fn):
    """The same code as the (already :func:`jitable`) ``fn``, registered again to be inlined into its callers at
    numba's level: one source, two ways of compiling it."""
    twin = types.FunctionType(fn.__code__, fn.__globals__, fn.__name__ + "_inline", fn.__defaults__, fn.__closure__)
    twin.__doc__, twin.__qualname__ = fn.__doc__, fn.__qualname__ + "_inline"
    return jitable(twin, inline=True)


LAUNCH_US = 400.0
"""Microseconds of work a second thread must take over before one of numba's parallel loops pays, whatever the work:
the loop's start and join (130-230 us with the workqueue pool on this project's 2-core machine: gymnasium's ant's
composite-inertia kernel over 1 state in a parallel loop 139-143 us, called directly 9 us) plus its blocks' own
scratch and the imbalance of a few blocks over the threads. Set from the break-even measured on ant and humanoid for
forward dynamics and kinematics with and without partials, 9 to 8192 states (benchmarks/history.md, "Threads"): at
180 us, 128-256 states still ran 10-20% slower on two threads than on one."""


def parallel_pays(n_states: int, us_per_state: float, block: int) -> bool:
    """Whether a parallel loop over ``n_states`` states in blocks of ``block`` beats running them on the calling
    thread: the work it spreads, ``n us_per_state (1 - 1/t)`` over ``t`` threads (numba's current count, at most one
    per block), must exceed :data:`LAUNCH_US`. A kernel that asks this is never slower on more threads than on one by
    more than the misestimate of its cost per state."""
    if not HAVE_NUMBA or n_states <= block:
        return False
    t = min(numba.get_num_threads(), -(-n_states // block))
    return t > 1 and n_states * us_per_state * (1.0 - 1.0 / t) > LAUNCH_US


def split(fn, args: tuple, n: int, block: int) -> Any:
    """``fn(*args, start, stop)`` over the states ``0 .. n - 1`` on numba's current thread count (at most one per
    ``block``), in equal shares of whole blocks: the calling thread runs the first share, a pool of Python threads
    the others (``fn`` is compiled with ``nogil=True``); returns the shares' results summed (counts, or tuples of
    counts element by element; None for a function that returns nothing).

    relacc's tree kernels (forward dynamics, kinematics, loads) run their batches this way rather than through a
    numba ``prange``: on this project's 2-core VM numba's ``workqueue`` pool ran one call in four to eight 1.4-2x
    slower than the others (its two workers woken for every call while the calling thread waits), where the calling
    thread working beside one pool thread held every call within a few percent (benchmarks/history.md, "Less work a
    state"). A forked child starts without the pool (``os.register_at_fork``) and makes its own when it needs one."""
    t = max(1, min(numba.get_num_threads() if HAVE_NUMBA else 1, -(-n // block)))
    cuts = [min(n, (n * k // t) // block * block) for k in range(t)] + [n]
    pending = [_pool(t - 1).submit(fn, *args, cuts[k], cuts[k + 1]) for k in range(1, t)] if t > 1 else []
    results = [fn(*args, cuts[0], cuts[1])] + [f.result() for f in pending]
    if results[0] is None:
        return None
    if isinstance(results[0], tuple):
        return tuple(sum(r[i] for r in results) for i in range(len(results[0])))
    return sum(results)


def first_touch(*arrays) -> None:
    """Fault in the pages of freshly allocated outputs on the calling thread, before a batch is split over threads:
    one write every 4 KiB (the values are overwritten by the kernel). On this project's 2-vCPU VM two threads faulting
    in the same fresh pages ran slower than one (gymnasium's ant's kinematics with partials, 1024 states, 17 MB of new
    outputs: 7.8 ms on one thread, 9.9 ms on two; with preallocated outputs 5.2 and 3.2 ms); faulting them first
    costs what the one-thread path pays anyway. Never for a caller's own arrays (``out=``: already in memory)."""
    for a in arrays:
        if a is not None and a.size > 512:
            a.reshape(-1)[::512] = 0.0


_POOL: list = []
_POOL_LOCK = threading.Lock()


def _pool(workers: int):
    """The process's pool of at least ``workers`` Python threads (made on first use, grown when asked for more)."""
    from concurrent.futures import ThreadPoolExecutor

    with _POOL_LOCK:
        if not _POOL or _POOL[0][0] < workers:
            _POOL[:] = [(workers, ThreadPoolExecutor(max_workers=workers, thread_name_prefix="relacc"))]
        return _POOL[0][1]


def _forget_pool() -> None:
    """In a forked child: the parent's pool threads do not exist there."""
    global _POOL_LOCK
    _POOL.clear()
    _POOL_LOCK = threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


@contextlib.contextmanager
def threads(n: int):
    """numba's parallel loops on ``min(n, NUMBA_NUM_THREADS)`` threads inside the block (no-op without numba)."""
    if not HAVE_NUMBA:
        yield
        return
    before = numba.get_num_threads()
    numba.set_num_threads(max(1, min(int(n), numba.config.NUMBA_NUM_THREADS)))
    try:
        yield
    finally:
        numba.set_num_threads(before)
