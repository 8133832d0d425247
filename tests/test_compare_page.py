"""``relacc compare --out``'s pages in a real browser (Debian's Chromium): the answer first, every evaluator's row,
the robot drawn at full width with labels that never overlap, the directory page's verdict and names."""

import shutil
from pathlib import Path

import pytest

from relacc.cli import main

CHROMIUM_FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync"]

PLACED = """<mujoco model="placed"><compiler angle="radian"/><worldbody>
  <body name="pedestal" pos="0.3 -0.2 0.5" euler="0 0 0.7"><inertial pos="0 0 0" mass="4" diaginertia=".1 .1 .1"/>
    <body name="link1" pos="0 0 0.1"><joint name="j1" axis="0 0 1"/>
      <inertial pos="0.02 0 0" mass="1" diaginertia=".01 .02 .03"/>
      <body name="link2" pos="0.04 0 0"><joint name="j2" axis="0 1 0"/>
        <inertial pos="0.02 0 0" mass=".8" diaginertia=".004 .005 .006"/>
        <body name="link3" pos="0.04 0 0"><joint name="j3" axis="1 0 0"/>
          <inertial pos="0.02 0.01 0" mass=".5" diaginertia=".001 .002 .002"/>
          <body name="link4" pos="0.03 0 0"><joint name="j4" axis="0 1 0"/>
            <inertial pos="0.01 0 0" mass=".2" diaginertia=".001 .001 .001"/>
          </body></body></body></body></body>
</worldbody></mujoco>
"""
"""A jointless, placed first body (Pinocchio puts it at the world frame): every link and joint of Pinocchio's reading
is flagged, and they lie a few centimetres apart: the labels' hard case."""


def _browser(p):
    chromium = shutil.which("chromium")
    assert chromium, "Debian's chromium is required for this test (apt-get install chromium; .ci/run does it)"
    return p.chromium.launch(executable_path=chromium, args=CHROMIUM_FLAGS)


def _opened(p, path, errors: list):
    """``path`` opened in Chromium at 1366 x 900, its console errors appended to ``errors``: the page."""
    page = _browser(p).new_page(viewport={"width": 1366, "height": 900})
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.goto(path.as_uri(), wait_until="load")
    return page


def _overlaps(boxes) -> list:
    return [(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1:]
            if a["x"] < b["x"] + b["width"] and b["x"] < a["x"] + a["width"]
            and a["y"] < b["y"] + b["height"] and b["y"] < a["y"] + a["height"]]


@pytest.mark.slow
def test_one_model_page_answers_first_and_draws_without_overlap(tmp_path):
    from playwright.sync_api import sync_playwright

    model = tmp_path / "placed.xml"
    model.write_text(PLACED)
    page_path = tmp_path / "page.html"
    assert main(["compare", str(model), "--states", "3", "--out", str(page_path), "--engines", "pinocchio,mujoco"]) == 1
    errors: list = []
    with sync_playwright() as p:
        page = _opened(p, page_path, errors)
        verdict = page.inner_text("#verdict")
        header = page.evaluate("[...document.querySelectorAll('#dynamics th')].map(t => t.innerText)")
        labels = page.evaluate("[...document.querySelectorAll('figure.drawing svg text')]"
                               ".filter(t => (t.getAttribute('style') || '').includes('#ff0000'))"
                               ".map(t => { const b = t.getBoundingClientRect();"
                               " return {x: b.x, y: b.y, width: b.width, height: b.height, text: t.textContent}; })")
        svg = page.evaluate("(() => { const s = document.querySelector('figure.drawing svg').getBoundingClientRect();"
                            " const m = document.querySelector('#drawing').getBoundingClientRect();"
                            " return [s.width, m.width]; })()")
        page.screenshot(path=str(tmp_path / "page.png"), full_page=True)
        page.context.browser.close()
    assert errors == []
    assert "The odd one out: pinocchio" in verdict, verdict
    assert {"pinocchio", "mujoco", "relacc (case 1)", "relacc (case 3)", "tolerance"} <= set(header), header
    assert len(labels) >= 4 and _overlaps(labels) == [], labels
    assert svg[0] >= 0.95 * svg[1], svg  # the drawing takes the section's width


@pytest.mark.slow
def test_a_directory_page_opens_with_its_verdict_and_names_models_by_their_place(tmp_path, capsys):
    from playwright.sync_api import sync_playwright

    robots = tmp_path / "robots"
    (robots / "arms").mkdir(parents=True)
    (robots / "arms" / "placed.xml").write_text(PLACED)
    (robots / "ball.xml").write_text('<mujoco><worldbody><body name="b"><joint name="j" type="ball"/>'
                                     '<geom type="sphere" size=".1" pos=".1 0 0"/></body></worldbody></mujoco>')
    (robots / "empty.xml").write_text("<mujoco><worldbody/></mujoco>")
    page_path = tmp_path / "all.html"
    assert main(["compare", str(robots), "--states", "2", "--out", str(page_path)]) == 2
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "relacc compare: 3 models: 1 agree, 1 disagree, 1 cannot be compared"  # the counts first
    assert any(line.split()[:2] == ["1", "arms/placed.xml"] for line in out[1:5]), out
    assert len(out) <= 7, out  # a line per model, not each model's detail
    with sync_playwright() as p:
        browser = _browser(p)
        page = browser.new_page(viewport={"width": 1366, "height": 900})
        page.goto(page_path.as_uri(), wait_until="load")
        verdict = page.inner_text("#verdict")
        names = page.evaluate("[...document.querySelectorAll('#models td:first-child')].map(t => t.innerText)")
        links = page.evaluate("[...document.querySelectorAll('#models a')].map(a => a.getAttribute('href'))")
        landed = all(page.evaluate(f"!!document.querySelector('{href}')") for href in links)
        browser.close()
    assert verdict.startswith("1 agree, 1 disagree, 1 cannot be compared")
    assert names == ["arms/placed.xml", "ball.xml", "empty.xml"]
    assert len(links) == 2 and landed and str(Path(tmp_path)) not in "".join(names)
