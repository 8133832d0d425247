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


ALWAYS_FITS = 2**20
"""Requests of at most this many bytes (1 MiB: a few thousand states of a small tree) are not checked: reading the
memory available (``/proc/meminfo``) costs about 10 us, more than a single state's forward dynamics."""

CONVERT_BYTES = 64 * 2**20
"""About the most memory :func:`relacc.core.tree.coordinates.convert` gives the walk at once (a chunk of states at a
time)."""

STATE_COPIES = 3
"""A batch of random tree states is held about this many times over while it is drawn and converted: the case-2
draw, the converted case's copy and the temporaries of the conversion, which walks a chunk of states at a time
(measured: ``random_states`` of gymnasium's humanoid, 1e6 states, peaks at 1.1, 2.5 and 2.65 times its final arrays
in cases 2, 1 and 3)."""

GRADE_DOUBLES = 16
"""Doubles per evaluated state per body and speed that grading a model's body holds at once (relacc's and an engine's
kinematics of every body: positions, Jacobians, their rates, scales and bounds). Measured with ``relacc grade
--model``: gymnasium's ant (13 bodies, 14 speeds) 201 bytes, humanoid (13, 23) 190 bytes per requested state per
body and speed, over two evaluated states each (ordinary and hard): 12-13 doubles per evaluated state."""


COMPARE_DOUBLES = 10
"""Doubles per state evaluated at once, per link and per entry of a link's Jacobian (3 x speeds), that comparing a
model's dynamics holds (relacc's and an engine's Jacobians, their rates, the gravity terms' Jacobians, the scales):
measured with ``compare`` on a 301-body, 306-speed tree, tracemalloc's peak 7.2-8.7 per state over 1 to 20 states."""

CHUNK_STATES = 64
"""States the dynamics comparison evaluates in one batched call of each evaluator
(:data:`relacc.validation.robots.agreement.CHUNK`)."""


def compare_bytes(tree, n_states: int) -> float:
    """Bytes comparing ``tree``'s dynamics at ``n_states`` random states and the reference configuration holds at once
    (:data:`COMPARE_DOUBLES` per state of a chunk, link and Jacobian entry)."""
    at_once = min(int(n_states) + 1, CHUNK_STATES)
    return 8.0 * COMPARE_DOUBLES * at_once * tree.nb * 3 * tree.nv


def require_comparable(tree, n_states: int, what: str) -> None:
    """Refuse up front a dynamics comparison that cannot fit (:func:`compare_bytes`), saying why in the model's terms.

    Raises:
        InputError: the estimate, what is available, and what to do instead.
    """
    at_once = min(int(n_states) + 1, CHUNK_STATES)
    instead = ("compare fewer states (--states)" if at_once > 1 else
               "even one state is too much: the comparison holds every link's Jacobian (bodies x 3 x speeds) in each "
               "engine; compare a smaller model, or parts of this one")
    require_memory(compare_bytes(tree, n_states), f"{what} {tree.name!r} ({tree.nb} bodies, {tree.nv} speeds) at "
                   f"{at_once} state{'s' if at_once > 1 else ''} at once", instead)


def tree_states_bytes(tree, n: float, case: int = 3) -> float:
    """Bytes to draw ``n`` states of ``tree`` in ``case`` (coordinates, speeds, rates; :data:`STATE_COPIES`), and in
    cases 1 and 3 the conversion's walk over a chunk of them
    (:data:`CONVERT_BYTES`)."""
    arrays = 8.0 * float(n) * (max(tree.nq_in(2), tree.nq_in(3)) + 2 * tree.nv) * STATE_COPIES
    return arrays + (CONVERT_BYTES if int(case) != 2 else 0.0)


def require_memory(nbytes: float, what: str, instead: str) -> None:
    """Refuse up front a request whose arrays need more than the memory available.

    Raises:
        InputError: naming the request, its estimate, what is available and what to do ``instead``.
    """
    if nbytes <= ALWAYS_FITS:
        return
    free = available_memory()
    if free is not None and nbytes > free:
        raise InputError(f"{what} needs about {nbytes / 2**30:.3g} GiB of memory, more than the "
                         f"{free / 2**30:.3g} GiB available; {instead}")
