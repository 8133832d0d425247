"""Sweeps on a Dask cluster: ``--scheduler local[:N]`` or ``--scheduler tcp://host:port``.

The local, in-process run stays the default; this layer only distributes work the other layers
define chunk by chunk (every chunk's states come from its own seed, never from a shared stream), so
the same seed gives the same answer, the same maxima, worst states and verdicts, whatever runs it:

* :func:`connect` opens a client: a ``LocalCluster`` of N single-threaded worker processes started
  and stopped here, or an existing cluster by address; within a bounded time, the workers must
  import relacc at the client's version, else one :class:`ClusterError` line;
* :class:`RelaccPlugin`, registered on every worker, loads relacc's kernels once per worker and keeps
  what tasks load (engines, harnesses) in a per-worker cache, so nothing heavy is pickled per task;
* :func:`run` submits coarse tasks, drives the progress callback from their completion, reduces
  their small answers on the workers (a tree of merges), retries the tasks of a worker that dies,
  and cancels everything on Ctrl-C.

Users: :mod:`relacc.cluster.sweeps` (``check``, ``compare`` over many models, ensembles).

Layer rule: imports Dask and the layers below the report (core, kernels, dynamics, fixtures, reading,
:mod:`relacc.engines`, simulate, validation), never the report or the CLI, and never an engine's
own package: engines are reached through their adapters, on the workers.
"""

from relacc.cluster.client import (
    FAN_IN,
    RETRIES,
    TIMEOUT,
    ClusterError,
    connect,
    max_local_workers,
    parse_address,
    probe,
    quiet,
    run,
)

__all__ = ["FAN_IN", "RETRIES", "TIMEOUT", "ClusterError", "connect", "max_local_workers", "parse_address", "probe",
           "quiet", "run"]
