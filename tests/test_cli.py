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
    relacc's kernels (its compile events), stderr shows a bar with the seconds so far and an estimate: the recorded
    seconds of the kernels still expected, scaled by this run's pace. Numba compiling anything else, or a quiet
    command, says nothing. Here with a clock the test moves and a record of two kernels, 10 s and 30 s: f takes 20 s
    (twice the record), so g's 30 s are estimated at 60 s; g then takes 30 s, and the whole is said to take 50.4 s,
    the time outside compilation (70 s) not counted. An outermost compilation shorter than a second shows no bar."""
    from types import SimpleNamespace

    from numba.core import event

    from relacc.cli import progress
    from relacc.kernels import jit

    now = [0.0]

    def compiled(module, name, seconds, inner=()):
        fn = SimpleNamespace(py_func=SimpleNamespace(__module__=module, __qualname__=name))
        event.start_event("numba:compile", data={"dispatcher": fn})
        for args in inner:
            compiled(*args)
        now[0] += seconds
        event.end_event("numba:compile", data={"dispatcher": fn})

    def last_line(err):
        return err.split("\r")[-1].rstrip("\n").rstrip()

    before = {k: list(v) for k, v in event._registered.items()}
    state, counted = dict(progress.NOTICE), dict(jit.COMPILING)
    progress.NOTICE.update(listening=False)
    jit.COMPILING.update(clock=lambda: now[0], spent=0.0)
    monkeypatch.setattr(progress, "recorded_compile_seconds",
                        lambda key: {"relacc.k.f": 10.0, "relacc.k.g": 30.0} if key == "simulate --model" else {})
    try:
        progress.compile_notice(quiet=True, key="simulate --model")
        compiled("relacc.k", "f", 20.0)
        assert capsys.readouterr().err == ""
        progress.compile_notice(quiet=False, key="simulate --model")
        compiled("numba.cpython.builtins", "impl", 5.0)
        assert capsys.readouterr().err == ""
        compiled("relacc.k", "f", 16.0, inner=[("numba.np.arrayobj", "impl", 4.0)])
        err = capsys.readouterr().err
        assert err.endswith("\n") and err.count("\n") == 1, err
        assert last_line(err) == f"{progress.COMPILE_LABEL} [#####               ] 20 s so far, about 60 s more"
        now[0] += 70.0  # the command runs
        compiled("relacc.k", "short", 0.4)  # an outermost compilation under SHOWN_AFTER: no bar
        assert capsys.readouterr().err == ""
        compiled("relacc.k", "g", 28.0, inner=[("relacc.k", "h", 2.0)])  # h is not in the record
        err = capsys.readouterr().err
        live = f"{progress.COMPILE_LABEL} [#####               ] 22 s, about 67 s left"  # 30 s at pace 22.4 / 10
        assert err.split("\r")[1].rstrip() == live, err
        assert last_line(err) == f"{progress.COMPILE_LABEL}: compiled in 50 s"  # 20 + 0.4 + 30 s
        progress.compile_notice(quiet=False, key="check")  # a command without a record: seconds and kernels
        compiled("relacc.k", "h", 3.0, inner=[("relacc.k", "i", 1.0)])
        assert last_line(capsys.readouterr().err) == f"{progress.COMPILE_LABEL}: 4 s, 2 kernels so far"
    finally:
        event._registered.clear()
        event._registered.update(before)
        progress.NOTICE.clear()
        progress.NOTICE.update(state)
        jit.COMPILING.update(counted)


def test_the_recorded_first_compilations_name_kernels_and_commands_that_exist():
    """The compile bar's record (written by the benchmark first_compile.py) names each kernel by module and qualified
    name and each command as the command line keys it: a renamed kernel or command would leave the bar without its
    estimate."""
    import argparse
    import importlib

    from relacc.cli.parser import build_parser
    from relacc.cli.progress import COMPILE_RECORD, compile_key
    from relacc.fixtures.shipped import latest_recorded

    (sub,) = [a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)]
    keys = {compile_key(name, model) for name in sub.choices for model in (None, "m.xml")}
    record = json.loads(latest_recorded(COMPILE_RECORD).read_text())
    assert set(record["commands"]) <= keys
    assert record["commands"]["simulate --model"]["kernels"], "the first simulate --model compiles kernels"
    for command in record["commands"].values():
        for name in command["kernels"]:  # module.function
            module, function = name.rsplit(".", 1)
            assert callable(getattr(importlib.import_module(module), function, None)), name
