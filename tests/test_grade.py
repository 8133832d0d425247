"""``relacc grade``: the truth is computed before, and apart from, anything a user's function touches; whatever the
function does to the objects it gets, to the process or to stdout, the verdict is relacc's and one line says what
went wrong."""

import json
import subprocess
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np
import pytest

from relacc.cli import main
from relacc.testing import check_formula
from relacc.testing.user import CallError, load_function
from tests.cli import formula_module, one_line, run_relacc

ROOT = Path(__file__).resolve().parents[1]
ARM = ROOT / "examples" / "three_link_arm.xml"


def _module(tmp_path, body: str, name: str = "student") -> str:
    path = tmp_path / f"{name}.py"
    path.write_text("import numpy as np\nimport relacc\n" + textwrap.dedent(body))
    return f"{path}:fn"


def test_a_function_that_edits_the_chain_cannot_make_its_own_truth(tmp_path):
    """The formula leaves out r2' (wrong) and then sets the chain's r2' to zero, read-only flag flipped, so that a
    truth computed afterwards on the same chain would agree with it: graded wrong, at the size of the r2' terms."""
    fn = load_function(_module(tmp_path, """
        def fn(chain, q, u, udot):
            chain.r2.flags.writeable = True
            chain.r2[:] = 0.0
            return relacc.g2_kinematics(chain, 1, q, u, udot).acceleration
    """))
    grade = check_formula(fn, quantity="acceleration", case=1, n=10)
    assert not grade.ok and grade.worst_error > 1e-3, grade.text()


def test_a_function_that_edits_the_tree_cannot_make_its_own_truth(tmp_path):
    fn = load_function(_module(tmp_path, """
        def fn(tree, q, u, udot):
            b = tree.body("forearm")
            tree.bodies[b].com.flags.writeable = True
            tree.bodies[b].com[:] = 0.0
            return relacc.tree_kinematics(tree, 2, q, u, udot).V[b]
    """))
    grade = check_formula(fn, quantity="V", case=2, n=10, model=str(ARM), body="forearm")
    assert not grade.ok and grade.worst_error > 1e-3, grade.text()


@pytest.mark.parametrize("body,said", [
    ("raise GeneratorExit('bye')", "GeneratorExit"),
    ("raise KeyboardInterrupt('from the function')", "KeyboardInterrupt"),
    ("import os; os._exit(3)", "exit status 3"),
    ("import os, signal; os.kill(os.getpid(), signal.SIGKILL)", "SIGKILL"),
])
def test_whatever_the_function_does_to_the_process_is_one_line(tmp_path, capsys, body, said):
    """Exit 2 and one line naming what the function did; a KeyboardInterrupt the function raises is its error, not
    an interrupt of relacc (exit 130 is for signals relacc receives)."""
    spec = _module(tmp_path, f"def fn(chain, q, u, udot):\n    {body}\n")
    assert main(["grade", spec, "--quantity", "velocity", "--case", "1", "--states", "2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and said in err[0] and "fn" in err[0], err


@pytest.mark.slow
def test_writing_to_file_descriptor_1_does_not_corrupt_json(tmp_path):
    """``os.write(1, ...)`` in the module and in the function goes to stderr: stdout is relacc's JSON alone."""
    spec = _module(tmp_path, """
        import os
        os.write(1, b"module writes to fd 1\\n")
        def fn(chain, q, u, udot):
            os.write(1, b"fn writes to fd 1\\n")
            return relacc.g2_kinematics(chain, 1, q, u).velocity
    """)
    out = subprocess.run([sys.executable, "-m", "relacc", "grade", spec, "--quantity", "velocity", "--case", "1",
                          "--states", "2", "--json"], capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["ok"] is True
    assert "fn writes to fd 1" in out.stderr and "module writes to fd 1" in out.stderr


def test_a_tree_grade_names_the_tree_in_its_call(tmp_path):
    fn = load_function(_module(tmp_path, "def fn(tree, q, u, udot):\n    raise ValueError('nope')\n"))
    with pytest.raises(CallError, match=r"called as fn\(tree, q, u, udot\)"):
        check_formula(fn, quantity="V", case=2, n=2, model=str(ARM), body="forearm")


def test_the_chain_and_states_the_user_gets_are_copies_each_call(tmp_path):
    """A function that zeroes the state it is given on its first call still gets the right state on the next."""
    fn = load_function(_module(tmp_path, """
        def fn(chain, q, u, udot):
            v = relacc.g2_kinematics(chain, 1, q, u).velocity
            q[...] = 0.0
            u[...] = 0.0
            chain.q2.flags.writeable = True
            chain.q2[:] = 9.0
            return v
    """))
    grade = check_formula(fn, quantity="velocity", case=1, n=5)
    assert grade.ok, grade.text()


def test_a_graded_function_gets_copies(tmp_path):
    """A function that zeroes the u and udot it is given and returns zeros is wrong; a right one that scribbles on
    q after using it is right: relacc's truth never reads what the user's function touched."""
    from relacc.testing import check_formula
    from relacc.testing.user import load_function

    liar = load_function(formula_module(tmp_path, "def fn(chain, q, u, udot):\n    u[...] = 0\n    udot[...] = 0\n"
                                           "    return np.zeros(3)\n", "liar"))
    assert not check_formula(liar, quantity="acceleration", case=1, n=10).ok
    right = load_function(formula_module(tmp_path, "import relacc\ndef fn(chain, q, u, udot):\n"
                                            "    a = relacc.g2_acceleration(chain, 1, q, u, udot)\n"
                                            "    q[...] = 7.0\n    return a\n", "scribbler"))
    assert check_formula(right, quantity="acceleration", case=1, n=10).ok


@pytest.mark.slow
def test_grade_json_is_strict_with_nan_results(tmp_path):
    out = run_relacc("grade", formula_module(tmp_path, "def fn(chain, q, u, udot):\n    return np.full(3, np.nan)\n"),
                  "--quantity", "velocity", "--case", "1", "--states", "3", "--json", cwd=tmp_path)
    assert out.returncode == 1, out.stderr
    data = json.loads(out.stdout, parse_constant=lambda c: pytest.fail(f"{c} in strict JSON"))
    assert data["worst_error"] is None and data["ok"] is False


@pytest.mark.slow
def test_a_printing_function_does_not_corrupt_json(tmp_path):
    spec = formula_module(tmp_path, "import relacc\nprint('module says hi')\ndef fn(chain, q, u, udot):\n"
                             "    print('hello from fn')\n    return relacc.g2_kinematics(chain, 1, q, u).velocity\n")
    out = run_relacc("grade", spec, "--quantity", "velocity", "--case", "1", "--states", "3", "--json", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["ok"] is True
    assert "hello from fn" in out.stderr and "module says hi" in out.stderr


@pytest.mark.slow
@pytest.mark.parametrize("where", ["module", "function"])
def test_a_graded_sys_exit_isone_line(tmp_path, where):
    body = ("import sys\nsys.exit(3)\ndef fn(chain, q, u, udot):\n    return np.zeros(3)\n" if where == "module" else
            "import sys\ndef fn(chain, q, u, udot):\n    sys.exit(3)\n")
    out = run_relacc("grade", formula_module(tmp_path, body), "--quantity", "velocity", "--case", "1", "--states", "3",
                  cwd=tmp_path)
    assert "exit" in one_line(out)


def test_a_complex_result_is_not_graded_right(tmp_path):
    from relacc.testing import check_formula
    from relacc.testing.user import CallError, load_function

    fn = load_function(formula_module(tmp_path, "import relacc\ndef fn(chain, q, u, udot):\n"
                                         "    return relacc.g2_kinematics(chain, 1, q, u).velocity + 1e-3j\n"))
    with warnings.catch_warnings():  # as a user runs it: numpy's ComplexWarning is only a warning there
        warnings.simplefilter("ignore", np.exceptions.ComplexWarning)
        with pytest.raises(CallError, match="complex"):
            check_formula(fn, quantity="velocity", case=1, n=3)


WRONG_VELOCITY = """
def fn(chain, q, u, udot):
    return relacc.g2_kinematics(chain, 1, q, u).velocity * 1.5
"""


def test_the_graded_modules_top_level_cannot_reach_the_grader(tmp_path, capsys):
    """Issue 50 item 1: module-level code that replaces the grader's error measure with zeros (in relacc's own
    process, it turned a WRONG 0.351 into right) runs only in the child that imports the module: still WRONG,
    exit 1, at the size of the wrong factor (0.5 of the velocity's terms)."""
    spec = _module(tmp_path, textwrap.dedent("""
        import relacc.testing.grade, relacc.testing.grading
        relacc.testing.grading.worst_against.__globals__["normalized_error"] = (
            lambda mine, values, scale: np.zeros(len(values)))
    """) + WRONG_VELOCITY)
    assert main(["grade", spec, "--quantity", "velocity", "--case", "1", "--states", "5"]) == 1
    out = capsys.readouterr().out
    assert "WRONG" in out, out
    import relacc.testing.grading
    assert relacc.testing.grading.worst_against.__globals__["normalized_error"].__module__ == "relacc.core.tolerances"


def test_what_the_child_sends_back_cannot_run_code_here(tmp_path):
    """Issue 50 item 1: a batch call returning an object array whose element unpickles by running code (here: writing
    a file) is refused as plain data; the parent never runs it, and the function is graded one state at a time."""
    marker = tmp_path / "ran-in-the-parent"
    spec = _module(tmp_path, f"""
        import os
        class Trap:
            def __reduce__(self):
                return (os.mkdir, ({str(marker)!r},))
        def fn(chain, q, u, udot):
            v = relacc.g2_kinematics(chain, 1, q, u).velocity * 1.5
            if np.ndim(q) == 2:
                out = np.empty(len(q), dtype=object)
                out[:] = [Trap() for _ in range(len(q))]
                return out
            return v
    """)
    grade = check_formula(load_function(spec), quantity="velocity", case=1, n=4)
    assert not grade.ok and grade.called == "one state at a time", grade.text()
    np.testing.assert_allclose(grade.worst_error, 0.5, rtol=0, atol=0.5)  # 1.5x: an error of the velocity's size
    assert not marker.exists()


def test_a_forged_stream_from_the_child_is_refused(tmp_path):
    """The child's own relacc is the user's to change: a function that rewrites the child's encoder to send a pickle
    gets one line, never an unpickling here."""
    from relacc import isolate

    marker = tmp_path / "unpickled-here"

    def step():
        import os
        import pickle

        class Trap:
            def __reduce__(self):
                return (os.mkdir, (str(marker),))
        os.write(1, b"")  # nothing on stdout
        return {"ok": True}, [pickle.dumps(Trap())]  # bytes, not an array: refused in the child

    got = isolate.run_plain(step, timeout=30)
    assert isinstance(got, isolate.Raised) or isinstance(got, tuple), got
    assert not marker.exists()
    # a stream that is not the plain format at all
    header, arrays = isolate._unplain(isolate._plain({"a": 1}, [np.arange(3.0)]))
    assert header == {"a": 1} and arrays[0].tolist() == [0.0, 1.0, 2.0]
    with pytest.raises(ValueError):
        isolate._unplain(isolate._plain({"a": 1}, [np.arange(3.0)])[:-3] + b"\x80\x04N.")


@pytest.mark.slow
def test_a_function_that_never_returns_is_stopped(tmp_path):
    """Issue 50 item 1: ``while True: pass`` hung grade; the child has --timeout seconds: one line, exit 2."""
    spec = formula_module(tmp_path, "def fn(chain, q, u, udot):\n    while True:\n        pass\n")
    out = run_relacc("grade", spec, "--quantity", "velocity", "--case", "1", "--states", "2", "--timeout", "2",
                     cwd=tmp_path, timeout=120)
    line = one_line(out)
    assert "did not finish in 2 s" in line and "fn" in line, line


@pytest.mark.slow
def test_a_graded_module_beside_a_file_named_like_an_engine_is_one_line(tmp_path):
    """Issue 50 item 9: a graded module importing its sibling ``mujoco.py`` gave a 53-line ImportError traceback
    (relacc, started by ``python -m`` in that directory, then imported the sibling as the engine). relacc's engines
    are its own in any working directory, and the module is imported in the child only, where the engine relacc
    already loaded is the ``mujoco`` it gets: the function's failure is one line, exit 2."""
    (tmp_path / "mujoco.py").write_text("HELPER = 2.0\n")
    spec = formula_module(tmp_path, "import relacc\nimport mujoco\ndef fn(chain, q, u, udot):\n"
                                    "    return relacc.g2_kinematics(chain, 1, q, u).velocity * mujoco.HELPER / 2\n")
    line = one_line(run_relacc("grade", spec, "--quantity", "velocity", "--case", "1", "--states", "3",
                               cwd=tmp_path))
    assert "fn raised AttributeError" in line and "HELPER" in line, line


def test_grade_refuses_when_its_own_references_disagree(tmp_path, monkeypatch):
    """Issue 50 item 4: when relacc's reading and an engine's disagree (there, a DTD entity only relacc's reader
    applied), a student whose answer equals one of them was graded WRONG against the other. grade now checks its
    references against each other first and refuses in one line, naming both and the state. Planted here: MuJoCo's
    truth of the arm's forearm moved by 1 mm."""
    from relacc.errors import ModelError
    from relacc.testing import trees

    real = trees.model_truth

    def moved(s, engine="relacc", quantities=trees.TREE_QUANTITIES):
        out = real(s, engine, quantities)
        if engine == "mujoco":
            for e in out.values():
                e.values[...] += 1e-3
        return out

    monkeypatch.setattr("relacc.testing.grade.model_truth", moved)
    spec = _module(tmp_path, "def fn(tree, q, u, udot):\n"
                             "    return relacc.tree_kinematics(tree, 2, q, u).position[2]\n")
    with pytest.raises(ModelError, match=r"grade's references disagree on the position of body 'forearm'.*relacc and "
                                         r"mujoco at state \d+, .* times their tolerance apart"):
        check_formula(load_function(spec), quantity="position", case=2, n=3, model=str(ARM), body="forearm")
