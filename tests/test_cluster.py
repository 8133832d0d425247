"""Sweeps on a real Dask cluster (scheduler and two workers on 127.0.0.1): the local run's answer, also after a
worker dies; bad schedulers and workers are one line and exit 2."""

import http.server
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from relacc.cli import main
from tests.cli import one_line, run_relacc

DASK = shutil.which("dask") or str(Path(sys.executable).parent / "dask")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start(args, env=None):
    return subprocess.Popen([DASK, *args], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            env={**os.environ, **(env or {})}, start_new_session=True)


def stop(proc):
    """Stop a process we started, by its process group (a worker's nanny and its child)."""
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(10)


def wait_for_workers(address, n, timeout=60):
    from distributed import Client

    with Client(address, timeout="20s") as client:
        client.wait_for_workers(n, timeout=timeout)


@pytest.fixture(scope="module")
def cluster():
    """`dask scheduler` and two single-threaded `dask worker`s on 127.0.0.1; stopped by process id at the end."""
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    procs = [start(["scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"])]
    try:
        for _ in range(2):
            procs.append(start(["worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                                "--host", "127.0.0.1"]))
        wait_for_workers(address, 2)
        yield {"address": address, "workers": procs[1:], "procs": procs}
    finally:
        for proc in reversed(procs):
            stop(proc)
    assert all(p.poll() is not None for p in procs)


def run_json(args, capsys):
    code = main(args)
    out = capsys.readouterr().out
    return code, json.loads(out)


CHECK = ["check", "--states", "15000", "--cases", "1", "--engines", "mujoco", "--json", "--quiet"]


@pytest.mark.slow
def test_check_on_the_cluster_is_the_local_run(cluster, capsys, monkeypatch):
    """relacc check --scheduler tcp://... --json equals the in-process run, over three tasks of 5,000 states."""
    from relacc.cluster import sweeps

    monkeypatch.setattr(sweeps, "CHECK_STATES", 5_000)  # three tasks, merged on the workers
    local_code, local = run_json(CHECK, capsys)
    code, remote = run_json(CHECK + ["--scheduler", cluster["address"]], capsys)
    assert (code, remote) == (local_code, local)


@pytest.mark.slow
def test_a_worker_killed_mid_run_changes_nothing(cluster, capsys, monkeypatch):
    """One worker SIGKILLed after the first task finishes: its tasks are retried and the answer is unchanged."""
    import relacc.cluster.client as cluster_module
    from relacc.cluster import sweeps

    monkeypatch.setattr(sweeps, "CHECK_STATES", 5_000)  # eight tasks: the victim is at work on one when killed
    args = ["check", "--states", "40000", "--cases", "2", "--engines", "mujoco", "--json", "--quiet"]
    _, local = run_json(args, capsys)
    victim = cluster["workers"][1]
    original = cluster_module.run

    def run_and_kill(client, function, tasks, merge, progress=None):
        def kill_once(done, total):
            if victim.poll() is None:
                os.killpg(victim.pid, signal.SIGKILL)
                victim.wait(10)
        return original(client, function, tasks, merge, kill_once)

    monkeypatch.setattr(sweeps, "run", run_and_kill)
    try:
        _, remote = run_json(args + ["--scheduler", cluster["address"]], capsys)
    finally:  # the module's later tests get two workers again (with one, they waited on it behind other work)
        replacement = start(["worker", cluster["address"], "--nthreads", "1", "--no-nanny", "--no-dashboard",
                             "--host", "127.0.0.1"])
        cluster["procs"].append(replacement)
        cluster["workers"][1] = replacement
        wait_for_workers(cluster["address"], 2)
    assert victim.poll() is not None, "the worker was not killed"
    assert remote == local


@pytest.mark.slow
def test_ctrl_c_cancels_the_clusters_work(cluster):
    """SIGINT to a running `relacc check --scheduler`: one line, exit 130, and the scheduler holds no task after."""
    from distributed import Client

    relacc = shutil.which("relacc") or str(Path(sys.executable).parent / "relacc")
    proc = subprocess.Popen([relacc, "check", "--states", "2000000", "--cases", "1",
                             "--engines", "mujoco", "--quiet", "--scheduler", cluster["address"]],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    with Client(cluster["address"], timeout="20s") as client:
        def tasks():
            return client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks))

        deadline = time.monotonic() + 60
        while tasks() == 0 and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.2)
        assert tasks() > 0, "the sweep never reached the scheduler"
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
        deadline = time.monotonic() + 30
        while tasks() > 0 and time.monotonic() < deadline:
            time.sleep(0.2)
        left = tasks()
    assert proc.returncode == 130 and err.strip().count("\n") == 0 and "interrupted" in err, err
    assert left == 0


@pytest.mark.slow
def test_compare_of_several_models_on_the_cluster(cluster, capsys, tmp_path):
    """relacc compare A B --scheduler: the same JSON as in-process, one entry per model, a broken one exit 2."""
    from relacc.fixtures.shipped import models_dir

    broken = tmp_path / "broken.xml"
    broken.write_text("<mujoco><worldbody>")
    args = ["compare", str(models_dir() / "two_body.xml"), str(models_dir() / "two_body_euler.xml"), str(broken),
            "--engines", "drake", "--states", "3", "--json"]
    local_code, local = run_json(args, capsys)
    code, remote = run_json(args + ["--scheduler", cluster["address"]], capsys)
    assert code == local_code == 2 and remote == local
    assert [entry["exit"] for entry in remote] == [0, local[1]["exit"], 2]


@pytest.mark.slow
def test_ensemble_on_the_cluster(cluster, capsys):
    """relacc simulate --ensemble on the cluster: the same members, the same largest differences as in-process."""
    args = ["simulate", "tumbling", "--ensemble", "1100", "--duration", "0.02", "--engines", "relacc,mujoco",
            "--json", "--quiet"]
    _, local = run_json(args, capsys)
    _, remote = run_json(args + ["--scheduler", cluster["address"]], capsys)
    assert remote["largest_point_position_difference"] == local["largest_point_position_difference"]
    assert remote["members"] == local["members"] == 1100


@pytest.mark.slow
def test_version_mismatch_is_one_line(cluster, capsys, monkeypatch):
    """Workers at another relacc version than the client's: one line naming both, exit 2."""
    import relacc

    monkeypatch.setattr(relacc, "__version__", "0.0.0-client")
    assert main(["check", "--states", "10", "--scheduler", cluster["address"]]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "0.0.0-client" in err and "same version" in err


@pytest.mark.slow
def test_workers_without_relacc_are_one_line(cluster, capsys, tmp_path):
    """A worker that cannot import relacc (its own Python path shadows it): one line, exit 2, then it is stopped."""
    (tmp_path / "relacc").mkdir()
    (tmp_path / "relacc" / "__init__.py").write_text("raise ImportError('relacc is not installed on this worker')\n")
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    procs = [start(["scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"]),
             None]
    try:
        procs[1] = start(["worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard", "--host", "127.0.0.1"],
                         env={"PYTHONPATH": str(tmp_path)})
        wait_for_workers(address, 1)
        assert main(["check", "--states", "10", "--scheduler", address]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "cannot import relacc" in err
    finally:
        for proc in reversed([p for p in procs if p is not None]):
            stop(proc)


@pytest.mark.parametrize("address,message", [
    ("tcp://127.0.0.1:9", "cannot connect (Connection refused)"),
    ("local:zero", "local:N needs a whole number"),
    ("http://example", "accepted are local"),
])
def test_bad_schedulers_are_one_line_in_bounded_time(address, message, capsys, monkeypatch):
    """An unreachable scheduler or a malformed address: one line, exit 2, within the timeout."""
    import relacc.cluster.client as cluster_module

    monkeypatch.setattr(cluster_module, "TIMEOUT", 3.0)
    started = time.monotonic()
    assert main(["check", "--states", "10", "--scheduler", address]) == 2
    assert time.monotonic() - started < 3.0 + 5.0  # the timeout plus the client's start and shutdown
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err


@pytest.mark.slow
def test_local_cluster_is_started_and_stopped(capsys):
    """--scheduler local:2 starts two worker processes here, gives the in-process answer and stops them."""
    args = ["check", "--states", "500", "--cases", "3", "--engines", "pinocchio", "--json", "--quiet"]
    _, local = run_json(args, capsys)
    _, remote = run_json(args + ["--scheduler", "local:2"], capsys)
    assert remote == local


@pytest.mark.slow
@pytest.mark.parametrize("address", ["tcp://[::1", "tcp://", "tcp://localhost:notaport", "inproc://x",
                                     "local:99999"])
def test_bad_scheduler_addresses_areone_line(tmp_path, address):
    line = one_line(run_relacc("check", "--states", "10", "--scheduler", address, cwd=tmp_path, timeout=60))
    assert "--scheduler" in line


@pytest.mark.slow
def test_something_else_on_the_port_is_one_line_in_time(tmp_path):
    server = http.server.HTTPServer(("127.0.0.1", 0), http.server.BaseHTTPRequestHandler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        start = time.monotonic()
        env = dict(os.environ, RELACC_SCHEDULER_TIMEOUT="3")
        line = one_line(run_relacc("check", "--states", "10", "--scheduler", f"tcp://127.0.0.1:{server.server_port}",
                                 cwd=tmp_path, timeout=60, env=env))
        assert time.monotonic() - start < 30 and "--scheduler" in line
    finally:
        server.shutdown()


@pytest.mark.slow
def test_an_unroutable_scheduler_isone_line(tmp_path):
    env = dict(os.environ, RELACC_SCHEDULER_TIMEOUT="3")
    line = one_line(run_relacc("check", "--states", "10", "--scheduler", "tcp://10.255.255.1:8786", cwd=tmp_path,
                             timeout=60, env=env))
    assert "memory" not in line and "--scheduler" in line


@pytest.mark.slow
def test_sigterm_while_local_workers_start_isone_line(tmp_path):
    proc = subprocess.Popen([sys.executable, "-m", "relacc", "check", "--states", "100000", "--scheduler", "local:4",
                             "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    time.sleep(1.0)  # while the workers start
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Exception ignored" not in err and "Traceback" not in err, err
