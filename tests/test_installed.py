"""relacc from a wheel, in a fresh virtual environment, run from an empty directory, behaves as from the checkout."""

import json
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

from tests.cli import borrowed_site_dirs

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """A wheel built from this tree, installed (without dependencies) in a new venv that borrows them.

    The new environment finds numpy, the engines and the rest through a ``.pth`` naming this
    environment's site directories (those on ``sys.path`` under ``sys.prefix``: site-packages and
    the ones its own ``.pth`` files add); relacc itself comes only from the wheel (the checkout's
    editable hook is not active there: ``.pth`` files are not read from a directory a ``.pth`` adds).
    """
    root = tmp_path_factory.mktemp("wheel")
    subprocess.run([sys.executable, "-m", "pip", "wheel", str(REPO), "--no-deps", "-q", "-w", str(root / "dist")],
                   check=True, capture_output=True, timeout=300)
    (wheel,) = (root / "dist").glob("relacc-*.whl")
    venv = root / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True, timeout=120)
    python = venv / "bin" / "python"
    purelib = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                             capture_output=True, text=True, check=True).stdout.strip()
    borrowed = borrowed_site_dirs()
    assert sysconfig.get_paths()["purelib"] in borrowed
    (Path(purelib) / "borrowed_dependencies.pth").write_text("\n".join(borrowed) + "\n")
    subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "--no-deps", "-q", str(wheel)],
                   check=True, capture_output=True, timeout=300)
    empty = root / "empty"
    empty.mkdir()
    return {"wheel": wheel, "bin": venv / "bin", "python": python, "cwd": empty}


@pytest.mark.slow
def test_wheel_carries_the_shipped_models_and_scenes(installed):
    """The wheel holds the chain's TOML, its engine files, every scene, the templates and the recorded runs."""
    names = set(zipfile.ZipFile(installed["wheel"]).namelist())
    shipped = {f"relacc/models/{p.relative_to(REPO / 'models')}" for p in (REPO / "models").rglob("*")
               if p.is_file() and p.suffix in (".toml", ".xml", ".urdf")}
    assert shipped and shipped <= names
    assert {"relacc/fixtures/templates/two_body.xml.j2", "relacc/report/templates/report.html.j2"} <= names
    assert any(n.startswith("relacc/recorded/throughput-") for n in names)
    assert any(n.startswith("relacc/recorded/compile-seconds-") for n in names)  # the compile bar's estimate


@pytest.mark.slow
def test_installed_relacc_comes_from_the_wheel(installed):
    """In the new environment relacc and its models are imported from that environment, not the checkout."""
    out = subprocess.run([str(installed["python"]), "-c", "import relacc\nfrom relacc.fixtures import shipped\n"
                          "print(relacc.__file__)\nprint(shipped.default_model_path())"],
                         capture_output=True, text=True, cwd=installed["cwd"], check=True)
    module, model = out.stdout.split()
    venv = str(installed["bin"].parent)
    assert module.startswith(venv) and model.startswith(venv), out.stdout


@pytest.mark.slow
def test_check_simulate_and_report_run_from_an_empty_directory(installed):
    """`relacc check`, `relacc simulate tumbling` and `relacc report --quick --out X` work from an empty directory.

    The three run at once, as three users of one installation would: they compile the kernels into the
    installed package's cache side by side (and the run takes the longest command's time, not the sum).
    """
    commands = {"check": ["check", "--states", "20", "--quiet", "--json"],
                "simulate": ["simulate", "tumbling", "--duration", "0.05", "--quiet", "--json"],
                "report": ["report", "--quick", "--quiet", "--out", "X.html"]}
    procs = {name: subprocess.Popen([str(installed["bin"] / "relacc"), *argv], stdout=subprocess.PIPE,
                                    stderr=subprocess.PIPE, text=True, cwd=installed["cwd"])
             for name, argv in commands.items()}
    done = {name: (proc, *proc.communicate(timeout=600)) for name, proc in procs.items()}
    for name, (proc, _, err) in done.items():
        assert proc.returncode == 0, f"{name}: {err}"
    assert json.loads(done["check"][1])["passed"]
    assert json.loads(done["simulate"][1])["max_point_position_difference"] < 1e-9
    html = (installed["cwd"] / "X.html").read_text()
    assert "relacc agreement report" in html and 'id="recorded-runs"' in html
    assert sorted(p.name for p in installed["cwd"].iterdir()) == ["X.html"]  # nothing else left behind


@pytest.mark.slow
def test_a_models_folder_in_the_working_directory_changes_nothing(installed):
    """A `models/` folder in the working directory is not picked up: the shipped model is used."""
    decoy = installed["cwd"] / "decoy"
    (decoy / "models").mkdir(parents=True)
    (decoy / "models" / "two_body.toml").write_text('name = "decoy"\n')
    out = subprocess.run([str(installed["bin"] / "relacc"), "eval", "--case", "1", "--q",
                          "0,0,0,1,0,0,0,0,0,0,1,0,0,0", "--u", "0,0,0,0,0,1,0,0,0,0,0,0", "--json"],
                         capture_output=True, text=True, cwd=decoy, timeout=120)
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["model"].startswith(str(installed["bin"].parent))
