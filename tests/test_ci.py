"""relacc in a description repository's CI (issue 53): JUnit XML and SARIF 2.1.0 pointing at the element's file and
line, a baseline of accepted results, and the rules' fixed list (docs/ci.md)."""

import json
import xml.etree.ElementTree as ET

import pytest
from sarif_pydantic import Sarif

from relacc.cli import main
from relacc.report.ci import RULES
from tests.cli import borrowed_site_dirs

GOOD = """<robot name="good"><link name="base"/>
  <link name="arm"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""
BAD = GOOD.replace('izz="0.02"', 'izz="0.05"').replace('"good"', '"bad"')
"""The same arm whose link breaks the triangle inequality (0.01 + 0.02 < 0.05): a finding at line 2, its <inertial>."""


@pytest.fixture
def repo(tmp_path, monkeypatch):
    """A description repository: two URDFs under robots/, relacc run from its root (as CI runs it)."""
    (tmp_path / "robots").mkdir()
    (tmp_path / "robots" / "good.urdf").write_text(GOOD)
    (tmp_path / "robots" / "bad.urdf").write_text(BAD)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_junit_has_a_testcase_per_model_failing_at_file_and_line(repo, capsys):
    assert main(["compare", "robots", "--states", "2", "--engines", "pinocchio,mujoco", "--junit", "out/j.xml"]) == 1
    suite = ET.parse(repo / "out" / "j.xml").getroot().find("testsuite")
    cases = {c.get("name"): c for c in suite.findall("testcase")}
    assert set(cases) == {"robots/bad.urdf", "robots/good.urdf"} and suite.get("failures") == "1"
    assert cases["robots/good.urdf"].find("failure") is None
    failure = cases["robots/bad.urdf"].find("failure")
    lines = failure.text.splitlines()
    assert any(line.startswith("robots/bad.urdf:2: body arm: principal moments that break the triangle inequality")
               and "[RELACC001 non-physical-body]" in line for line in lines), lines


def test_sarif_is_sarif_2_1_0_and_points_at_the_element(repo, capsys):
    """The file parses as SARIF 2.1.0 (sarif-pydantic's model of the standard, every rule declared once); the finding
    is a result of rule RELACC001, level error, at robots/bad.urdf line 2, where the link's <inertial> starts."""
    assert main(["compare", "robots", "--states", "2", "--engines", "pinocchio,mujoco", "--sarif", "s.sarif"]) == 1
    data = json.loads((repo / "s.sarif").read_text())
    log = Sarif.model_validate(data)
    assert log.version == "2.1.0" and len(log.runs) == 1
    driver = data["runs"][0]["tool"]["driver"]
    assert [r["id"] for r in driver["rules"]] == list(RULES) and driver["name"] == "relacc"
    (found,) = [r for r in data["runs"][0]["results"] if r["ruleId"] == "RELACC001"]
    assert found["level"] == "error" and driver["rules"][found["ruleIndex"]]["id"] == "RELACC001"
    where = found["locations"][0]["physicalLocation"]
    assert where == {"artifactLocation": {"uri": "robots/bad.urdf"}, "region": {"startLine": 2}}
    assert "<inertial>" in (repo / "robots" / "bad.urdf").read_text().splitlines()[1]


def test_a_baseline_accepts_known_results_and_fails_on_new_ones(repo, capsys):
    """--write-baseline records what fails now; with --baseline the same tree exits 0, and a new problem (the good arm
    broken too) exits 1, its SARIF results marked new, the accepted ones unchanged. A line moved by an edit elsewhere
    keeps a result accepted (fingerprints name what, not where)."""
    args = ["compare", "robots", "--states", "2", "--engines", "pinocchio,mujoco"]
    assert main(args + ["--write-baseline", "base.json"]) == 1
    assert main(args + ["--baseline", "base.json"]) == 0
    (repo / "robots" / "bad.urdf").write_text("\n\n" + BAD)  # the same finding two lines down
    assert main(args + ["--baseline", "base.json"]) == 0
    (repo / "robots" / "good.urdf").write_text(BAD.replace('"bad"', '"good"'))
    assert main(args + ["--baseline", "base.json", "--sarif", "s.sarif"]) == 1
    states = {(r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"], r["ruleId"]): r["baselineState"]
              for r in json.loads((repo / "s.sarif").read_text())["runs"][0]["results"]}
    assert states[("robots/good.urdf", "RELACC001")] == "new"
    assert states[("robots/bad.urdf", "RELACC001")] == "unchanged"
    assert "new result" in capsys.readouterr().out
    (repo / "junk.json").write_text("[1, 2]")
    assert main(args + ["--baseline", "junk.json"]) == 2
    assert "not a relacc baseline" in capsys.readouterr().err


def test_a_refusal_is_a_result_and_an_error_in_junit(repo, capsys):
    (repo / "robots" / "broken.urdf").write_text("<robot name='x'><link name='a'/><joint name='j' type='planar'>"
                                                 "<parent link='a'/><child link='b'/></joint></robot>")
    assert main(["compare", "robots", "--states", "2", "--engines", "mujoco", "--junit", "j.xml", "--sarif",
                 "s.sarif"]) == 2
    cases = {c.get("name"): c for c in ET.parse(repo / "j.xml").getroot().iter("testcase")}
    assert cases["robots/broken.urdf"].find("error") is not None
    results = json.loads((repo / "s.sarif").read_text())["runs"][0]["results"]
    assert any(r["ruleId"] == "RELACC008" for r in results)


XACRO = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="mass" default="1.0"/>
  <xacro:property name="len" value="0.3"/>
  <xacro:macro name="box_inertial" params="m x y z">
    <inertial><origin xyz="${x/2} 0 0"/><mass value="${m}"/>
      <inertia ixx="${m*(y*y+z*z)/12}" ixy="0" ixz="0" iyy="${m*(x*x+z*z)/12}" iyz="0" izz="${IZZ}"/>
    </inertial>
  </xacro:macro>
  <link name="base"/>
  <link name="upper"><xacro:box_inertial m="$(arg mass)" x="${len}" y="0.05" z="0.05"/></link>
  <link name="lower"><xacro:box_inertial m="0.5" x="${len}" y="0.04" z="0.04"/></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="5"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="lower"/><origin xyz="${len} 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="5"/></joint>
</robot>
"""


@pytest.mark.slow
@pytest.mark.parametrize("izz,verdict", [("m*(x*x+y*y)/12", 0), ("m*(x*x+y*y)", 1)])
def test_a_xacro_is_read_directly_with_its_expansions_verdict(repo, capsys, izz, verdict):
    """Issue 53 item 5: relacc compare robot.urdf.xacro expands it with the xacro package (properties, macros, an
    argument) and gives its expansion's verdict; a finding is placed at the link's line in the xacro source (its name
    written there once), not in an expansion nobody has. --xacro-arg sets an argument."""
    import xacro

    from relacc.engines import judges

    path = repo / "robots" / "arm.urdf.xacro"
    path.write_text(XACRO.replace("${IZZ}", "${" + izz + "}"))
    (repo / "robots" / "good.urdf").unlink()
    (repo / "robots" / "bad.urdf").unlink()
    expanded = repo / "robots" / "expanded.urdf"
    expanded.write_text(xacro.process_file(str(path)).toprettyxml())
    assert main(["compare", str(expanded), "--states", "2", "--json"]) == verdict
    theirs = json.loads(capsys.readouterr().out)
    assert main(["compare", "robots/arm.urdf.xacro", "--states", "2", "--json", "--sarif", "s.sarif"]) == verdict
    mine = json.loads(capsys.readouterr().out)
    assert [f["condition"] for f in mine["findings"]] == [f["condition"] for f in theirs["findings"]]
    assert mine["compared"] == theirs["compared"] == ["relacc", *judges("urdf")] or verdict == 1
    if verdict:
        (found,) = [r for r in json.loads((repo / "s.sarif").read_text())["runs"][0]["results"]
                    if r["ruleId"] == "RELACC001" and "upper" in r["message"]["text"]]
        assert found["locations"][0]["physicalLocation"] == {"artifactLocation": {"uri": "robots/arm.urdf.xacro"},
                                                              "region": {"startLine": 11}}
    else:
        assert main(["compare", "robots/arm.urdf.xacro", "--states", "2", "--json", "--xacro-arg", "mass:=2.5"]) == 0
        heavier = json.loads(capsys.readouterr().out)
        links = {x["name"]: x["mass"] for x in heavier["geometry"]["relacc"]["links"]}
        assert links["upper"] == 2.5
        # the next command without it reads the default again (the argument stayed in the process for every later
        # command and Tree.from_file: seen when the full suite ran another xacro test after this one in one worker)
        assert main(["compare", "robots/arm.urdf.xacro", "--states", "2", "--json"]) == 0
        links = {x["name"]: x["mass"] for x in json.loads(capsys.readouterr().out)["geometry"]["relacc"]["links"]}
        assert links["upper"] == 1.0


@pytest.mark.slow
def test_the_pre_commit_hook_fails_on_a_non_physical_link_and_passes_once_it_is_fixed(tmp_path):
    """Issue 53 item 4: in a temporary git repository holding two URDFs (one with a link that breaks the triangle
    inequality) and a ROS package.xml, whose .pre-commit-config.yaml names relacc's hook, `pre-commit run
    --all-files` fails and names the link's file and line, skipping package.xml with a word; with the link fixed it
    passes. pre-commit installs relacc into its own environment once (its cache kept apart, in the test's directory)
    from a snapshot of this checkout, its uncommitted changes committed there as `pre-commit try-repo` does (which
    installs afresh at every call: two installs and two first compilations, 93-166 s of the test command).

    relacc alone is installed there (``PIP_NO_DEPS``); its dependencies are borrowed from this environment through
    ``PYTHONPATH``, as tests/test_installed.py borrows them. Installing them too took 1.5 GB of /tmp and 25 s, and
    once failed the CI run on a full disk; the dependency ranges are pip's to resolve, tested by the README's setup."""
    import os
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    env = {**os.environ, "PRE_COMMIT_HOME": str(tmp_path / "pre-commit-home"), "PIP_NO_DEPS": "1",
           "PYTHONPATH": os.pathsep.join(borrowed_site_dirs()), "GIT_AUTHOR_NAME": "t",
           "GIT_AUTHOR_EMAIL": "t@t", "GIT_COMMITTER_NAME": "t", "GIT_COMMITTER_EMAIL": "t@t"}

    def git(where, *args):
        return subprocess.run(["git", *args], cwd=where, check=True, capture_output=True, text=True, env=env).stdout

    hooks = tmp_path / "relacc"
    git(tmp_path, "clone", "-q", str(root), str(hooks))
    changed = git(root, "diff", "--name-only", "HEAD").split() + git(root, "ls-files", "--others",
                                                                      "--exclude-standard").split()
    for name in changed:
        (hooks / name).parent.mkdir(parents=True, exist_ok=True)
        if (root / name).exists():
            shutil.copyfile(root / name, hooks / name)
        elif (hooks / name).exists():
            (hooks / name).unlink()
    if changed:
        git(hooks, "add", "-A")
        git(hooks, "commit", "-qm", "uncommitted changes")
    rev = git(hooks, "rev-parse", "HEAD").strip()
    repo = tmp_path / "descriptions"
    (repo / "robots").mkdir(parents=True)
    (repo / "robots" / "good.urdf").write_text(GOOD)
    (repo / "robots" / "bad.urdf").write_text(BAD)
    (repo / "package.xml").write_text('<package format="2"><name>descriptions</name></package>')
    (repo / ".pre-commit-config.yaml").write_text(f"repos:\n  - repo: {hooks}\n    rev: {rev}\n    hooks:\n"
                                                  "      - id: relacc-compare\n")

    def hook():
        return subprocess.run([sys.executable, "-m", "pre_commit", "run", "--all-files"], cwd=repo,
                              capture_output=True, text=True, env=env, timeout=1500)

    git(repo, "init", "-q")
    git(repo, "add", "-A")
    git(repo, "commit", "-qm", "descriptions")
    out = hook()
    assert out.returncode == 1, out.stdout[-3000:]
    assert "robots/bad.urdf:2: body arm: principal moments that break the triangle inequality" in out.stdout
    assert "skipped 1 file that is not a robot description: package.xml" in out.stdout
    (repo / "robots" / "bad.urdf").write_text(GOOD.replace('"good"', '"bad"'))
    git(repo, "commit", "-qam", "fixed")
    out = hook()
    assert out.returncode == 0, out.stdout[-3000:]
    assert len(list((tmp_path / "pre-commit-home").glob("repo*"))) == 1, "pre-commit installed relacc twice"


def test_a_file_a_xacro_includes_is_an_input(repo, capsys):
    """A xacro's included files are the command's inputs, as an MJCF's <include>s are: an output naming one is refused
    up front (exit 2, one line) and the file is unchanged."""
    robots = repo / "robots"
    (robots / "inertial.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="box_inertial" params="m x y z">\n'
        '    <inertial><origin xyz="${x/2} 0 0"/><mass value="${m}"/>\n'
        '      <inertia ixx="${m*(y*y+z*z)/12}" ixy="0" ixz="0" iyy="${m*(x*x+z*z)/12}" iyz="0" '
        'izz="${m*(x*x+y*y)/12}"/></inertial>\n  </xacro:macro>\n</robot>\n')
    main_file = robots / "arm.urdf.xacro"
    main_file.write_text(XACRO.replace('<xacro:macro name="box_inertial"', '<xacro:include filename="inertial.xacro"/>'
                                       '<xacro:macro name="unused"').replace("${IZZ}", "0"))
    before = (robots / "inertial.xacro").read_bytes()
    assert main(["compare", str(main_file), "--states", "2", "--out", str(robots / "inertial.xacro")]) == 2
    out, err = capsys.readouterr()
    assert len(err.strip().splitlines()) == 1 and "inertial.xacro" in err, err
    assert (robots / "inertial.xacro").read_bytes() == before


def _arm_package(folder):
    """A ROS package ``arm_description`` in ``folder`` (its package.xml) with the box-inertial macro in urdf/."""
    (folder / "package.xml").write_text('<?xml version="1.0"?>\n<package format="3"><name>arm_description</name>'
                                        "<version>1.0.0</version></package>\n")
    (folder / "urdf" / "inertial.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="box_inertial" params="m x y z">\n'
        '    <inertial><origin xyz="${x/2} 0 0"/><mass value="${m}"/>\n'
        '      <inertia ixx="${m*(y*y+z*z)/12}" ixy="0" ixz="0" iyy="${m*(x*x+z*z)/12}" iyz="0" '
        'izz="${m*(x*x+y*y)/12}"/></inertial>\n  </xacro:macro>\n</robot>\n')


def test_find_and_package_uris_name_the_package_its_package_xml_names(tmp_path, monkeypatch, capsys):
    """ROS finds a package by the <name> of its package.xml, not by its folder's name: a description repository
    cloned under another name (a CI checkout is named after the repository) is still that package. Found on
    Makabeyuuat/cooperative_transportation_4ws_description (`063dd2c`), whose xacro includes
    $(find cooperative_transportation_4ws_description)/urdf/...: relacc refused it unless the clone's folder had the
    package's name. Here the folder is `checkout`; the xacro includes its inertial macro by $(find), and a package://
    mesh resolves there. A package that nothing names is one line naming it, not xacro's wrapping of relacc's
    message."""
    from relacc.reading.packages import package_folders
    from relacc.reading.urdf import resolve_uri

    checkout = tmp_path / "checkout"
    (checkout / "urdf").mkdir(parents=True)
    (checkout / "meshes").mkdir()
    (checkout / "meshes" / "part.stl").write_bytes(b"solid part\nendsolid part\n")
    _arm_package(checkout)
    arm = checkout / "urdf" / "arm.urdf.xacro"
    arm.write_text(XACRO.replace('<xacro:macro name="box_inertial"',
                                 '<xacro:include filename="$(find arm_description)/urdf/inertial.xacro"/>'
                                 '<xacro:macro name="unused"').replace("${IZZ}", "0"))
    (checkout / "arm_description").mkdir()  # an ament_python package's module folder, named like the package
    (checkout / "arm_description" / "__init__.py").write_text("")
    assert list(package_folders("arm_description", arm))[0] == checkout  # the manifest's folder, not the module's
    assert resolve_uri("package://arm_description/meshes/part.stl", arm) == checkout / "meshes" / "part.stl"
    assert resolve_uri("package://arm_description/meshes/none.stl", arm) is None
    monkeypatch.chdir(tmp_path)
    assert main(["compare", str(arm), "--states", "2", "--engines", "mujoco", "--json"]) == 0, capsys.readouterr()
    capsys.readouterr()
    arm.write_text(arm.read_text().replace("$(find arm_description)", "$(find other_description)"))
    assert main(["compare", str(arm), "--states", "2", "--engines", "mujoco"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.count("other_description") == 2, err
    assert "no package 'other_description' above the file" in err and "<class" not in err, err


def test_a_package_across_the_repository_or_in_ros_package_path_is_found(tmp_path, monkeypatch, capsys):
    """ROS finds a package anywhere in its workspace (colcon and rospack search every depth), not only beside the
    file's folders. Found on fiveages-sim/robot_descriptions (`f609e7f`): humanoid/ARX/lift_description's xacro
    includes $(find arx5_description), which lives in manipulator/ARX/: relacc refused 7 of its robots (exit 2). Now
    the file's repository (the folder holding .git) is searched as a workspace, a folder with a COLCON_IGNORE is
    skipped, and ROS_PACKAGE_PATH's folders are searched too. The robot read through the other package is the one
    the test writes: its inertia is the box macro's, checked against the closed form."""
    import os

    import numpy as np

    from relacc.reading import packages, read

    repo = tmp_path / "repo"
    arm = repo / "manipulator" / "vendor" / "arm_description"
    (arm / "urdf").mkdir(parents=True)
    _arm_package(arm)
    robot = repo / "humanoid" / "vendor" / "body_description" / "urdf" / "body.urdf.xacro"
    robot.parent.mkdir(parents=True)
    robot.write_text(XACRO.replace('<xacro:macro name="box_inertial"',
                                   '<xacro:include filename="$(find arm_description)/urdf/inertial.xacro"/>'
                                   '<xacro:macro name="unused"').replace("${IZZ}", "0"))
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.chdir(tmp_path)
    assert main(["compare", str(robot), "--states", "2", "--engines", "mujoco"]) == 2  # no repository yet
    assert "set ROS_PACKAGE_PATH" in capsys.readouterr().err
    (repo / ".git").mkdir()
    packages._crawled.cache_clear()
    assert list(packages.package_folders("arm_description", robot)) == [arm]
    (upper,) = [b for b in read(robot).tree.bodies if b.name == "upper"]
    m, x, y, z = 1.0, 0.3, 0.05, 0.05  # XACRO's upper link: box_inertial m=$(arg mass) x=${len} y=z=0.05
    # xacro writes the float it computes as repr (exact), so the two sides differ by a few ulp (8.7e-19) at most
    np.testing.assert_allclose(np.diag(upper.inertia), [m * (y * y + z * z) / 12, m * (x * x + z * z) / 12,
                                                        m * (x * x + y * y) / 12], rtol=0, atol=1e-15)
    (arm / "COLCON_IGNORE").touch()
    packages._crawled.cache_clear()
    assert list(packages.package_folders("arm_description", robot)) == []
    (repo / ".git").rmdir()
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "nothing") + os.pathsep + str(repo))
    (arm / "COLCON_IGNORE").unlink()
    packages._crawled.cache_clear()
    assert list(packages.package_folders("arm_description", robot)) == [arm]
    assert main(["compare", str(robot), "--states", "2", "--engines", "mujoco", "--json"]) == 0, capsys.readouterr()
    capsys.readouterr()
    monkeypatch.setattr(packages, "CRAWL_LIMIT", 3)  # a search cut short is said with the error, never silently
    packages._crawled.cache_clear()
    assert main(["compare", str(robot), "--states", "2", "--engines", "mujoco"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"the search of {repo} stopped after 3 folders" in err, err
    packages._crawled.cache_clear()


def test_models_only_skips_the_files_of_a_description_repository_that_hold_no_robot(tmp_path, monkeypatch, capsys):
    """A ROS description repository keeps its xacro macros and fragments beside the robots that include them:
    frankaemika/franka_description (`b299b39`: robots/common/franka_arm.xacro, utils.xacro, ...; a rigid tool,
    cobot_pump.urdf.xacro, whose one joint is fixed) and hello-robot's stretch_urdf (`c8c6e27`: stretch_aruco.xacro,
    whose joint names the base_link the main xacro defines). With the pre-commit hook's `--models-only`, each was
    "cannot be compared" (exit 2): the hook failed on every such repository whatever its robots. Now a xacro of
    macros (no <link>), a xacro fragment (joints naming links another file defines) and a description in which
    nothing moves are skipped, named on one line of stderr; a plain URDF whose joint names a missing link is still
    an error (exit 2), and without --models-only each is the error it was."""
    monkeypatch.chdir(tmp_path)
    head = '<?xml version="1.0"?>\n<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
    (tmp_path / "macros.xacro").write_text(head + '<xacro:macro name="m" params="n"><link name="${n}"/></xacro:macro>'
                                           '\n</robot>\n')
    (tmp_path / "fragment.xacro").write_text(head + '<link name="camera"/><joint name="mount" type="fixed">'
                                             '<parent link="base_link"/><child link="camera"/></joint>\n</robot>\n')
    (tmp_path / "tool.urdf").write_text('<robot name="tool"><link name="a"/><link name="b"/><joint name="w" '
                                        'type="fixed"><parent link="a"/><child link="b"/></joint></robot>')
    # a MuJoCo scene of a floor and lights (NASA-JSC-Robotics/surface_robotics_mockups_description `041036d`,
    # mujoco/cpc/scene.xml, the robot in another file): no <body> at all
    (tmp_path / "scene.xml").write_text('<mujoco><worldbody><light pos="0 0 2"/><geom type="plane" size="1 1 0.1"/>'
                                        "</worldbody></mujoco>")
    (tmp_path / "arm.urdf").write_text(GOOD)
    (tmp_path / "broken.urdf").write_text(GOOD.replace('<parent link="base"/>', '<parent link="nowhere"/>'))
    skipped = ["macros.xacro", "fragment.xacro", "tool.urdf", "scene.xml"]
    assert main(["compare", "--models-only", "--states", "2", *skipped, "arm.urdf", "broken.urdf"]) == 2
    out, err = capsys.readouterr()
    assert err.count("\n") == 1 and "skipped 4 files with no robot to compare" in err, err
    assert all(name in err for name in skipped), err
    assert "arm.urdf" in out and "broken.urdf" in out and "macros.xacro" not in out, out
    assert main(["compare", "--models-only", "--states", "2", *skipped, "arm.urdf"]) == 0
    capsys.readouterr()
    # a file that is not there is no "file that is not a robot description": a CI step's glob matching nothing
    # (`relacc compare --models-only robots/*.urdf` hands the pattern itself) was skipped with exit 0
    assert main(["compare", "--models-only", "--states", "2", "arm.urdf", "robots/*.urdf"]) == 2
    out, err = capsys.readouterr()
    assert "robots/*.urdf" in out + err and "not a robot description" not in err, (out, err)
    assert main(["compare", "--models-only", "--states", "2", "macros.xacro"]) == 0
    # every file skipped: the CI files asked for are written all the same (a CI step publishing them finds them)
    assert main(["compare", "--models-only", "--states", "2", "macros.xacro", "--junit", "j.xml", "--sarif",
                 "s.sarif"]) == 0
    suite = ET.parse(tmp_path / "j.xml").getroot().find("testsuite")
    assert suite.get("tests") == "0" and suite.get("failures") == "0"
    assert json.loads((tmp_path / "s.sarif").read_text())["runs"][0]["results"] == []
    capsys.readouterr()
    for name in skipped:
        assert main(["compare", "--states", "2", name]) == 2, name
        said = capsys.readouterr().err
        assert said.startswith("relacc compare: error: ") and said.count("\n") == 1, said


def test_an_xacro_arg_xacro_cannot_substitute_is_named_with_the_flag_that_gives_it(tmp_path, monkeypatch, capsys):
    """UniversalRobots' Universal_Robots_ROS2_Description (`2221ec0`): `ur.urdf.xacro` writes `<robot
    name="$(arg name)">` and declares `<xacro:arg name="name" default="ur"/>` inside it, after xacro has read the
    root's attributes: expanded without `name:=...`, as its own tests never do, xacro stops at "Undefined substitution
    argument name". relacc said only xacro's words; it now adds the flag that gives the argument, and with it the robot
    is compared."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "arm.urdf.xacro").write_text(
        '<?xml version="1.0"?>\n<robot name="$(arg prefix)robot" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '<xacro:arg name="prefix" default=""/>\n' + GOOD.split(">", 1)[1])
    assert main(["compare", "arm.urdf.xacro", "--states", "2"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "give it with --xacro-arg prefix:=VALUE" in err, err
    assert main(["compare", "arm.urdf.xacro", "--states", "2", "--json", "--xacro-arg", "prefix:=left_"]) == 0
    json.loads(capsys.readouterr().out)
    # inside an expression (wei-hsuan-cheng/robot_descriptions `df424af`: "Undefined substitution argument
    # ros2_control_hardware_type when evaluating expression ..."): the same flag, named
    (tmp_path / "arm.urdf.xacro").write_text(
        '<?xml version="1.0"?>\n<robot name="robot" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        "<xacro:if value=\"${'$(arg hardware)' == 'gz'}\"><link name=\"gz\"/></xacro:if>\n"
        + GOOD.split(">", 1)[1])
    assert main(["compare", "arm.urdf.xacro", "--states", "2"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "give it with --xacro-arg hardware:=VALUE" in err, err
