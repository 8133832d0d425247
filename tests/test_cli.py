"""The relacc command line: outputs name their frames, errors are one line, exit codes mean something."""

import json
import re
import subprocess
import sys

import numpy as np
import pytest

import relacc
from relacc.cli import main
from relacc.engines import CHAIN_ENGINES as ENGINES
from tests.cli import one_line, run_relacc

SPIN = ["--case", "1", "--q", "0,0,0, 1,0,0,0, 0,0,0, 1,0,0,0", "--u", "0,0,0, 0,0,2.5, 0,0,0, 0,0,0",
        "--udot", "0,0,0,0,0,0,0,0,0,0,0,0"]


@pytest.mark.slow
def test_version_via_python_m():
    """`python -m relacc --version` prints the package version."""
    out = subprocess.run([sys.executable, "-m", "relacc", "--version"], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.strip() == f"relacc {relacc.__version__}"


def test_eval_text_names_point_and_frames(capsys, fixture):
    """eval prints each vector with its point, frame and kind (classical)."""
    assert main(["eval", *SPIN, "--model", str(fixture.source)]) == 0
    out = capsys.readouterr().out
    assert "fixed-frame components" in out and "classical" in out and "case 1" in out


def test_eval_json_equals_library(capsys, fixture, chain):
    """eval --json returns what relacc.g2_kinematics returns for the same state."""
    assert main(["eval", *SPIN, "--json", "--model", str(fixture.source)]) == 0
    out = json.loads(capsys.readouterr().out)
    u = np.zeros(12)
    u[5] = 2.5
    q = np.r_[0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0.0]
    k = relacc.g2_kinematics(fixture.chain, 1, q, u, np.zeros(12))
    assert out["velocity"] == k.velocity.tolist() and out["acceleration"] == k.acceleration.tolist()
    assert out["V"] == k.V.tolist() and "fixed-frame" in out["conventions"]["velocity"]


def test_eval_reads_a_json_state_file(tmp_path, capsys, fixture):
    """eval STATE.json takes case, q, u, udot from a file."""
    path = tmp_path / "state.json"
    path.write_text(json.dumps({"case": 3, "q": [0.0] * 12, "u": [0.0] * 12}))
    assert main(["eval", str(path), "--json", "--model", str(fixture.source)]) == 0
    assert json.loads(capsys.readouterr().out)["acceleration"] is None


@pytest.mark.parametrize(
    "argv,match",
    [
        (["eval", "--case", "1", "--q", "0,0,0,0.7,0,0,0.7,0,0,0,1,0,0,0", "--u", ",".join("0" * 12)],
         "does not normalize"),
        (["eval", "--case", "1", "--q", "0,0,0,1,0,0,0,0,0,0,1,0,0,0", "--u", "0"], r"shape \(\.\.\., 12\)"),
        (["eval", "--case", "5", "--q", "0", "--u", "0"], "accepted cases"),
        (["eval", "--case", "1", "--q", "a,b", "--u", "0"], "expected numbers"),
        (["eval", "--case", "1", "--u", "0"], "missing q"),
        (["eval", "nonexistent.json"], "no such file"),
        (["check", "--engines", "bullet", "--states", "5"], "unknown engines"),
        (["check", "--states", "0"], "at least 1"),
        (["fixtures", "--model", "nope.toml"], "no such file"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(capsys, argv, match):
    """Every bad input prints exactly one line on stderr, no traceback, and exits 2."""
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert re.search(match, err), err


def test_check_json_passes_and_names_conventions(capsys, fixture):
    """check --json exits 0 and every comparison carries its convention."""
    assert main(["check", "--states", "50", "--quiet", "--json", "--model", str(fixture.source)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["passed"] and len(out["comparisons"]) == 20 * len(ENGINES)  # per engine: 4 routes x 5 quantities
    assert all("fixed-frame" in c["convention"] for c in out["comparisons"])


def test_check_text_table(capsys, fixture):
    """check prints a table with pass per row and a final verdict."""
    assert main(["check", "--states", "20", "--cases", "2", "--engines", "mujoco", "--quiet",
                 "--model", str(fixture.source)]) == 0
    out = capsys.readouterr().out
    assert "all 5 comparisons agree" in out and "classical" in out


def test_errata_json_lists_every_id(capsys, fixture):
    """errata --json is a list with exactly the five documented keys per id."""
    assert main(["errata", "--states", "50", "--quiet", "--json", "--model", str(fixture.source)]) == 0
    items = json.loads(capsys.readouterr().out)
    assert [i["id"] for i in items] == [e.id for e in relacc.EQUATIONS]
    assert all(set(i) == {"id", "status", "printed_error", "corrected_error", "explanation"} for i in items)


def test_fixtures_check_is_up_to_date(capsys, fixture):
    """fixtures --check exits 0 on the checked-in files."""
    assert main(["fixtures", "--check", "--model", str(fixture.source)]) == 0


@pytest.mark.parametrize("argv, match", [
    (["simulate", "tumbling", "--spread", "0.1"], "--spread"),
    (["simulate", "tumbling", "--seed", "3"], "--seed"),
    (["simulate", "tumbling", "--scheduler", "local:1"], "--scheduler"),
    (["eval", "--case", "1", "--q", "0,,0,1,0,0,0,0,0,0,1,0,0,0", "--u", "0,0,0,0,0,0,0,0,0,0,0,0"], "--q"),
    (["check", "--engines", "pinocchio,pinocchio", "--states", "5"], "--engines"),
])
@pytest.mark.slow
def test_arguments_that_would_do_nothing_are_refused(tmp_path, argv, match):
    assert match in one_line(run_relacc(*argv, cwd=tmp_path))


@pytest.mark.slow
def test_unknown_keys_in_an_eval_state_are_refused(tmp_path):
    state = tmp_path / "state.json"
    state.write_text(json.dumps({"case": 1, "q": [0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0], "u": [0] * 12,
                                 "udott": [0] * 12}))
    assert "udott" in one_line(run_relacc("eval", str(state), cwd=tmp_path))


def test_the_first_compilation_of_kernels_is_a_bar_with_an_estimate(capsys, monkeypatch):
    """Issues 49 and 52: the first simulate --model after install compiled for 444 s with no word. While numba compiles
    relacc's kernels (its compile events), stderr shows a bar for the outermost compilation under way: its seconds so
    far and an estimate, the recorded seconds of the kernels still expected under it scaled by this run's pace; when it
    ends, "compiled in N s" on its own line. Numba compiling anything else, a quiet command, or a compilation under a
    second says nothing. Here with a clock the test moves and a record of g's compilation: h 10 s, g itself 30 s. h
    takes 20 s (twice the record), so g's 30 s are estimated at 60 s; g then takes 30 s: 50 s in all."""
    from types import SimpleNamespace

    from numba.core import event

    from relacc.cli import progress
    from relacc.kernels import jit

    now = [0.0]

    def compiled(module, name, seconds, inner=(), waiting=False):
        fn = SimpleNamespace(py_func=SimpleNamespace(__module__=module, __qualname__=name))
        event.start_event("numba:compile", data={"dispatcher": fn, "waiting": waiting})
        for args in inner:
            compiled(*args)
        now[0] += seconds
        event.end_event("numba:compile", data={"dispatcher": fn, "waiting": waiting})

    def lines(err):  # each line as it is left on a terminal (splitlines would split at the carriage returns too)
        return [line.split("\r")[-1].rstrip() for line in err.split("\n") if line]

    before = {k: list(v) for k, v in event._registered.items()}
    state, counted = dict(progress.NOTICE), dict(jit.COMPILING)
    progress.NOTICE.update(listening=False)
    event._registered["numba:compile"] = [x for x in event._registered["numba:compile"]  # a bar an earlier main()
                                          if type(x).__module__ != progress.__name__]   # in this process listens
    jit.COMPILING.update(clock=lambda: now[0], spent=0.0)
    was_open, progress.OPEN[0] = progress.OPEN[0], False  # no bar left open by an earlier test in this process
    monkeypatch.setattr(progress, "recorded_compile_seconds",
                        lambda root: {"relacc.k.h": 10.0, "relacc.k.g": 30.0} if root == "relacc.k.g" else {})
    try:
        progress.compile_notice(quiet=True)
        compiled("relacc.k", "g", 50.0, inner=[("relacc.k", "h", 20.0)])
        assert capsys.readouterr().err == ""
        progress.compile_notice(quiet=False)
        compiled("numba.cpython.builtins", "impl", 5.0)
        compiled("relacc.k", "short", 0.4, inner=[("relacc.k", "h", 0.2)])
        assert capsys.readouterr().err == ""
        compiled("relacc.k", "g", 30.0, inner=[("relacc.k", "h", 16.0, [("numba.np.arrayobj", "impl", 4.0)])])
        err = capsys.readouterr().err
        live = f"{progress.COMPILE_LABEL} [#####               ] 20 s, about 60 s left"  # 30 s at pace 20 / 10
        assert err.split("\r")[1].rstrip() == live, err
        assert lines(err) == [f"{progress.COMPILE_LABEL}: compiled in 50 s"], err
        compiled("relacc.k", "x", 3.0, inner=[("relacc.k", "y", 1.0)])  # not in the record: seconds and kernels
        err = capsys.readouterr().err
        assert err.split("\r")[1].rstrip() == f"{progress.COMPILE_LABEL}: 1 s, 1 kernels so far", err
        assert lines(err) == [f"{progress.COMPILE_LABEL}: compiled in 4 s"], err
        # another process compiles g (kernels/jit's lock): said when the wait begins, whatever it lasts
        compiled("relacc.k", "g", 25.0, waiting=True)  # as jit's lock opens it: the wait alone, then a cache load
        err = capsys.readouterr().err
        assert err.split("\r")[1].rstrip() == (f"{progress.COMPILE_LABEL}: waiting for another relacc process "
                                               "compiling g (it is cached for both)"), err
        assert lines(err) == [f"{progress.COMPILE_LABEL}: ready in 25 s"], err
    finally:
        event._registered.clear()
        event._registered.update(before)
        progress.NOTICE.clear()
        progress.NOTICE.update(state)
        jit.COMPILING.update(counted)
        progress.OPEN[0] = was_open


def test_the_recorded_first_compilations_name_kernels_that_exist():
    """The compile bar's record (written by the benchmark first_compile.py) names each outermost kernel and each kernel
    compiled under it by module and qualified name: a renamed kernel would leave the bar without its estimate. The
    first simulate --model's outermost kernel, the trees' stepper, is among them."""
    import importlib
    import json

    from relacc.cli.progress import COMPILE_RECORD
    from relacc.fixtures.shipped import latest_recorded

    roots = json.loads(latest_recorded(COMPILE_RECORD).read_text())["roots"]
    assert roots["relacc.kernels.tree_step.record"], "the stepper's compilation is recorded"
    for root, under in roots.items():
        for name in (root, *under):  # module.function
            module, function = name.rsplit(".", 1)
            assert callable(getattr(importlib.import_module(module), function, None)), name
