"""docs/compare.md's corpus table is what ``relacc compare`` gives now on other people's robot descriptions (issue 24).

The three pinned wheels of ``scripts/corpus.py`` (example-robot-data, robosuite, gymnasium-robotics) are fetched
with ``pip download --no-deps`` into pytest's cache (pip's own cache makes it a copy after the first time) and only
their description folders unpacked; nothing of them enters the repository or the environment. Each file is one test:
``relacc compare FILE --states 5 --json`` in this process, from an empty directory, must print exactly the row the
docs show, exit 2 with exactly one line on stderr and nothing else, and leave the directory empty.
"""

import importlib.util
import json
import warnings
from pathlib import Path

import pytest

from relacc.cli import main
from relacc.errors import AccuracyWarning

SCRIPT = Path(__file__).resolve().parents[1] / "scripts" / "corpus.py"
_spec = importlib.util.spec_from_file_location("corpus", SCRIPT)
corpus = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(corpus)
SHOWN = corpus.shown_rows(corpus.DOC.read_text())


@pytest.fixture(scope="session")
def roots(request):
    return corpus.fetch(Path(request.config.cache.mkdir("relacc-corpus")))


@pytest.mark.slow
def test_the_table_has_every_file_of_the_pinned_wheels(roots):
    """One row per description file of the three wheels, no more, no fewer."""
    found = {(package, shown) for package, root in roots.items() for shown, _ in corpus.files(package, root)}
    assert len(found) == 150
    assert set(SHOWN) == found, "run python scripts/corpus.py --write"


@pytest.mark.slow
@pytest.mark.parametrize("package, shown", sorted(SHOWN), ids=[f"{p}:{s}" for p, s in sorted(SHOWN)])
def test_each_row_is_what_compare_gives_now(roots, package, shown, tmp_path, monkeypatch, capfd):
    """Each engine's load unprobed (relacc.isolate.FORKS off): no row says an engine ended the process, and the probe
    that contains one is tested in tests/test_compare_real.py; a probe loads each engine a second time, in a fork of
    this process (40 s of the 300 tests' 120). An engine that did end it would end this test's worker: a failure."""
    from relacc import isolate

    assert not any("SIG" in line for line in SHOWN.values())
    monkeypatch.setattr(isolate, "FORKS", False)
    root = roots[package]
    monkeypatch.chdir(tmp_path)
    with warnings.catch_warnings(record=True) as caught:  # what the command would print on stderr, pytest records
        warnings.simplefilter("always", AccuracyWarning)
        code = main(["compare", str(root / shown), "--states", str(corpus.STATES), "--json"])
    out, err = capfd.readouterr()
    assert [str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)] == []
    row = corpus.summarize(code, out, err, root)
    assert not row["traceback"] and row["stderr_lines"] == (1 if code == 2 else 0), err
    assert list(tmp_path.iterdir()) == []
    assert corpus.line(package, shown, row) == SHOWN[(package, shown)], "run python scripts/corpus.py --write"
    if code != 2:
        json.loads(out)  # the JSON is whole


@pytest.mark.slow
@pytest.mark.parametrize("package, shown", sorted(SHOWN), ids=[f"{p}:{s}" for p, s in sorted(SHOWN)])
def test_relaccs_reading_is_mujocos_compiled_model_where_mujoco_reads_the_file(roots, package, shown):
    """Issue 32's measure of relacc's own reading: on every file of the three packages that MuJoCo compiles, body by
    body and joint by joint (mass, mass centre, inertia, joint axes and anchors, armature, damping, gravity, the joint
    order), relacc's reading is MuJoCo's model to c eps, once MuJoCo's known readings of a file that is not physical
    are applied (relacc.validation.robots.causes.READINGS: MuJoCo drops the inertia of a massless body; each such file
    has a finding). A file relacc cannot read is one MuJoCo cannot either."""
    from relacc.engines import load
    from relacc.errors import ModelError
    from relacc.reading import read
    from relacc.validation.robots.causes import READINGS
    from tests.test_reading import differences

    path = roots[package] / shown
    try:
        mujoco = load("mujoco", path)
    except ModelError:
        return  # MuJoCo's refusal: tests/test_corpus.py's rows say what relacc answers then
    reading = read(path)
    for known in READINGS["mujoco"]:
        if known.key == "massless_inertia" and known.applies(reading):
            assert any(f.condition == "no mass but an inertia" for f in reading.findings)
            reading = known.change(reading)
    assert differences(reading, mujoco) == []


DIFF_EXCEPTIONS = {
    # MuJoCo's conversion drops the inertia of a massless link fused into its parent (FL_FOOT, FR_FOOT: mass 0,
    # inertia diag(5.7e-7, 8.4e-7, 5.3e-7) kg m^2); relacc names it, body by body
    "bolt_description/robots/bolt.urdf": [("dropped", "FL_LOWER_LEG (massless fused body FL_FOOT)", "inertia"),
                                          ("dropped", "FR_LOWER_LEG (massless fused body FR_FOOT)", "inertia")],
}
"""The URDFs of example-robot-data whose MJCF, as MuJoCo saves it, is not the same robot (docs/diff.md)."""

WORLD_ONLY = {"hector_description/robots/quadrotor_base.urdf": "no <body>",
              "iris_description/robots/iris_simple.urdf": "no <body>", "ur_description/urdf/ur3.urdf": "no <link>"}
"""URDFs with nothing to compare: two one-link robots, whose only link MuJoCo fuses into the world (it saves an MJCF
without a body, which relacc's reading refuses: nothing moves), and an empty ``<robot>`` (a xacro expansion without
its macro's call), which MuJoCo loads as an empty model and relacc refuses."""


@pytest.mark.slow
def test_diff_of_each_urdf_and_the_mjcf_mujoco_saves_from_it(roots, tmp_path, monkeypatch):
    """Issue 47: for every URDF of the pinned example-robot-data that MuJoCo loads, ``relacc diff robot.urdf
    saved.xml`` against the MJCF MuJoCo itself saves from it is the same robot, except the conversions in
    :data:`DIFF_EXCEPTIONS` (each difference a reproduced MuJoCo behaviour). The URDFs' visual and collision elements
    are left out first: MuJoCo looks for meshes by file name, and no mesh takes part in a URDF's dynamics here (each
    link has its <inertial>)."""
    import xml.etree.ElementTree as ET

    import mujoco  # a declared dependency: never skipped

    from relacc.errors import ModelError
    from relacc.validation.diff import diff

    monkeypatch.chdir(tmp_path)  # MuJoCo, called directly, appends its warnings to MUJOCO_LOG.TXT there

    root = roots["example-robot-data"]
    seen, same, refused = {}, 0, []
    for shown, path in corpus.files("example-robot-data", root):
        if not shown.endswith(".urdf"):
            continue
        document = ET.parse(path)
        for link in document.getroot().iter("link"):
            for tag in ("visual", "collision"):
                for element in link.findall(tag):
                    link.remove(element)
        urdf = tmp_path / shown.replace("/", "_")
        document.write(urdf)
        saved = urdf.with_suffix(".xml")
        try:
            mujoco.mj_saveLastXML(str(saved), mujoco.MjModel.from_xml_path(str(urdf)))
        except ValueError:
            refused.append(shown)
            continue
        try:
            result = diff(urdf, saved, states=2)
        except ModelError as exc:
            assert WORLD_ONLY.get(shown, "?") in str(exc), (shown, str(exc))
            continue
        seen[shown] = sorted((d.kind, d.element, d.quantity) for d in result.differences)
        same += result.same
    assert {k: v for k, v in seen.items() if v} == DIFF_EXCEPTIONS
    assert same >= 40, (same, refused)
