"""The HTML agreement report: content, self-containment, atomic writes, and a real browser."""

import json
import re
import shutil
from pathlib import Path

import pytest

from relacc.cli import main
from relacc.report import build as report_mod
from relacc.report.sections import SECTIONS

REPO = Path(__file__).resolve().parents[1]
CHROMIUM_FLAGS = [
    "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
    "--disable-component-update", "--disable-sync",
]


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory, fixture):
    """`relacc report --quick` run as a user runs it, from an empty working directory, which it leaves empty
    (the report's case of tests/test_hygiene.py::test_every_command_leaves_the_working_directory_empty)."""
    import subprocess
    import sys

    out = tmp_path_factory.mktemp("report") / "agreement.html"
    work = tmp_path_factory.mktemp("work")
    run = subprocess.run([sys.executable, "-m", "relacc", "report", "--quick", "--quiet", "--out", str(out),
                          "--model", str(fixture.source)], capture_output=True, text=True, cwd=work, timeout=900)
    assert run.returncode == 0, run.stderr[-2000:]
    assert list(work.iterdir()) == []
    return out


@pytest.mark.slow
def test_report_has_verdict_and_every_section(quick_report):
    """The page carries the verdict, the versions, the seed and one <section> per section module."""
    html = quick_report.read_text()
    assert 'id="verdict"' in html and "agree with Pinocchio, MuJoCo and Drake" in html  # the report shows three engines
    for name in ("pinocchio", "mujoco", "drake", "numpy", "python", "relacc"):
        assert name in html
    for module in SECTIONS:
        assert f'<section id="{module.ID}"' in html
    assert "seed 0" in html


@pytest.mark.slow
def test_report_is_self_contained(quick_report):
    """No src/href points outside the file: only data: URIs and in-page anchors."""
    html = quick_report.read_text()
    refs = re.findall(r'(?:src|href)="([^"]*)"', html)
    assert refs, "no pictures or links found"
    assert all(r.startswith(("data:", "#")) for r in refs), [r for r in refs if not r.startswith(("data:", "#"))]
    assert "<script" not in html and "@import" not in html and "url(http" not in html


@pytest.mark.slow
def test_report_shows_every_erratum(quick_report):
    """Every equation id has a row with a status badge."""
    html = quick_report.read_text()
    from relacc.core.note.equations import IDS

    for i in IDS:
        assert f'id="eq-{i}"' in html


def test_failed_run_leaves_no_file(tmp_path, monkeypatch, fixture):
    """If rendering fails, neither the report nor a temporary file is left behind."""
    def boom(ctx):
        raise RuntimeError("render failed")

    monkeypatch.setattr(report_mod, "build_context", lambda **kwargs: {})  # the run itself is not under test here
    monkeypatch.setattr(report_mod, "render", boom)
    out = tmp_path / "agreement.html"
    with pytest.raises(RuntimeError):
        report_mod.build_report(out=out, quick=True, n_states=5, model=fixture.source)
    assert list(tmp_path.iterdir()) == []


def test_out_is_a_directory_is_one_line_error(tmp_path, capsys):
    """--out pointing at a directory is a one-line error with exit 2."""
    assert main(["report", "--quick", "--quiet", "--out", str(tmp_path)]) == 2
    assert "is a directory" in capsys.readouterr().err


def test_processes_is_an_option_of_the_chains_report(tmp_path, capsys):
    """``--processes`` takes 1 or 2, and only for the chain's report: a model file's report runs in one process, and
    says so rather than ignore it (one line, exit 2)."""
    out = str(tmp_path / "r.html")
    assert main(["report", "--model", str(REPO / "models" / "two_body.xml"), "--processes", "2", "--out", out]) == 2
    err = capsys.readouterr().err
    assert "--processes applies to the chain's report" in err and len(err.strip().splitlines()) == 1
    assert main(["report", "--processes", "3", "--out", out]) == 2
    assert "--processes: must be at most 2, got 3" in capsys.readouterr().err
    assert not (tmp_path / "r.html").exists()


@pytest.mark.slow
def test_report_in_headless_chromium(quick_report):
    """Chromium loads the page with no console error, no network request and no table wider than the page."""
    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium")
    assert chromium, "Debian's chromium is required for this test (apt-get install chromium; .ci/run does it)"
    console_errors, requests = [], []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=CHROMIUM_FLAGS)
        page = browser.new_page(viewport={"width": 1366, "height": 900})
        page.on("console", lambda m: console_errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: console_errors.append(str(e)))
        page.on("request", lambda r: requests.append(r.url))
        page.goto(quick_report.as_uri(), wait_until="load")
        assert page.locator("#verdict").is_visible()
        assert "agree" in page.inner_text("#verdict")
        for module in SECTIONS:
            assert page.locator(f"section#{module.ID} h2").is_visible()
        wide = page.evaluate("[...document.querySelectorAll('table')].filter("
                             "t => t.getBoundingClientRect().right > document.body.getBoundingClientRect().right + 1)"
                             ".map(t => t.id || t.parentElement.id)")
        overflow = page.evaluate("document.documentElement.scrollWidth - document.documentElement.clientWidth")
        broken = page.evaluate("[...document.images].filter(i => !i.complete || i.naturalWidth === 0).length")
        n_images = page.evaluate("document.images.length")
        shot = quick_report.parent / "report-quick.png"  # beside the page, never into the repository
        page.screenshot(path=str(shot), full_page=True)
        browser.close()
    assert wide == [] and overflow <= 0, f"tables wider than the page: {wide}; page overflow {overflow} px"
    assert console_errors == []
    outside = [u for u in requests if not u.startswith(("file://", "data:"))]
    assert outside == [], f"network requests: {outside}"
    assert n_images > 30 and broken == 0
    assert shot.stat().st_size > 10_000  # a page, not a blank


@pytest.mark.slow
def test_report_shows_the_recorded_benchmark_runs(quick_report):
    """Every recorded run in benchmarks/results has a row in the throughput section's table."""
    html = quick_report.read_text()
    runs = sorted((REPO / "benchmarks" / "results").glob("throughput-*.json"))
    assert runs, "no recorded runs in benchmarks/results"
    assert 'id="recorded-runs"' in html
    for path in runs:
        assert f"<td>{path.name}</td>" in html
    # issue 49 item 10: the latest run shown, the history behind a disclosure; no raw Python data on the page
    latest = html[html.index('id="recorded-runs"'):]
    assert f"<td>{runs[-1].name}</td>" in latest[:latest.index("</table>")]
    assert (len(runs) == 1) == ('id="recorded-runs-earlier"' not in html)
    assert "{&#39;" not in html and "[&#39;" not in html, "a Python dict or list printed raw"


def test_recorded_runs_ratios_are_time_ratios(tmp_path):
    """recorded_runs divides the engine's time by relacc's (median and minimum) and reads the one-thread row."""
    from relacc.tradeoff.throughput import recorded_runs

    def row(who, median, best):
        return {"case": 2, "who": who, "output": "acceleration", "seconds": median, "seconds_min": best,
                "relacc_speedup_over_this": median / {"relacc": 0.004}.get(who, 0.004),
                "relacc_speedup_over_this_best": best / 0.003}

    data = {"machine": {"date": "2026-11-22", "cpu": "x", "logical_cpus": 2}, "n_states": 10,
            "rows": [row("relacc", 0.004, 0.003), row("relacc-1-thread", 0.008, 0.007), row("pinocchio", 0.2, 0.15),
                     row("mujoco", 0.3, 0.25)]}
    for name in ("throughput-2026-11-22-run10.json", "throughput-2026-11-22-run9.json", "throughput-x.json"):
        (tmp_path / name).write_text(json.dumps(data))
    runs = recorded_runs(tmp_path)  # oldest first, run numbers as numbers; a file not named as a run is not one
    assert [run["file"] for run in runs] == ["throughput-2026-11-22-run9.json", "throughput-2026-11-22-run10.json"]
    r = runs[-1]["ratios"][(2, "acceleration")]
    assert r["pinocchio"] == 0.2 / 0.004 and r["pinocchio_best"] == 0.15 / 0.003 and r["mujoco"] == 0.3 / 0.004
    assert r["one_thread_over_pinocchio"] == 0.2 / 0.008
    assert recorded_runs(tmp_path / "missing") == []


def test_batched_ratios_compare_like_with_like(tmp_path):
    """batched.ratios: anchor time over relacc's (slowest case) for times, relacc over anchor for steps/s."""
    from relacc.tradeoff.batched import ratios, recorded_runs

    def row(section, who, threads, value, best, case=None):
        return {"section": section, "who": who, "threads": threads, "value": value, "value_best": best, "case": case}

    rows = [row("dynamics", "relacc", 2, 150.0, 140.0, 1), row("dynamics", "relacc", 2, 300.0, 280.0, 3),
            row("dynamics", "relacc", 1, 1.0, 1.0, 1), row("dynamics", "pinocchio abaInParallel", 2, 1200.0, 1120.0),
            row("dynamics", "pinocchio abaInParallel", 1, 9.0, 9.0),
            row("step", "relacc, step per call", 1, 4.0, 3.0), row("step", "mujoco mj_step per call", 1, 14.0, 12.0),
            row("step", "relacc, compiled loop", 1, 2.0, 1.5), row("step", "mujoco rollout", 1, 13.0, 12.0),
            row("ensemble", "relacc", 2, 1e6, 1.2e6), row("ensemble", "mujoco rollout", 2, 1.25e5, 1.5e5),
            row("ensemble", "relacc", 1, 1.0, 1.0), row("ensemble", "mujoco rollout", 1, 1.0, 1.0)]
    r = ratios({"rows": rows})
    assert r["threads"] == 2
    assert (r["dynamics"], r["dynamics_best"]) == (1200.0 / 300.0, 1120.0 / 280.0)
    assert (r["ensemble"], r["ensemble_best"]) == (8.0, 8.0)
    assert (r["step"], r["step_best"]) == (3.5, 4.0) and (r["step_loop"], r["step_loop_best"]) == (6.5, 8.0)
    (tmp_path / "batched-2026-11-22-run1.json").write_text(json.dumps({"machine": {"date": "d"}, "rows": rows}))
    assert [run["ratios"] for run in recorded_runs(tmp_path)] == [r]


@pytest.mark.slow
def test_report_shows_the_recorded_dynamics_runs(quick_report):
    """Every recorded run of benchmarks/batched.py has a row in the throughput section, as does the live run."""
    html = quick_report.read_text()
    runs = sorted((REPO / "benchmarks" / "results").glob("batched-*.json"))
    assert runs, "no recorded dynamics runs in benchmarks/results"
    assert 'id="batched-table"' in html and 'id="recorded-batched"' in html
    for path in runs:
        assert f"<td>{path.name}</td>" in html
