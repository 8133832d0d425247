"""``relacc diff A B`` (issue 47): a URDF and the MJCF MuJoCo saves from it are the same robot; each change planted in
that MJCF is found, named and classified, and nothing else is reported.

The reference for "the same robot" is MuJoCo's own conversion (``MjModel.from_xml_path`` then ``mj_saveLastXML``): an
independent writer of the second file, which fuses the fixed link, drops the link welded to the world, rewrites every
inertia as principal moments and a quaternion, and prints 6 significant digits. Each planted change is one edit of
that file, so the expected answer is known without relacc.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from relacc.cli.main import main
from relacc.validation.diff import diff, rounds_to, significant_digits

URDF = """<robot name="arm">
  <link name="base">
    <inertial><origin xyz="0 0 0.05"/><mass value="2.0"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/><origin xyz="0 0 0.1625"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/><dynamics damping="0.5"/>
  </joint>
  <link name="l1">
    <inertial><origin xyz="0.01 0.02 0.1" rpy="0.1 0.2 0.3"/><mass value="3.7"/>
      <inertia ixx="0.0102675" ixy="0.001" ixz="0.0005" iyy="0.0102675" iyz="0.0002" izz="0.00666"/></inertial>
  </link>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/><origin xyz="0 0.138 0" rpy="0 1.5708 0"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
  <link name="l2">
    <inertial><origin xyz="0.21254 0 0.13617"/><mass value="8.393"/>
      <inertia ixx="0.133886" ixy="0" ixz="0" iyy="0.133886" iyz="0" izz="0.0151074"/></inertial>
  </link>
  <joint name="j3" type="revolute">
    <parent link="l2"/><child link="l3"/><origin xyz="0 -0.1197 0.425"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
  <link name="l3">
    <inertial><origin xyz="0 0 0.196125"/><mass value="2.275"/>
      <inertia ixx="0.0311796" ixy="0" ixz="0" iyy="0.0311796" iyz="0" izz="0.004095"/></inertial>
  </link>
  <joint name="tool_fixed" type="fixed">
    <parent link="l3"/><child link="tool"/><origin xyz="0 0 0.39225" rpy="0 0 1.2"/>
  </joint>
  <link name="tool">
    <inertial><origin xyz="0.003 0.001 0.02"/><mass value="0.1879"/>
      <inertia ixx="0.0001" ixy="0" ixz="0" iyy="0.0002" iyz="0" izz="0.00015"/></inertial>
  </link>
</robot>
"""


@pytest.fixture(autouse=True)
def _in_a_scratch_directory(tmp_path, monkeypatch):
    """MuJoCo, called directly here to write the reference MJCF, appends its warnings to MUJOCO_LOG.TXT in the working
    directory: that directory is the test's own."""
    monkeypatch.chdir(tmp_path)


def saved_by_mujoco(tmp_path, urdf_text: str, name: str = "arm"):
    """``(urdf path, MJCF path)``: the URDF written, and the MJCF MuJoCo saves after reading it."""
    import mujoco  # a declared dependency: never skipped
    urdf = tmp_path / f"{name}.urdf"
    urdf.write_text(urdf_text)
    xml = tmp_path / f"{name}.xml"
    mujoco.mj_saveLastXML(str(xml), mujoco.MjModel.from_xml_path(str(urdf)))
    return urdf, xml


def edited(xml, edit):
    """The MJCF at ``xml`` with ``edit(root)`` applied, written beside it."""
    tree = ET.parse(xml)
    edit(tree.getroot())
    out = xml.with_name("edited.xml")
    tree.write(out)
    return out


def body(root, name):
    return next(b for b in root.iter("body") if b.get("name") == name)


def joint(root, name):
    return next(j for j in root.iter("joint") if j.get("name") == name)


def heavier(root, name, factor):
    """Body ``name``'s mass times ``factor``, written back by ``repr`` (read exactly)."""
    inertial = body(root, name).find("inertial")
    inertial.set("mass", repr(float(inertial.get("mass")) * factor))


def kinds(result):
    return sorted((d.kind, d.element, d.quantity) for d in result.differences)


def test_mujoco_s_own_conversion_is_the_same_robot(tmp_path):
    urdf, xml = saved_by_mujoco(tmp_path, URDF)
    result = diff(urdf, xml)
    assert result.differences == [] and result.same, [d.line() for d in result.differences]
    assert [(p["a"], p["b"], p["how"]) for p in result.matched["parts"]] == [
        ("l1", "l1", "joint name"), ("l2", "l2", "joint name"), ("l3", "l3", "joint name")]
    assert result.matched["parts"][2]["bodies_a"] == ["l3", "tool"]  # the fixed link fused, as MuJoCo fuses it
    assert any("base (2 kg) welded to the world" in n for n in result.notes)
    # the dynamics at matched coordinates: MuJoCo printed 6 digits, so they agree to about 1e-6 of the largest entry
    assert {row["quantity"] for row in result.dynamics} == {"mass matrix", "bias forces", "forward dynamics"}
    assert all(row["normalized"] < 1e-5 and not row["beyond"] for row in result.dynamics), result.dynamics


def test_a_file_and_itself(tmp_path, capsys):
    urdf, xml = saved_by_mujoco(tmp_path, URDF)
    assert main(["diff", str(xml), str(xml), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["same"] is True and data["differences"] == []
    assert all(row["normalized"] == 0.0 for row in data["dynamics"])  # the same numbers, the same operations


@pytest.mark.parametrize("plant, expected", [
    ("mass", [("changed", "l2", "mass")]),
    ("armature", [("added", "j1", "armature")]),
    ("rounded", [("rounded", "l2", "mass centre (body frame)")]),
    ("placement", [("placement", "the robot", "placement")]),
    ("reversed", [("convention", "j2", "axis")]),
    ("removed", [("unmatched", "l3", "joint")]),
    ("principal axes", []),
])
def test_each_planted_change_is_found_named_and_classified_and_nothing_else(tmp_path, plant, expected):
    urdf, xml = saved_by_mujoco(tmp_path, URDF)

    def edit(root):
        if plant == "mass":  # 1 % more
            heavier(root, "l2", 1.01)
        elif plant == "armature":
            joint(root, "j1").set("armature", "0.1")
        elif plant == "rounded":  # the mass centre to 3 significant digits
            body(root, "l2").find("inertial").set("pos", "0.213 0 0.136")
        elif plant == "placement":  # the whole robot turned 30 degrees about z and moved
            root_body = body(root, "l1")
            turn = np.array([np.cos(np.pi / 12), 0, 0, np.sin(np.pi / 12)])
            c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
            pos = np.array([float(x) for x in root_body.get("pos").split()])
            root_body.set("pos", " ".join(repr(float(x)) for x in np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ pos
                                          + [0.4, -0.2, 0.0]))
            root_body.set("quat", " ".join(repr(float(x)) for x in turn))
        elif plant == "reversed":
            joint(root, "j2").set("axis", "0 -1 0")
        elif plant == "removed":
            l3 = body(root, "l3")
            l3.remove(joint(root, "j3"))
        elif plant == "principal axes":  # l1's principal moments listed in another order, the quaternion turned
            from scipy.spatial.transform import Rotation

            inertial = body(root, "l1").find("inertial")
            a, b, c = (float(x) for x in inertial.get("diaginertia").split())
            w, x, y, z = (float(v) for v in inertial.get("quat").split())
            before = Rotation.from_quat([x, y, z, w])
            # P's columns: the axes of the moments b, c, a in the old principal frame (y, z, x)
            turned = before * Rotation.from_matrix(np.array([[0.0, 0, 1], [1, 0, 0], [0, 1, 0]]))
            x, y, z, w = turned.as_quat()
            np.testing.assert_allclose(turned.as_matrix() @ np.diag([b, c, a]) @ turned.as_matrix().T,
                                       before.as_matrix() @ np.diag([a, b, c]) @ before.as_matrix().T,
                                       rtol=0, atol=16 * np.finfo(float).eps * a)  # the same tensor, to rounding
            inertial.set("diaginertia", f"{b!r} {c!r} {a!r}")
            inertial.set("quat", " ".join(repr(float(v)) for v in (w, x, y, z)))

    result = diff(urdf, edited(xml, edit))
    assert kinds(result) == sorted(expected), [d.line() for d in result.differences]
    if plant == "mass":
        (d,) = result.differences
        assert d.a == 8.393 and d.b == 8.393 * 1.01  # the number written back by repr, read exactly
        np.testing.assert_allclose(d.relative, 0.01 / 1.01, rtol=0, atol=1e-12)  # one subtraction of ~8.5: ~1e-15
        line = 1 + next(n for n, text in enumerate(URDF.splitlines()) if "0.21254" in text)  # l2's <inertial>
        assert d.where_a.endswith(f"{urdf.name}:{line}") and d.where_b.endswith("edited.xml:9")
    if plant == "placement":
        (d,) = result.differences
        # the motion planted: B's robot is A's turned 30 degrees about z, then moved by (0.4, -0.2, 0) m; the printed
        # quaternion of l1 (6 digits) and the fit allow 1e-5
        np.testing.assert_allclose(d.b["turned_deg"], 30.0, rtol=0, atol=1e-4)  # 6-digit quaternion: ~2e-6 rad
        np.testing.assert_allclose(d.b["about"], [0, 0, 1], rtol=0, atol=1e-5)  # the same printed quaternion
        np.testing.assert_allclose(d.b["moved_m"], [0.4, -0.2, 0.0], rtol=0, atol=1e-5)  # 6-digit positions, ~1 m
    if plant == "reversed":
        assert result.dynamics and not any(row["beyond"] for row in result.dynamics)  # through q -> -q: the same
    if plant in ("mass", "armature"):
        assert any(row["beyond"] for row in result.dynamics)  # the consequence shows in the dynamics
    if plant == "principal axes":
        assert result.same


def test_a_fused_link_s_mass_left_out_is_named(tmp_path):
    """B made by MuJoCo from the URDF without the fixed link's inertial: its 0.1879 kg is missing from l3."""
    urdf, _ = saved_by_mujoco(tmp_path, URDF)
    without = URDF.replace('<inertial><origin xyz="0.003 0.001 0.02"/><mass value="0.1879"/>\n      <inertia '
                           'ixx="0.0001" ixy="0" ixz="0" iyy="0.0002" iyz="0" izz="0.00015"/></inertial>', "")
    assert without != URDF
    _, xml = saved_by_mujoco(tmp_path, without, "light")
    result = diff(urdf, xml)
    assert kinds(result) == [("dropped", "l3 (fused body tool)", "mass")], [d.line() for d in result.differences]
    (d,) = result.differences
    np.testing.assert_allclose(d.a - d.b, 0.1879, rtol=0, atol=1e-12)  # sums of three masses of ~10 kg: ~1e-15


def test_a_difference_counts_beyond_six_digits_and_not_within(tmp_path):
    """The default tolerance: a mass off in its 7th digit is what printing to 6 digits does (not a difference); off
    by 1e-4 of itself it is one; --rtol 1e-3 accepts that too."""
    urdf, xml = saved_by_mujoco(tmp_path, URDF)

    def mass(factor):
        def edit(root):
            inertial = body(root, "l2").find("inertial")
            inertial.set("mass", repr(8.393 * factor))
        return edit

    assert diff(urdf, edited(xml, mass(1 + 2e-7))).differences == []
    assert kinds(diff(urdf, edited(xml, mass(1 + 1e-4)))) == [("changed", "l2", "mass")]
    assert diff(urdf, edited(xml, mass(1 + 1e-4)), rtol=1e-3).differences == []


def test_significant_digits_and_rounding():
    assert [significant_digits(x) for x in (0.163, 0.1625, 1.0, 2.4629, 1e-7)] == [3, 4, 1, 5, 1]
    assert rounds_to(0.1625, 0.163)  # the UR5e's shoulder height in Menagerie's MJCF against the ROS URDF (issue 47)
    assert rounds_to(0.21254, 0.213) and rounds_to(0.0311796, 0.03118) and not rounds_to(0.163, 0.1625)


def test_the_command_line(tmp_path, capsys):
    urdf, xml = saved_by_mujoco(tmp_path, URDF)
    changed = edited(xml, lambda root: joint(root, "j1").set("damping", "0.7"))
    assert main(["diff", str(urdf), str(changed)]) == 1
    out, err = capsys.readouterr()
    first, *rest = out.splitlines()
    assert first.startswith("relacc diff: not the same robot: 1 difference (1 changed)") and err == ""
    assert any(line.split()[:3] == ["changed", "j1:", "damping:"] for line in rest), out
    assert main(["diff", str(urdf), str(xml), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) == {"same", "a", "b", "rtol", "matched", "differences", "notes", "dynamics", "trees", "engines",
                         "not_compared"}
    assert data["engines"] == {}  # not asked for (--engines)
    assert [p["name"] for p in data["trees"]["b"]["parts"]] == ["l1", "l2", "l3"]
    assert [p["parent"] for p in data["trees"]["b"]["parts"]] == [-1, 0, 1]
    for bad in (["diff", str(urdf)], ["diff", str(urdf), str(tmp_path / "none.xml")],
                ["diff", str(urdf), str(xml), "--rtol", "1e-9"]):
        assert main(bad) == 2
        out, err = capsys.readouterr()
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err


def test_compare_urdf_is_diff(tmp_path, capsys):
    """Issue 47 item 9: one way to compare two files. ``compare MODEL.xml --urdf MODEL.urdf`` says so on stderr and
    answers as ``diff MODEL.urdf MODEL.xml``."""
    urdf, xml = saved_by_mujoco(tmp_path, URDF)
    changed = edited(xml, lambda root: joint(root, "j1").set("armature", "0.1"))
    assert main(["compare", str(changed), "--urdf", str(urdf)]) == 1
    out, err = capsys.readouterr()
    assert err.splitlines() == [f"relacc compare: --urdf compares two files of one robot, which relacc diff does: "
                                f"relacc diff {urdf} {changed}"]
    assert out.startswith("relacc diff: not the same robot: 1 difference (1 added)")


def test_diff_writes_junit_and_sarif_at_the_places_in_b(tmp_path, capsys):
    """Issue 53 item 1 on diff: --junit and --sarif name each difference at its file:line in B (RELACC010); both
    parse (SARIF against sarif-pydantic's 2.1.0 model) and the run's exit code is diff's."""
    from sarif_pydantic import Sarif

    urdf, xml = saved_by_mujoco(tmp_path, URDF)
    changed = edited(xml, lambda root: joint(root, "j1").set("armature", "0.1"))
    junit, sarif = tmp_path / "d.xml", tmp_path / "d.sarif"
    assert main(["diff", str(urdf), str(changed), "--junit", str(junit), "--sarif", str(sarif)]) == 1
    capsys.readouterr()
    case = ET.parse(junit).getroot().find("testsuite/testcase")
    assert case.get("classname") == "relacc.diff" and case.find("failure") is not None
    line = 1 + next(n for n, text in enumerate(changed.read_text().splitlines()) if 'armature="0.1"' in text)
    assert f"edited.xml:{line}: added j1: armature" in case.find("failure").text
    data = json.loads(sarif.read_text())
    Sarif.model_validate(data)
    results = data["runs"][0]["results"]
    assert {r["ruleId"] for r in results} == {"RELACC010"}
    assert any(r["locations"][0]["physicalLocation"]["region"]["startLine"] == line for r in results)


def test_the_page_s_rows_put_each_part_beside_its_counterpart_and_b_s_own_after_its_parent():
    """The side-by-side order of ``--out``'s page, on trees written by hand: A depth first in file order; a part of B
    without a counterpart right after its parent's row."""
    from relacc.report.diff_page import rows

    def parts(*spec):
        return {"world": [], "parts": [{"name": n, "parent": p, "bodies": [n], "joints": []} for n, p in spec]}

    trees = {"a": parts(("a0", -1), ("a1", 0), ("a2", -1), ("a3", 1), ("a4", 0)),
             "b": parts(("b0", -1), ("b1", 0), ("b2", 0), ("b3", -1)),
             "pairs": [[0, 0, "joint name"], [1, 1, "structure"], [2, 3, "body name"]]}
    assert [(r["a"], r["b"]) for r in rows(trees)] == [
        (0, 0), (None, 2), (1, 1), (3, None), (4, None), (2, 3)]


@pytest.mark.slow
def test_the_page_shows_both_trees_side_by_side_with_every_difference_at_its_element(tmp_path, capsys):
    """Issue 47 item 8: ``--out page.html`` in a real browser (Debian's Chromium): the verdict first; the two trees
    side by side (A's labels left of B's); one numbered mark per difference of the JSON, in the row of its element;
    no label overlaps another; an input as --out refused."""
    from playwright.sync_api import sync_playwright

    from tests.test_compare_page import _opened, _overlaps

    urdf, xml = saved_by_mujoco(tmp_path, URDF)

    def edit(root):
        inertial = body(root, "l2").find("inertial")
        inertial.set("mass", repr(float(inertial.get("mass")) * 1.01))
        joint(root, "j1").set("armature", "0.1")
        joint(root, "j3").set("damping", "0.2")

    changed = edited(xml, edit)
    assert main(["diff", str(urdf), str(changed), "--json"]) == 1
    expected = json.loads(capsys.readouterr().out)["differences"]
    assert sorted((d["kind"], d["element"], d["quantity"]) for d in expected) == [
        ("added", "j1", "armature"), ("added", "j3", "damping"), ("changed", "l2", "mass")]
    page_path = tmp_path / "page.html"
    assert main(["diff", str(urdf), str(changed), "--out", str(page_path)]) == 1
    capsys.readouterr()
    assert main(["diff", str(urdf), str(changed), "--out", str(changed)]) == 2  # an input is never written over
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    errors: list = []
    with sync_playwright() as p:
        page = _opened(p, page_path, errors)
        verdict = page.inner_text("#verdict")
        boxes = page.evaluate("[...document.querySelectorAll('#trees .label, #trees a.mark')].map(t => {"
                              " const b = t.getBoundingClientRect(); return {x: b.x, y: b.y, width: b.width,"
                              " height: b.height, text: t.textContent,"
                              " side: t.closest('td').className}; })")
        rows = page.evaluate("[...document.querySelectorAll('#trees tr')].slice(1).map(r => ({"
                             " a: r.querySelector('td.side-a .part')?.textContent || null,"
                             " b: r.querySelector('td.side-b .part')?.textContent || null,"
                             " marks: [...r.querySelectorAll('a.mark')].map(m => m.textContent) }))")
        listed = page.evaluate("[...document.querySelectorAll('#differences tr[id]')].map(r => [r.id,"
                               " r.children[2].textContent])")
        page.context.browser.close()
    assert errors == []
    assert verdict.startswith("Not the same robot: 3 differences"), verdict
    assert rows[0]["a"] == "world" and [(r["a"], r["b"]) for r in rows[1:]] == [("l1", "l1"), ("l2", "l2"),
                                                                               ("l3", "l3")]
    element_of = {number.removeprefix("d"): element for number, element in listed}
    assert sorted(element_of.values()) == sorted(d["element"] for d in expected)
    where = {element_of[m]: (r["a"], r["b"]) for r in rows for m in r["marks"]}
    assert where == {"j1": ("l1", "l1"), "l2": ("l2", "l2"), "j3": ("l3", "l3")}  # each at its part's row
    assert _overlaps(boxes) == [], boxes
    right_of_a = max(b["x"] + b["width"] for b in boxes if b["side"] == "side-a")
    assert all(b["x"] > right_of_a for b in boxes if b["side"] == "side-b")  # side by side


@pytest.mark.slow
def test_the_engines_line_is_compare_s_verdict_on_each_file(tmp_path, capsys):
    """Issue 47 item 6: ``--engines`` says per file whether the engines read it as relacc does; the reference is
    ``relacc compare`` run on each file by itself."""
    urdf, xml = saved_by_mujoco(tmp_path, URDF)
    codes = []
    for path in (urdf, xml):
        codes.append(main(["compare", str(path), "--engines", "mujoco,pinocchio", "--states", "2"]))
        capsys.readouterr()
    assert main(["diff", str(urdf), str(xml), "--engines", "mujoco,pinocchio", "--states", "2", "--json"]) == 0
    engines = json.loads(capsys.readouterr().out)["engines"]
    assert [engines["a"]["exit"], engines["b"]["exit"]] == codes == [0, 0]
    assert engines["a"]["compared"][:1] == ["relacc"] and {"mujoco", "pinocchio"} <= set(engines["a"]["compared"])
    assert main(["diff", str(urdf), str(xml), "--engines", "mujoco", "--states", "2"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[1:3] == [f"  engines on A ({urdf}): every engine reads the file as relacc does and the dynamics agree",
                        f"  engines on B ({xml}): every engine reads the file as relacc does and the dynamics agree"]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_robot_moved_and_printed_to_six_digits_is_found_moved_not_turned(seed):
    """unitree_ros' G1: its MJCF is its URDF 0.793 m up, every number printed to 6 digits. The least-squares fit of the
    matched points found the move and a turn of 1.9e-5 deg, which is only that rounding: a translation alone fits
    every point within its tolerance, and is what the fit now gives, the rotation exactly the identity."""
    from relacc.validation.diff import fit_placement

    rng = np.random.default_rng(seed)
    a = rng.uniform(-0.5, 0.5, (30, 3))
    t = np.array([0.0, 0.0, 0.793])
    b = np.round(a - t, 6)  # B's points as its file prints them
    a = np.round(a, 6)
    R, p = fit_placement(a, b, np.full(len(a), 2e-6))  # 2e-6 m: twice a 6-digit rounding of a coordinate below 1 m
    assert np.array_equal(R, np.eye(3)), (seed, R)
    np.testing.assert_allclose(p, t, rtol=0, atol=1e-6, err_msg=f"seed {seed}")  # the rounding's mean, at most 5e-7
    turned = Rotation.from_rotvec([0.0, 0.0, 0.5]).as_matrix()  # a real turn is still found as one
    R, _ = fit_placement(a, np.round((a - t) @ turned, 6), np.full(len(a), 2e-6))
    np.testing.assert_allclose(R, turned, rtol=0, atol=1e-5, err_msg=f"seed {seed}")


FIXED_URDF = """<robot name="arm">
  <link name="base"><inertial><origin xyz="0 0 0.05"/><mass value="2"/>
    <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial></link>
  <link name="upper"><inertial><origin xyz="0 0 0.2"/><mass value="1.5"/>
    <inertia ixx="0.03" ixy="0" ixz="0" iyy="0.025" iyz="0" izz="0.004"/></inertial></link>
  <link name="lower"><inertial><origin xyz="0.1 0 0.15"/><mass value="{mass}"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.012" iyz="0" izz="0.003"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="10" velocity="10"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="lower"/><origin xyz="0 0 0.4"/>
    <axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="10" velocity="10"/></joint>
</robot>
"""

FLOATING_MJCF = """<mujoco model="arm">
  <worldbody>
    <body name="base" pos="0 0 0.5">
      <freejoint name="floating_base"/>
      <inertial pos="0 0 0.05" mass="2" diaginertia="0.02 0.02 0.01"/>
      <body name="upper" pos="0 0 0.1">
        <joint name="shoulder" axis="0 1 0"/>
        <inertial pos="0 0 0.2" mass="1.5" diaginertia="0.03 0.025 0.004"/>
        <body name="lower" pos="0 0 0.4">
          <joint name="elbow" axis="1 0 0"/>
          <inertial pos="0.1 0 0.15" mass="1" diaginertia="0.01 0.012 0.003"/>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("mass, beyond", [("1", False), ("1.1", True)])
def test_a_fixed_base_against_a_floating_one_compares_the_rest_with_the_free_joint_held(tmp_path, mass, beyond):
    """unitree_ros' G1 pairs: the URDF's base is fixed (its floating joint commented out), the MJCF's free. The
    dynamics were not compared at all ("parts without a counterpart"); they are now compared with the MJCF's free joint
    held where it places its base: the same arm agrees within printing, and a link 10% heavier in the URDF is beyond
    it in the mass matrix. The unmatched free joint and the placement stay differences."""
    urdf, mjcf = tmp_path / "arm.urdf", tmp_path / "arm.xml"
    urdf.write_text(FIXED_URDF.format(mass=mass))
    mjcf.write_text(FLOATING_MJCF)
    d = diff(urdf, mjcf)
    kinds = sorted(x.kind for x in d.differences)
    assert "unmatched" in kinds and "placement" in kinds, kinds
    assert any("free joint 'floating_base' (of base) held" in n for n in d.notes), d.notes
    rows = {row["quantity"]: row for row in d.dynamics}
    assert set(rows) == {"mass matrix", "bias forces", "forward dynamics"}, rows
    assert rows["mass matrix"]["beyond"] is beyond, rows["mass matrix"]
    if not beyond:
        assert not any(row["beyond"] for row in d.dynamics), d.dynamics


@pytest.mark.parametrize("plant", ["mass", "armature", "anchor", "not physical"])
def test_a_dynamics_row_beyond_printing_says_whether_the_listed_masses_and_armatures_explain_it(tmp_path, plant):
    """SO-ARM100's SO-101 pair (TheRobotStudio/SO-ARM100): the MJCF adds armature 0.028 to every joint, and the mass
    matrix differs by 0.78 of its largest entry. The rows said "BEYOND" and nothing of why. Each row beyond printing is
    now compared again with A given B's masses, mass centres, inertias, armatures and gravity: a mass or an armature
    planted alone is then within printing (MuJoCo printed 6 digits: about 1e-6 of the largest entry, as in
    test_mujoco_s_own_conversion_is_the_same_robot), and an anchor moved 2 cm is not (the geometry differs). An
    inertia no rigid body has (B's l2 breaking the triangle inequality) is given to A as written: the first version
    held it to A's physical checks and the command failed."""
    urdf, xml = saved_by_mujoco(tmp_path, URDF)

    def edit(root):
        if plant == "mass":  # 10 % more
            heavier(root, "l2", 1.1)
        elif plant == "armature":
            joint(root, "j2").set("armature", "0.5")
        elif plant == "not physical":  # 0.01 + 0.01 < 0.5: relacc reads it and names it, MuJoCo would refuse it
            body(root, "l2").find("inertial").set("diaginertia", "0.01 0.01 0.5")
        else:  # l3's joint 2 cm further along l2
            l3 = body(root, "l3")
            pos = np.array([float(x) for x in l3.get("pos").split()])
            l3.set("pos", " ".join(repr(float(x)) for x in pos + [0.0, 0.0, 0.02]))

    result = diff(urdf, edited(xml, edit))
    beyond = [row for row in result.dynamics if row["beyond"]]
    assert {row["quantity"] for row in beyond} >= {"mass matrix"}, result.dynamics
    for row in beyond:
        again = row["explained"]
        if plant == "anchor":
            assert again["beyond"] and again["normalized"] > 1e-3, row  # 2 cm on a 0.4 m link: percents
        else:
            assert not again["beyond"] and again["normalized"] < 1e-5, row
    for row in result.dynamics:
        assert ("explained" in row) is row["beyond"], row
    text = main_output(["diff", str(urdf), str(xml.with_name("edited.xml"))])
    said = "so the geometry differs too" if plant == "anchor" else "so those differences explain it"
    assert any(line.startswith("  dynamics: mass matrix") and said in line for line in text), text


def test_a_dynamics_row_printing_cannot_decide_says_so(tmp_path):
    """unitree_rl_gym's H1-2 pair: its fingers' links weigh grams, the mass matrix's condition number makes the
    forward dynamics' allowance 2.8e4 times its largest entry, and the row read "printing allows 2.8e+04" as if it had
    passed. A row whose allowance reaches its entries says that it cannot tell the files apart; a well-conditioned
    arm's rows decide."""
    light = URDF.replace('<mass value="2.275"/>', '<mass value="2.275e-05"/>').replace(
        'ixx="0.0311796" ixy="0" ixz="0" iyy="0.0311796" iyz="0" izz="0.004095"',
        'ixx="3.11796e-13" ixy="0" ixz="0" iyy="3.11796e-13" iyz="0" izz="4.095e-14"').replace(
        '<mass value="0.1879"/>', '<mass value="1.879e-06"/>').replace(
        'ixx="0.0001" ixy="0" ixz="0" iyy="0.0002" iyz="0" izz="0.00015"',
        'ixx="1e-13" ixy="0" ixz="0" iyy="2e-13" iyz="0" izz="1.5e-13"')
    assert light != URDF
    for text, decides in ((URDF, True), (light, False)):
        urdf, xml = saved_by_mujoco(tmp_path, text, "light" if not decides else "arm")
        rows = {row["quantity"]: row for row in diff(urdf, xml).dynamics}
        fd = rows["forward dynamics"]
        assert fd["decides"] is decides and (fd["tolerance"] >= 1.0) is not decides, fd
        assert rows["mass matrix"]["decides"], rows
        out = main_output(["diff", str(urdf), str(xml)])
        line = next(x for x in out if x.startswith("  dynamics: forward dynamics"))
        assert ("cannot tell the files apart" in line) is not decides, line


def main_output(argv) -> list[str]:
    """The text ``relacc diff`` prints, its lines."""
    import contextlib
    import io

    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        main(argv)
    return buffer.getvalue().splitlines()


@pytest.mark.parametrize("written, kind", [("8", "changed"), ("8.4", "rounded"), ("8.39", "rounded")])
def test_a_number_written_with_one_digit_is_a_change_not_a_rounding(tmp_path, written, kind):
    """example-robot-data's SO-101 against SO-ARM100's SO-100: the gripper's range ``-0.2 2`` against ``-0.174533
    1.74533`` read as "rounded", each the other to one significant digit, though 13% apart (two ranges chosen apart).
    A number of one significant digit no longer counts as another rounded; two or more still do. Here l2's mass,
    8.393 kg, written 8, 8.4 and 8.39."""
    urdf, xml = saved_by_mujoco(tmp_path, URDF)
    result = diff(urdf, edited(xml, lambda root: body(root, "l2").find("inertial").set("mass", written)))
    assert [(d.kind, d.quantity) for d in result.differences if d.quantity == "mass"] == [(kind, "mass")], \
        [d.line() for d in result.differences]


def test_a_part_only_one_file_has_is_held_and_the_rest_s_dynamics_compared(tmp_path):
    """mujoco_menagerie's Z1 arm against example-robot-data's, whose URDF has a gripper (a jaw on a hinge) the MJCF
    lacks: the dynamics were not compared at all ("parts without a counterpart"). The jaw's joint is now held where the
    URDF places it and the rest compared: the jaw's 0.4 kg makes the mass matrix differ beyond printing, and A given
    B's masses agrees within printing (MuJoCo printed 6 digits), so the listed differences explain it; without the jaw
    in either file the arm is the same robot."""
    jaw = URDF.replace("</robot>", """  <joint name="grip" type="revolute">
    <parent link="tool"/><child link="jaw"/><origin xyz="0 0.02 0.05"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <link name="jaw">
    <inertial><origin xyz="0 0 0.03"/><mass value="0.4"/>
      <inertia ixx="0.0003" ixy="0" ixz="0" iyy="0.0003" iyz="0" izz="0.0001"/></inertial>
  </link>
</robot>""")
    assert jaw != URDF
    _, xml = saved_by_mujoco(tmp_path, URDF)  # B: the arm without the jaw
    urdf = tmp_path / "with_jaw.urdf"
    urdf.write_text(jaw)
    d = diff(urdf, xml)
    assert ("unmatched", "jaw", "part") in kinds(d), kinds(d)
    assert any("held where that file places them (grip)" in n for n in d.notes), d.notes
    rows = {row["quantity"]: row for row in d.dynamics}
    assert rows["mass matrix"]["beyond"], rows
    for row in d.dynamics:
        if row["beyond"]:
            assert not row["explained"]["beyond"] and row["explained"]["normalized"] < 1e-5, row


def _line_of(path, text: str) -> int:
    """The 1-based line of ``path`` on which ``text`` first appears."""
    return next(n for n, line in enumerate(path.read_text().splitlines(), 1) if text in line)


def test_gravity_compensation_is_a_difference_at_its_body_and_constraints_are_said(tmp_path, capsys):
    """Trossen's arm (trossen_arm_mujoco `77aba5d`, against trossen_arm_description `8834f2e`): its MJCF puts
    gravcomp="1" on every body, so that MuJoCo holds up each body's whole weight, and couples the gripper's carriages
    by an <equality><joint>, where its URDF has a <mimic>. diff named neither: with only those in B it would have called
    the files the same robot. Now the compensation of each part is a difference at its body's line, the fraction of
    the part's weight (1: all of it); joint couplings are compared (the next test); and every other element beyond the
    tree that no comparison evaluates (here a <connect> equality) is a note of its file's, in the JSON's
    "not_compared" and counted in the verdict."""
    urdf, xml = saved_by_mujoco(tmp_path, URDF)

    def compensated(root):
        body(root, "l2").set("gravcomp", "1")

    def connected(root):
        ET.SubElement(ET.SubElement(root, "equality"), "connect", body1="l3", body2="l1", anchor="0 0 0.1")

    b = edited(xml, compensated)
    d = diff(urdf, b)
    assert kinds(d) == [("added", "l2", "gravity compensation")], [x.line() for x in d.differences]
    (g,) = d.differences
    assert (g.a, g.b) == (0.0, 1.0)
    assert g.where_b == f"{b}:{_line_of(b, 'name=' + chr(34) + 'l2')}"
    assert not any(row["beyond"] for row in d.dynamics)  # the bodies' own dynamics: the same
    assert d.beyond == [] and not any("gravity compensation" in n for n in d.notes), d.notes  # compared: no note

    b = edited(xml, connected)
    assert main(["diff", str(xml), str(b), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["same"] is True and data["differences"] == []
    assert data["not_compared"] == ["B: 1 equality constraint (connect): the comparisons are the tree's without "
                                    "constraints"]
    assert main(["diff", str(xml), str(b)]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert "the same robot within printing" in first and "1 kind of element beyond the tree not compared" in first


MIMIC = '<mimic joint="j2" multiplier="-0.5" offset="0.1"/>'
"""j3 follows j2 in the URDF: q3 = 0.1 - 0.5 q2 (MuJoCo's URDF reader writes it as an <equality><joint>)."""


@pytest.mark.parametrize("offset, expected", [(0.0, None), (0.05, [0.15, -0.5, 0.0, 0.0, 0.0])])
def test_a_coupling_written_through_another_joint_is_the_relation_it_implies(tmp_path, offset, expected):
    """pollen-robotics' Reachy 2 couples a finger's distal joint to its proximal one in the URDF and to the finger
    joint in the MJCF: diff said "dropped" and "added", two differences where the files may mean one relation. A
    coupling is now compared, where the other file has no coupling of those two joints, with the relation that
    file's linear couplings imply through other joints. Here A (the URDF) has q2 = 0.2 + 2 q1 and q3 = 0.1 - 0.5 q2;
    B (MuJoCo's MJCF of it) keeps the first and writes q3 = offset - q1. By hand, with offset 0: q3 = 0.1 - 0.5 (0.2
    + 2 q1) = -q1, the same relation (no difference); with offset 0.05, B's q3 = 0.05 - q1 = 0.15 - 0.5 q2. Each
    file's couplings are held to the other's: A's q3 on q2, (0.1, -0.5) against B's implied (0.15, -0.5), and B's q3
    on q1, A's implied (0, -1) against (0.05, -1): two "changed" at j3, each at its own file's line, nothing dropped
    or added."""
    limit = '<limit lower="-3" upper="3" effort="10" velocity="1"/>'
    text = URDF.replace(f'{limit}\n  </joint>\n  <link name="l2">',
                        f'{limit}<mimic joint="j1" multiplier="2" offset="0.2"/>\n  </joint>\n  <link name="l2">')
    text = text.replace(f'{limit}\n  </joint>\n  <link name="l3">', f'{limit}{MIMIC}\n  </joint>\n  <link name="l3">')
    assert text.count("<mimic") == 2
    urdf, xml = saved_by_mujoco(tmp_path, text)

    def through_j1(root):
        (eq,) = [e for e in root.find("equality") if e.get("joint1") == "j3"]
        eq.set("joint2", "j1")
        eq.set("polycoef", f"{offset} -1 0 0 0")

    b = edited(xml, through_j1)
    d = diff(urdf, b)
    found = [(x.kind, x.element, x.quantity) for x in d.differences]
    if expected is None:
        assert found == [], [x.line() for x in d.differences]
        return
    # each names its leader: A's q3 on q2, B's on q1
    assert found == [("changed", "j3", "coupling (on j2)"), ("changed", "j3", "coupling (on j1)")], \
        [x.line() for x in d.differences]
    (on_q2, on_q1), eps = d.differences, np.finfo(float).eps
    np.testing.assert_allclose(on_q2.a, [0.1, -0.5, 0.0, 0.0, 0.0], rtol=0, atol=0)  # A's, as written
    np.testing.assert_allclose(on_q2.b, expected, rtol=0, atol=4 * eps)  # a few products and sums of printed numbers
    np.testing.assert_allclose(on_q1.a, [0.0, -1.0, 0.0, 0.0, 0.0], rtol=0, atol=4 * eps)  # likewise
    np.testing.assert_allclose(on_q1.b, [offset, -1.0, 0.0, 0.0, 0.0], rtol=0, atol=0)  # B's, as written
    # each at its own file's line; the relation implied through other joints at the other file, which has no one line
    assert on_q2.where_a.startswith(f"{urdf}:") and on_q2.where_b == str(b)
    assert on_q1.where_a == str(urdf) and on_q1.where_b.startswith(f"{b}:")


@pytest.mark.parametrize("edit, expected", [
    (None, []),
    ("multiplier", [("changed", "j3", "coupling (on j2)", [0.1, -0.5, 0.0, 0.0, 0.0], [0.1, -0.4, 0.0, 0.0, 0.0])]),
    ("inverted", []),
    ("removed", [("dropped", "j3", "coupling (on j2)", [0.1, -0.5, 0.0, 0.0, 0.0], None)]),
    ("inactive", [("dropped", "j3", "coupling (on j2)", [0.1, -0.5, 0.0, 0.0, 0.0], None)]),
    ("no mimic in A", [("added", "j3", "coupling (on j2)", None, [0.1, -0.5, 0.0, 0.0, 0.0])]),
])
def test_a_joint_coupling_is_compared_whichever_way_each_file_writes_it(tmp_path, edit, expected):
    """A URDF's <mimic> and an MJCF's <equality><joint> are one relation, q_follower = offset + multiplier q_leader
    (MuJoCo's polycoef, relative to each joint's ref; 0 here): compared between matched joints, not left to a note.
    The MJCF MuJoCo saves from the URDF couples j3 to j2 as the URDF does: no difference. Each planted edit is found:
    the multiplier -0.5 -> -0.4 (changed); the same relation written the other way, j2 = 0.2 - 2 q3 (by hand: q3 =
    0.1 - 0.5 q2 <=> q2 = (0.1 - q3) / 0.5), no difference; the equality removed, or made inactive (dropped; the
    inactive one said as not compared); the mimic removed from A (added)."""
    limit = '<limit lower="-3" upper="3" effort="10" velocity="1"/>'
    text = URDF.replace(f'{limit}\n  </joint>\n  <link name="l3">', f'{limit}{MIMIC}\n  </joint>\n  <link name="l3">')
    assert MIMIC in text
    urdf, xml = saved_by_mujoco(tmp_path, text)

    def change(root):
        (eq,) = root.find("equality")
        if edit == "multiplier":
            eq.set("polycoef", "0.1 -0.4 0 0 0")
        elif edit == "inverted":
            eq.set("joint1", "j2")
            eq.set("joint2", "j3")
            eq.set("polycoef", "0.2 -2 0 0 0")
        elif edit == "removed":
            root.remove(root.find("equality"))
        elif edit == "inactive":  # MuJoCo starts without it (eq_active0 0): no coupling, and said as not compared
            eq.set("active", "false")

    b = edited(xml, change) if edit in ("multiplier", "inverted", "removed", "inactive") else xml
    a = urdf
    if edit == "no mimic in A":
        a = tmp_path / "plain.urdf"
        a.write_text(text.replace(MIMIC, ""))
    d = diff(a, b)
    found = [(x.kind, x.element, x.quantity, x.a, x.b) for x in d.differences]
    assert len(found) == len(expected), [x.line() for x in d.differences]
    for (kind, el, q, va, vb), (ek, eel, eq_, ea, eb) in zip(found, expected):
        assert (kind, el, q) == (ek, eel, eq_)
        for got, want in ((va, ea), (vb, eb)):
            assert (got is None) == (want is None)
            if want is not None:  # the inverted relation's numbers: one division each, c eps
                np.testing.assert_allclose(got, want, rtol=0, atol=4 * np.finfo(float).eps)
    if edit == "inactive":
        assert d.beyond == ["B: 1 equality constraint (joint): the comparisons are the tree's without constraints"]
    else:
        assert d.beyond == [] and not any("mimic" in n or "equality" in n for n in d.notes), d.notes


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_one_changed_part_does_not_make_the_robot_moved(seed):
    """Trossen's follower arm (trossen_arm_mujoco `77aba5d`): its MJCF's link_6 differs from the URDF's (mass centre
    3e-5 to 2.4e-4 m), and every other number is the URDF's 8 digits printed to 6. The fit left link_6's points out,
    then returned the mean of the others' rounding as a translation: "B's robot is A's moved by [-2.85e-06 2.5e-10
    7.4e-09] m", a placement difference that is only printing. When the points it keeps fit without a motion, there is
    none: the rotation and the translation are exactly the identity and zero."""
    from relacc.validation.diff import fit_placement

    rng = np.random.default_rng(seed)
    a = rng.uniform(-0.5, 0.5, (16, 3))
    b = np.round(a, 6)  # B prints A's points to 6 digits
    b[:2] += 1e-5  # and one part (two points: its mass centre, its foot on the axis) moved 5 times the tolerance
    R, p = fit_placement(a, b, np.full(len(a), 2e-6))
    assert np.array_equal(R, np.eye(3)) and np.array_equal(p, np.zeros(3)), (seed, R, p)


def test_a_floating_base_s_children_are_matched_to_the_fixed_base_s_by_structure(tmp_path):
    """Trossen's mobile AI: the URDF's arms hang from its base welded to the world and are named
    `follower_left/joint_0`, the MJCF's from a free base and named `follower_left_joint_0`. No joint or body name was
    shared, the structure was matched from the world's children only, so the 16 arm parts were 32 unmatched ones and
    the dynamics were compared without the arms. The unmatched free root of one file is now the other's world for the
    structure: the arms match, the free joint is held and the dynamics compared."""
    urdf, mjcf = tmp_path / "arm.urdf", tmp_path / "arm.xml"
    renamed = FIXED_URDF.format(mass="1")
    for old in ("upper", "lower", "shoulder", "elbow"):
        renamed = renamed.replace(f'"{old}"', f'"arm/{old}"')
    urdf.write_text(renamed)
    mjcf.write_text(FLOATING_MJCF)
    d = diff(urdf, mjcf)
    assert [(p["a"], p["b"], p["how"]) for p in d.matched["parts"]] == [
        ("arm/upper", "upper", "structure"), ("arm/lower", "lower", "structure")]
    assert d.matched["only_b"] == ["base"] and d.matched["only_a"] == []
    assert any("free joint 'floating_base' (of base) held" in n for n in d.notes), d.notes
    assert {row["quantity"] for row in d.dynamics} == {"mass matrix", "bias forces", "forward dynamics"}
    assert not any(row["beyond"] for row in d.dynamics), d.dynamics


def test_a_body_with_several_joints_is_the_same_part_as_a_urdf_chain_of_massless_links(tmp_path):
    """The shipped pair: the MJCF gives each body six joints (three slides, three hinges), the URDF reaches each
    through five massless links, one joint each (URDF has one joint a link). relacc called them "not the same robot",
    20 parts unmatched. A massless link with joints whose one child has joints is a frame of that child's part, its
    joints first. What the files really write differently (their texts): the URDF's placeholder limits of +-1000 on
    all twelve joints, and gravity (the MJCF's option is off; a URDF has none, read as standard gravity)."""
    from relacc.fixtures.shipped import models_dir

    d = diff(models_dir() / "two_body_euler.xml", models_dir() / "two_body_euler.urdf")
    joints = [f"s{i}_{x}" for i in (1, 2) for x in "xyz"] + [f"theta_B{i}_{k}" for i in (1, 2) for k in (1, 2, 3)]
    assert kinds(d) == sorted([("added", j, "range") for j in joints] + [("changed", "world", "gravity")]), kinds(d)
    assert [(p["a"], p["b"], p["how"]) for p in d.matched["parts"]] == [("B1", "B1", "joint name"),
                                                                       ("B2", "B2", "joint name")]
    assert d.matched["parts"][0]["bodies_b"] == ["B1", "B1_s1_x_link", "B1_s1_y_link", "B1_s1_z_link",
                                                 "B1_theta_B1_1_link", "B1_theta_B1_2_link"]
    rows = {row["quantity"]: row for row in d.dynamics}
    # the mass matrix does not see gravity: the same written numbers, composed through six joints of one body in A
    # and six bodies in B, agree to rounding (a few hundred eps of the largest entry at most; 1e-12 is 4,500 eps)
    assert not rows["mass matrix"]["beyond"] and rows["mass matrix"]["normalized"] <= 1e-12, rows
    # gravity's: A given B's gravity agrees to rounding, the forward dynamics' times the mass matrix's condition number
    # (up to 1.8e5 at these states; 1e-9 is 25 eps cond)
    for quantity in ("bias forces", "forward dynamics"):
        assert rows[quantity]["beyond"] and rows[quantity]["explained"]["normalized"] <= 1e-9, rows

    # an armature on one of A's frames' joints (the URDF as A): A given B's armatures puts it on that joint alone
    heavy = tmp_path / "armature.xml"
    heavy.write_text((models_dir() / "two_body_euler.xml").read_text().replace(
        'name="theta_B1_2" type="hinge"', 'name="theta_B1_2" type="hinge" armature="0.5"'))
    d = diff(models_dir() / "two_body_euler.urdf", heavy)
    assert ("added", "theta_B1_2", "armature") in kinds(d), kinds(d)
    rows = {row["quantity"]: row for row in d.dynamics}
    assert rows["mass matrix"]["beyond"] and rows["mass matrix"]["explained"]["normalized"] <= 1e-12, rows


def test_a_massless_link_given_a_small_mass_by_the_other_file_stays_a_part_of_its_own(tmp_path):
    """MuJoCo refuses a massless body that moves, so an MJCF made from a URDF with a massless link between two
    jointed ones gives it a small mass. Then the link is a part in both files (not a frame of its child's part in the
    URDF alone, which left the child's joint and part unmatched): one mass and one inertia changed, and the 1 g
    changes the dynamics by less than printing does."""
    j2 = '''  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/><origin xyz="0 0.138 0" rpy="0 1.5708 0"/>'''
    tiny = URDF.replace(j2, '''  <joint name="j2a" type="revolute">
    <parent link="l1"/><child link="l1a"/><origin xyz="0 0.05 0"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
  <link name="l1a">
    <inertial><mass value="0.001"/><inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial>
  </link>
  <joint name="j2" type="revolute">
    <parent link="l1a"/><child link="l2"/><origin xyz="0 0.088 0" rpy="0 1.5708 0"/>''')
    assert tiny != URDF
    _, xml = saved_by_mujoco(tmp_path, tiny)
    massless = tmp_path / "massless.urdf"
    massless.write_text(tiny.replace('<inertial><mass value="0.001"/><inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" '
                                     'iyz="0" izz="1e-6"/></inertial>', ""))
    d = diff(massless, xml)
    assert kinds(d) == [("changed", "l1a", "inertia"), ("changed", "l1a", "mass")], kinds(d)
    assert len(d.dynamics) == 3 and not any(row["beyond"] for row in d.dynamics), d.dynamics


def _legs(mjcf: bool, com_shift: float, mass_factor: float, up: float) -> str:
    """A base with four legs of a hip (about x), a thigh and a calf (about y) each: a URDF on a fixed base, or an
    MJCF on a free base ``up`` m above the world origin with each leg link's mass centre ``com_shift`` m further along
    x and its mass ``mass_factor`` times the URDF's (unitree's Go2 and B2, URDF against MJCF)."""
    legs = [("FL", 0.19, 0.05), ("FR", 0.19, -0.05), ("RL", -0.19, 0.05), ("RR", -0.19, -0.05)]
    parts = [("hip", "1 0 0", "0 {y2} 0", 0.7), ("thigh", "0 1 0", "0 0 -0.21", 1.1),
             ("calf", "0 1 0", "0 0 -0.21", 0.2)]
    if not mjcf:
        out = ['<robot name="legs"><link name="base"><inertial><mass value="6"/>'
               '<inertia ixx="0.03" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>']
        for leg, x, y in legs:
            parent, origin = "base", f"{x} {y} 0"
            for name, axis, nxt, m in parts:
                out.append(f'<link name="{leg}_{name}"><inertial><origin xyz="0.01 0 -0.05"/><mass value="{m}"/>'
                           '<inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.0015"/></inertial></link>')
                out.append(f'<joint name="{leg}_{name}_joint" type="revolute"><parent link="{parent}"/>'
                           f'<child link="{leg}_{name}"/><origin xyz="{origin}"/><axis xyz="{axis}"/>'
                           '<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>')
                parent, origin = f"{leg}_{name}", nxt.format(y2=0.09 if y > 0 else -0.09)
        return "\n".join(out + ["</robot>"])
    out = [f'<mujoco model="legs"><worldbody><body name="base" pos="0 0 {up}"><freejoint/>'
           '<inertial pos="0 0 0" mass="6" diaginertia="0.03 0.1 0.1"/>']
    for leg, x, y in legs:
        pos, close = f"{x} {y} 0", 0
        for name, axis, nxt, m in parts:
            out.append(f'<body name="{leg}_{name}" pos="{pos}"><joint name="{leg}_{name}_joint" axis="{axis}"/>'
                       f'<inertial pos="{0.01 + com_shift} 0 -0.05" mass="{m * mass_factor!r}" '
                       'diaginertia="0.001 0.002 0.0015"/>')
            pos, close = nxt.format(y2=0.09 if y > 0 else -0.09), close + 1
        out.append("</body>" * close)
    return "\n".join(out + ["</body></worldbody></mujoco>"])


def test_a_floating_base_placed_up_with_its_own_masses_is_one_placement_and_the_masses_explain_the_dynamics(
        tmp_path):
    """unitree's Go2 and B2 (unitree_ros `d6f13aa` against unitree_mujoco `c598f10`): the MJCF floats its base 0.445 m
    (0.8 m) up and has its own mass model, every mass centre elsewhere. The placement was fitted on mass centres and
    their feet on the joint axes, all moved, so none was found: every joint's anchor read "changed" by 0.445 m, and
    the dynamics "differ ... so the geometry differs too", which is wrong. The fit now also takes the points where two
    joint axes pass nearest each other (the joints' geometry alone) and starts from the translation most points agree
    on: one placement (0.445 m up), the masses and mass centres changed, no anchor, and A given B's masses agrees."""
    a, b = tmp_path / "legs.urdf", tmp_path / "legs.xml"
    a.write_text(_legs(False, 0, 1, 0))
    b.write_text(_legs(True, 0.02, 1.2, 0.445))
    d = diff(a, b)
    assert not [x for x in d.differences if x.quantity == "anchor"], [x.line() for x in d.differences]
    (placement,) = [x for x in d.differences if x.kind == "placement"]
    np.testing.assert_allclose(placement.b["moved_m"], [0, 0, 0.445], rtol=0, atol=1e-12)  # printed numbers summed
    assert placement.b["turned_deg"] == 0.0
    # besides: the URDF's limits (the MJCF has none), and the free joint alone without a counterpart (held)
    assert {x.quantity for x in d.differences} == {"placement", "mass", "mass centre", "range", "part"}, \
        [x.line() for x in d.differences]
    rows = {row["quantity"]: row for row in d.dynamics}
    assert rows["mass matrix"]["beyond"] and not rows["mass matrix"]["explained"]["beyond"], rows
