"""The second red team's defects, one test each: every one failed before its fix (see git log).

Each asserts what a user should see instead: a right grade, strict JSON, one line and exit 2, a refusal before
the work, a diverged run reported as such, arguments that do nothing refused.
"""

import http.server
import json
import os
import signal
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import relacc
from relacc.core.states import random_states
from relacc.core.stream import iter_g2_kinematics
from relacc.errors import InputError

ROOT = Path(__file__).resolve().parents[1]


def _relacc(*argv, cwd, timeout=300, env=None):
    return subprocess.run([sys.executable, "-m", "relacc", *argv], capture_output=True, text=True, cwd=cwd,
                          timeout=timeout, env=env)


def _one_line(out, code=2):
    assert out.returncode == code, (out.returncode, out.stdout[-500:], out.stderr[-2000:])
    lines = [line for line in out.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in out.stderr, out.stderr
    return lines[0]


def _module(tmp_path, body, name="formula"):
    path = tmp_path / f"{name}.py"
    path.write_text("import numpy as np\n" + body)
    return f"{path}:fn"


# --- lists, siblings of the stream defect -------------------------------------------------------------------

def test_stream_takes_lists(chain):
    s = random_states(1, 5, 0)
    chunks = list(iter_g2_kinematics(chain, 1, s.q.tolist(), s.u.tolist(), s.udot.tolist(), chunk_size=2))
    assert [c.stop for c, _ in chunks] == [2, 4, 5]
    np.testing.assert_array_equal(chunks[-1][1].acceleration,
                                  relacc.g2_kinematics(chain, 1, s.q[4:], s.u[4:], s.udot[4:]).acceleration)


def test_body_partials_and_generalized_forces_take_lists_and_check_shapes(chain):
    from relacc.dynamics import Effects, body_partials, generalized_forces

    s = random_states(2, 3, 1)
    bp = body_partials(chain, 2, s.q.tolist(), s.u.tolist())
    np.testing.assert_array_equal(bp.V2, body_partials(chain, 2, s.q, s.u).V2)
    Q = generalized_forces(chain, 2, s.q.tolist(), s.u.tolist(), Effects(gravity=[0, 0, -9.81]))
    assert Q.shape == (3, 12)
    with pytest.raises(InputError, match=r"expected shape \(\.\.\., 14\)"):
        body_partials(chain, 2, s.q[:, :11], s.u)


def test_truth_assert_agrees_and_random_states_say_what_is_wrong():
    from relacc.testing import assert_agrees, truth

    with pytest.raises(InputError, match="expected the states"):
        truth([np.zeros(14)])
    with pytest.raises(InputError, match="numbers"):
        assert_agrees(["a", "b", "c"], np.zeros(3))
    with pytest.raises(InputError, match="n: expected an integer"):
        random_states(1, 2.0, 0)


# --- grade and the plugin -----------------------------------------------------------------------------------

def test_a_graded_function_gets_copies(tmp_path):
    """A function that zeroes the u and udot it is given and returns zeros is wrong; a right one that scribbles on
    q after using it is right: relacc's truth never reads what the user's function touched."""
    from relacc.testing import check_formula
    from relacc.testing.user import load_function

    liar = load_function(_module(tmp_path, "def fn(chain, q, u, udot):\n    u[...] = 0\n    udot[...] = 0\n"
                                           "    return np.zeros(3)\n", "liar"))
    assert not check_formula(liar, quantity="acceleration", case=1, n=10).ok
    right = load_function(_module(tmp_path, "import relacc\ndef fn(chain, q, u, udot):\n"
                                            "    a = relacc.g2_acceleration(chain, 1, q, u, udot)\n"
                                            "    q[...] = 7.0\n    return a\n", "scribbler"))
    assert check_formula(right, quantity="acceleration", case=1, n=10).ok


@pytest.mark.slow
def test_grade_json_is_strict_with_nan_results(tmp_path):
    out = _relacc("grade", _module(tmp_path, "def fn(chain, q, u, udot):\n    return np.full(3, np.nan)\n"),
                  "--quantity", "velocity", "--case", "1", "--states", "3", "--json", cwd=tmp_path)
    assert out.returncode == 1, out.stderr
    data = json.loads(out.stdout, parse_constant=lambda c: pytest.fail(f"{c} in strict JSON"))
    assert data["worst_error"] is None and data["ok"] is False


@pytest.mark.slow
def test_a_printing_function_does_not_corrupt_json(tmp_path):
    spec = _module(tmp_path, "import relacc\nprint('module says hi')\ndef fn(chain, q, u, udot):\n"
                             "    print('hello from fn')\n    return relacc.g2_kinematics(chain, 1, q, u).velocity\n")
    out = _relacc("grade", spec, "--quantity", "velocity", "--case", "1", "--states", "3", "--json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["ok"] is True
    assert "hello from fn" in out.stderr and "module says hi" in out.stderr


@pytest.mark.slow
@pytest.mark.parametrize("where", ["module", "function"])
def test_a_graded_sys_exit_is_one_line(tmp_path, where):
    body = ("import sys\nsys.exit(3)\ndef fn(chain, q, u, udot):\n    return np.zeros(3)\n" if where == "module" else
            "import sys\ndef fn(chain, q, u, udot):\n    sys.exit(3)\n")
    out = _relacc("grade", _module(tmp_path, body), "--quantity", "velocity", "--case", "1", "--states", "3",
                  cwd=tmp_path)
    assert "exit" in _one_line(out)


def test_a_complex_result_is_not_graded_right(tmp_path):
    from relacc.testing import check_formula
    from relacc.testing.user import CallError, load_function

    fn = load_function(_module(tmp_path, "import relacc\ndef fn(chain, q, u, udot):\n"
                                         "    return relacc.g2_kinematics(chain, 1, q, u).velocity + 1e-3j\n"))
    with warnings.catch_warnings():  # as a user runs it: numpy's ComplexWarning is only a warning there
        warnings.simplefilter("ignore", np.exceptions.ComplexWarning)
        with pytest.raises(CallError, match="complex"):
            check_formula(fn, quantity="velocity", case=1, n=3)


def test_relacc_states_checks_its_arguments_and_hands_out_read_only_states(relacc_states):
    with pytest.raises(InputError, match="n: expected an integer"):
        relacc_states(n=3.9)
    with pytest.raises(InputError, match="seed: expected an integer"):
        relacc_states(seed=True)
    with pytest.raises(InputError, match="unknown case"):
        relacc_states(case=1.7)
    with pytest.raises(InputError, match="hard: expected True or False"):
        relacc_states(hard="no")
    s = relacc_states(case=1, n=3)
    with pytest.raises(ValueError, match="read-only"):
        s.q[:, 0] += 100
    first = s.q.copy()
    s.q.setflags(write=True)  # a test may make its copy writable: no other test sees the change
    s.q[:, 0] += 100
    again = relacc_states(case=1, n=3)
    assert again is not s and not again.q.flags.writeable
    np.testing.assert_array_equal(again.q, first)


def test_relacc_states_of_a_model_follow_the_file(tmp_path, relacc_states):
    """States are keyed by the model's content, not its path: after the file changes (a hinge becomes a ball), the
    same call gives the new model's states."""
    path = tmp_path / "m.xml"
    body = '<mujoco><worldbody><body name="b"><joint name="j" type="{}"/><geom type="sphere" size="0.1" mass="1"/>' \
        '</body></worldbody></mujoco>'
    path.write_text(body.format("hinge"))
    assert relacc_states(case=2, n=4, model=path).q.shape == (4, 1)
    path.write_text(body.format("ball"))
    assert relacc_states(case=2, n=4, model=path).q.shape == (4, 4)


# --- memory refused up front --------------------------------------------------------------------------------

@pytest.mark.slow
def test_huge_requests_are_refused_before_any_work(tmp_path, relacc_states):
    for argv in (["compare", str(ROOT / "models" / "two_body.xml"), "--states", "1000000000"],
                 ["grade", "examples/student_correct.py:velocity", "--quantity", "velocity", "--case", "1",
                  "--states", "1000000000"]):
        start = time.monotonic()
        line = _one_line(_relacc(*argv, cwd=ROOT if argv[0] == "grade" else tmp_path, timeout=60))
        assert "memory" in line and time.monotonic() - start < 30, (argv, line)
    with pytest.raises(InputError, match="memory"):
        relacc_states(n=10**12)


# --- simulation ---------------------------------------------------------------------------------------------

UNSTABLE = """title = "A stiff spring MuJoCo's Euler cannot hold"
[model]
fixture = "two_body"
[initial]
case = 2
q = [0.0, 0.0, 0.0,  1.0, 0.0, 0.0, 0.0,  0.1, 0.0, 0.0,  1.0, 0.0, 0.0, 0.0]
u = [0.0, 0.0, 0.0,  0.0, 0.0, 0.0,  0.0, 0.0, 0.0,  0.0, 0.0, 0.0]
[effects.spring]
stiffness = 1e9
[simulate]
duration = 5.0
dt = 0.01
integrator = "euler"
engines = ["mujoco"]
"""


@pytest.mark.slow
def test_an_unstable_engine_run_is_a_diverged_run(tmp_path):
    scene = tmp_path / "unstable.toml"
    scene.write_text(UNSTABLE)
    work = tmp_path / "work"
    work.mkdir()
    line = _one_line(_relacc("simulate", str(scene), cwd=work))
    assert "mujoco" in line and "diverged" in line
    assert list(work.iterdir()) == []


@pytest.mark.slow
def test_sigterm_during_simulate_removes_the_new_directory(tmp_path):
    out_dir = tmp_path / "new"
    proc = subprocess.Popen([sys.executable, "-m", "relacc", "simulate", "gimbal_spin", "--duration", "20",
                             "--out", str(out_dir)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=tmp_path)
    for _ in range(600):
        time.sleep(0.1)
        if out_dir.exists():
            break
    time.sleep(1.0)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert not out_dir.exists()
    last = [line for line in err.splitlines() if line.strip()][-1]
    assert last.startswith("relacc simulate: interrupted"), repr(last)


# --- --out means the same everywhere ------------------------------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("argv", [["compare", "MODEL", "--out", ""], ["simulate", "tumbling", "--out", ""],
                                  ["fixtures", "--out", ""], ["report", "--out", ""]])
def test_an_empty_out_is_refused(tmp_path, argv):
    argv = [str(ROOT / "models" / "two_body.xml") if a == "MODEL" else a for a in argv]
    assert "--out" in _one_line(_relacc(*argv, cwd=tmp_path))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_compare_out_creates_its_parents(tmp_path):
    page = tmp_path / "missing" / "dir" / "page.html"
    out = _relacc("compare", str(ROOT / "models" / "two_body.xml"), "--states", "2", "--engines", "drake",
                  "--out", str(page), cwd=tmp_path)
    assert out.returncode in (0, 1), out.stderr
    assert page.is_file() and "relacc compare" in out.stdout


@pytest.mark.slow
def test_fixtures_refuses_an_empty_name(tmp_path):
    assert "--name" in _one_line(_relacc("fixtures", "--out", str(tmp_path / "x"), "--name", "", cwd=tmp_path))
    assert not (tmp_path / "x").exists()


# --- cluster addresses --------------------------------------------------------------------------------------

@pytest.mark.slow
@pytest.mark.parametrize("address", ["tcp://[::1", "tcp://", "tcp://localhost:notaport", "inproc://x",
                                     "local:99999"])
def test_bad_scheduler_addresses_are_one_line(tmp_path, address):
    line = _one_line(_relacc("check", "--states", "10", "--scheduler", address, cwd=tmp_path, timeout=60))
    assert "--scheduler" in line


@pytest.mark.slow
def test_something_else_on_the_port_is_one_line_in_time(tmp_path):
    server = http.server.HTTPServer(("127.0.0.1", 0), http.server.BaseHTTPRequestHandler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        start = time.monotonic()
        env = dict(os.environ, RELACC_SCHEDULER_TIMEOUT="3")
        line = _one_line(_relacc("check", "--states", "10", "--scheduler", f"tcp://127.0.0.1:{server.server_port}",
                                 cwd=tmp_path, timeout=60, env=env))
        assert time.monotonic() - start < 30 and "--scheduler" in line
    finally:
        server.shutdown()


@pytest.mark.slow
def test_an_unroutable_scheduler_is_one_line(tmp_path):
    env = dict(os.environ, RELACC_SCHEDULER_TIMEOUT="3")
    line = _one_line(_relacc("check", "--states", "10", "--scheduler", "tcp://10.255.255.1:8786", cwd=tmp_path,
                             timeout=60, env=env))
    assert "memory" not in line and "--scheduler" in line


@pytest.mark.slow
def test_sigterm_while_local_workers_start_is_one_line(tmp_path):
    proc = subprocess.Popen([sys.executable, "-m", "relacc", "check", "--states", "100000", "--scheduler", "local:4",
                             "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    time.sleep(1.0)  # while the workers start
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Exception ignored" not in err and "Traceback" not in err, err


# --- flags and inputs that would do nothing -----------------------------------------------------------------

@pytest.mark.parametrize("argv, match", [
    (["simulate", "tumbling", "--spread", "0.1"], "--spread"),
    (["simulate", "tumbling", "--seed", "3"], "--seed"),
    (["simulate", "tumbling", "--scheduler", "local:1"], "--scheduler"),
    (["eval", "--case", "1", "--q", "0,,0,1,0,0,0,0,0,0,1,0,0,0", "--u", "0,0,0,0,0,0,0,0,0,0,0,0"], "--q"),
    (["check", "--engines", "pinocchio,pinocchio", "--states", "5"], "--engines"),
])
@pytest.mark.slow
def test_arguments_that_would_do_nothing_are_refused(tmp_path, argv, match):
    assert match in _one_line(_relacc(*argv, cwd=tmp_path))


@pytest.mark.slow
def test_unknown_keys_in_an_eval_state_are_refused(tmp_path):
    state = tmp_path / "state.json"
    state.write_text(json.dumps({"case": 1, "q": [0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0], "u": [0] * 12,
                                 "udott": [0] * 12}))
    assert "udott" in _one_line(_relacc("eval", str(state), cwd=tmp_path))
