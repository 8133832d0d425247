"""What a request costs in memory, checked before the work starts.

relacc streams what can be streamed (``relacc check`` and the errata chunk by
chunk, simulations block by block, :func:`relacc.core.stream.iter_g2_kinematics`);
what must be held at once (a batch's outputs, a simulation's kept records)
is estimated first and refused, with the estimate, when it cannot fit in
the memory available now.
"""

from __future__ import annotations

import os

from relacc.errors import InputError


def available_memory() -> int | None:
    """Bytes of memory available now (Linux ``MemAvailable``), or None when it cannot be read."""
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, AttributeError):
        return None


def require_memory(nbytes: float, what: str, instead: str) -> None:
    """Refuse up front a request whose arrays need more than the memory available.

    Raises:
        InputError: naming the request, its estimate, what is available and what to do ``instead``.
    """
    free = available_memory()
    if free is not None and nbytes > free:
        raise InputError(f"{what} needs about {nbytes / 2**30:.3g} GiB of memory, more than the "
                         f"{free / 2**30:.3g} GiB available; {instead}")
