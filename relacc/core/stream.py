"""Evaluate any number of states in chunks, with bounded memory.

``iter_g2_kinematics`` reads ``chunk_size`` states at a time from arrays or
``numpy.memmap`` files of any length and yields each chunk's results, so the
memory in use is set by the chunk size, not by N:

* full outputs: about ``chunk_size x 1.0 kB`` (inputs 38 doubles, outputs
  81 doubles per state), 64 MB at the default 65,536;
* acceleration only: about ``chunk_size x 0.33 kB``, 21 MB at the default.

``tests/test_fast.py`` measures the peak with ``tracemalloc``.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from relacc.core.cases import as_case, check_int
from relacc.core.kinematics import G2Kinematics, check_values, g2_acceleration, g2_kinematics
from relacc.errors import InputError, RelaccError

CHUNK_SIZE = 65_536
"""Default number of states per chunk."""


def iter_g2_kinematics(chain, case, q, u, udot=None, *, chunk_size: int = CHUNK_SIZE,
                       acceleration_only: bool = False, variant="corrected",
                       backend="auto", reuse: bool = False) -> Iterator[tuple[slice, object]]:
    """Yield ``(states, result)`` for consecutive chunks of a long batch.

    Args:
        chain, case, variant, backend: as :func:`relacc.g2_kinematics`.
        q: ``(N, 14)`` or ``(N, 12)``; u, udot: ``(N, 12)``: arrays or memmaps
            with one leading batch axis of equal length N.
        chunk_size: states per chunk (>= 1).
        acceleration_only: yield the ``(n, 3)`` acceleration of
            :func:`relacc.g2_acceleration` instead of a :class:`relacc.G2Kinematics`
            (needs ``udot``).
        reuse: write every chunk's results into the same buffers (``out=``): no new
            output memory after the first chunk, so none to touch for the first
            time; each yielded result is then overwritten by the next chunk's
            (copy what you keep). The last chunk, shorter, gets views of them.

    Yields:
        ``states``: the slice of the batch a chunk covers; ``result``: its
        :class:`relacc.G2Kinematics`, or its ``(n, 3)`` acceleration (fixed
        components, m/s^2).

    Raises:
        InputError: mismatched lengths or a bad chunk size; any input error of
            a chunk, with the chunk's state range named.
    """
    as_case(case)
    chunk_size = check_int("chunk_size", chunk_size, minimum=1)
    # lists and tuples (as everywhere arrays are accepted); arrays and memmaps stay as they are, read chunk by chunk
    q, u, udot = (np.asarray(a) if isinstance(a, (list, tuple)) else a for a in (q, u, udot))
    arrays = [a for a in (q, u, udot) if a is not None]
    if any(np.ndim(a) != 2 for a in arrays):
        raise InputError("q, u and udot must each have one batch axis: shapes (N, nq) and (N, 12)")
    n = q.shape[0]
    if any(a.shape[0] != n for a in arrays):
        raise InputError(f"q, u and udot must have the same number of states, got {[a.shape[0] for a in arrays]}")
    if acceleration_only and udot is None:
        raise InputError("acceleration_only needs udot")
    buffers = None
    if reuse:
        m = min(chunk_size, n)
        buffers = (np.empty((m, 3)),) if acceleration_only else (
            np.empty((m, 3)), np.empty((m, 3)), None if udot is None else np.empty((m, 3)), np.empty((m, 3, 12)),
            np.empty((m, 3, 12)))
    for start in range(0, n, chunk_size):
        states = slice(start, min(start + chunk_size, n))
        qc, uc = np.asarray(q[states]), np.asarray(u[states])
        dc = None if udot is None else np.asarray(udot[states])
        k = states.stop - states.start
        out = None if buffers is None else tuple(None if b is None else b[:k] for b in buffers)
        try:
            result: np.ndarray | G2Kinematics
            if acceleration_only and dc is not None:  # checked above: acceleration_only needs udot
                result = g2_acceleration(chain, case, qc, uc, dc, backend=backend, out=None if out is None else out[0])
            else:
                result = g2_kinematics(chain, case, qc, uc, dc, variant=variant, backend=backend, out=out)
        except RelaccError:
            try:  # name the bad state by its index in the whole batch, not in the chunk
                check_values(case, qc, uc, dc, offset=states.start)
            except RelaccError as named:
                exc = named
            raise type(exc)(f"states {states.start}..{states.stop - 1}: {exc}") from None
        yield states, result
