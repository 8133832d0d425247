"""Connecting to a Dask scheduler and running tasks on it (the package's docstring states the rule)."""

from __future__ import annotations

import contextlib
import logging
import os
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from relacc.errors import RelaccError

TIMEOUT = float(os.environ.get("RELACC_SCHEDULER_TIMEOUT", "15"))
"""Seconds to reach a scheduler and see its first worker, before one line and exit 2 (environment variable
``RELACC_SCHEDULER_TIMEOUT``)."""

RETRIES = 3
"""Times a task is resubmitted after its worker died (Dask reschedules it; the answer is unchanged)."""

FAN_IN = 16
"""Partial answers merged per reduction task on the workers."""


class ClusterError(RelaccError):
    """A scheduler that cannot be reached, workers without relacc or at another version, a malformed address."""


def max_local_workers() -> int:
    """The most worker processes ``local:N`` starts: four per core (more only slows this machine down)."""
    return 4 * (os.cpu_count() or 1)


def parse_address(address: str) -> tuple[str, int | None]:
    """``("local", N or None)`` or ``("tcp", None)``; raises :class:`ClusterError` naming what is accepted.

    ``local:N``: 1 <= N <= :func:`max_local_workers`. ``tcp://host:port`` or ``tls://host:port``: a host (a name,
    an IPv4 address or a bracketed IPv6 one) and a port from 1 to 65535.
    """
    from urllib.parse import urlsplit

    text = str(address).strip()
    accepted = ("accepted are local, local:N (N worker processes here) and tcp://host:port (a running "
                "`dask scheduler`)")
    if text == "local" or text.startswith("local:"):
        n = text.partition(":")[2]
        if n and not (n.isdigit() and 1 <= int(n) <= max_local_workers()):
            raise ClusterError(f"--scheduler {text!r}: local:N needs a whole number of workers from 1 to "
                               f"{max_local_workers()} (four per core here)")
        return "local", int(n) if n else None
    if text.startswith(("tcp://", "tls://")):
        try:
            parts = urlsplit(text)
            port = parts.port
        except ValueError as exc:
            raise ClusterError(f"--scheduler {text!r}: not a host and port ({exc}); {accepted}") from None
        if not parts.hostname or port is None or not 1 <= port <= 65535 or parts.path not in ("", "/"):
            raise ClusterError(f"--scheduler {text!r}: give a host and a port, tcp://host:port; {accepted}")
        return "tcp", None
    if text.startswith(("inproc://", "ucx://")):
        raise ClusterError(f"--scheduler {text!r}: relacc reaches a scheduler over tcp:// (or tls://); {accepted}")
    raise ClusterError(f"--scheduler {text!r}: {accepted}")


def probe(address: str, timeout: float) -> None:
    """Check that a Dask scheduler answers at a ``tcp://`` address before Dask's client tries it.

    A scheduler speaks first on a new connection: its handshake, an 8-byte frame length (a few hundred bytes)
    and the frames. Something else on the port (an HTTP server waits for a request; another service sends other
    bytes) would make the client wait past any timeout or read its bytes as a huge length. Raises
    :class:`ClusterError` within ``timeout`` seconds naming what happened.
    """
    import socket
    import struct
    from urllib.parse import urlsplit

    parts = urlsplit(address)
    try:
        with socket.create_connection((parts.hostname, parts.port), timeout=timeout) as sock:
            head = b""
            while len(head) < 8:
                chunk = sock.recv(8 - len(head))
                if not chunk:
                    break
                head += chunk
    except socket.timeout:
        raise ClusterError(f"--scheduler {address}: nothing answered as a Dask scheduler does within {timeout:g} s "
                           "(no connection, or something else listens there)") from None
    except OSError as exc:
        raise ClusterError(f"--scheduler {address}: cannot connect ({exc.strerror or exc})") from None
    size = struct.unpack("<Q", head)[0] if len(head) == 8 else 0
    if not 0 < size < 2**24:
        raise ClusterError(f"--scheduler {address}: what listens there is not a Dask scheduler (it answered "
                           f"{head!r:.40})")


def _worker_versions():  # runs on every worker
    import relacc

    return relacc.__version__


@contextlib.contextmanager
def connect(address: str, timeout: float | None = None) -> Iterator[Any]:
    """A ``distributed.Client`` for ``address`` with :class:`RelaccPlugin` registered, closed at the end.

    ``timeout`` in seconds; None reads :data:`TIMEOUT` at the call.

    Raises:
        ClusterError: a malformed address, no scheduler or no worker within ``timeout`` seconds,
            workers that cannot import relacc or run another version of it.
    """
    kind, n = parse_address(address)
    timeout = TIMEOUT if timeout is None else timeout
    from distributed import Client, LocalCluster

    import relacc

    quiet(logging.ERROR)
    with contextlib.ExitStack() as stack:
        if kind == "local":
            cluster = stack.enter_context(LocalCluster(n_workers=n or os.cpu_count() or 1, threads_per_worker=1,
                                                       processes=True, dashboard_address=":0",
                                                       silence_logs=logging.CRITICAL))
            target = cluster
        else:
            if address.startswith("tcp://"):
                probe(address, timeout)
            target = address
        try:
            client = stack.enter_context(Client(target, timeout=f"{timeout}s"))
            client.wait_for_workers(1, timeout=timeout)
        except MemoryError:  # Dask read something that is not its protocol as a frame length
            raise ClusterError(f"--scheduler {address}: what answers there does not speak Dask's protocol") from None
        except (OSError, TimeoutError) as exc:
            raise ClusterError(f"--scheduler {address}: no scheduler with a worker answered within {timeout:g} s "
                               f"({type(exc).__name__}: {' '.join(str(exc).split()) or 'timed out'})") from None
        try:
            versions = client.run(_worker_versions)
        except Exception as exc:  # a worker without relacc raises ModuleNotFoundError there
            raise ClusterError(f"--scheduler {address}: a worker cannot import relacc "
                               f"({type(exc).__name__}: {exc}); install relacc {relacc.__version__} on every "
                               "worker") from None
        other = {w: v for w, v in versions.items() if v != relacc.__version__}
        if other:
            raise ClusterError(f"--scheduler {address}: workers run relacc {sorted(set(other.values()))}, this "
                               f"client {relacc.__version__}; install the same version everywhere")
        from relacc.cluster.plugin import RelaccPlugin

        client.register_plugin(RelaccPlugin(), name=RelaccPlugin.name)
        try:
            yield client
        except BaseException:
            quiet(logging.CRITICAL)  # closing after Ctrl-C or an error: relacc says what happened, in one line
            raise


def quiet(level: int) -> None:
    """Dask's loggers (``distributed`` and its children, which Dask gives levels of their own) at ``level``."""
    for name in ["distributed", *[n for n in logging.root.manager.loggerDict if n.startswith("distributed.")]]:
        logging.getLogger(name).setLevel(level)


def run(client: Any, function: Callable, tasks: Sequence, merge: Callable,
        progress: Callable[[int, int], object] | None = None) -> Any:
    """``merge``-reduced results of ``function(*task)`` for every task, computed on the cluster.

    Args:
        tasks: argument tuples, one per task (coarse: each does seconds of work).
        merge: ``merge(a, b)`` of two answers, associative; answers are merged in task order, so the
            result does not depend on which worker finishes first.
        progress: called with ``(done, total)`` as tasks finish.
    """
    from distributed import as_completed

    futures = [client.submit(function, *task, pure=False, retries=RETRIES) for task in tasks]
    try:
        if progress is not None:
            for done, _ in enumerate(as_completed(futures), start=1):
                progress(done, len(futures))
        level = futures
        while len(level) > 1:  # a tree of merges on the workers, in task order
            level = [client.submit(_merge_all, merge, *level[i:i + FAN_IN], pure=False, retries=RETRIES)
                     for i in range(0, len(level), FAN_IN)]
        return level[0].result()
    except BaseException:
        quiet(logging.CRITICAL)  # the client's own complaints while it is torn down are not the user's news
        client.cancel(futures)
        raise


def _merge_all(merge, *answers):
    out = answers[0]
    for answer in answers[1:]:
        out = merge(out, answer)
    return out


__all__ = ["FAN_IN", "RETRIES", "TIMEOUT", "ClusterError", "connect", "max_local_workers", "parse_address", "probe",
           "quiet", "run"]
