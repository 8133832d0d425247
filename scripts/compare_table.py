"""Rewrite docs/compare.md's tables from ``relacc compare``: gymnasium's MuJoCo assets, and models outside that
set from the engines' own pip packages (tests/test_compare.py checks both tables are current).

Run:  python scripts/compare_table.py          (needs gymnasium: pip install -e .[gymnasium])
"""

import re
import sys
from pathlib import Path

DOC = Path(__file__).resolve().parents[1] / "docs" / "compare.md"
STATES, SEED = 20, 0

SHORT = {  # a cause's words -> its label in the table
    "settotalmass": "ignores settotalmass",
    "first <body> written": "reads only the first worldbody body",
    "first <body> that has no joint": "puts a jointless first body at the world frame",
    "inherited from a <default>": "ignores a default class's geom mass",
    "gives a mesh geom 1 kg": "unit mesh inertia",
    "mujoco#3559": "drops a URDF inertial's rotation",
    "drops the inertia of a massless body": "drops a massless body's inertia",
    "a mass of 1 kg": "gives a massless link 1 kg",
    "drops a free joint's damping": "drops a free joint's damping",
    "flag gravity": "ignores flag gravity=disable",
    "mj_jacDot": "MuJoCo's mj_jacDot",
    "contype=0": "leaves contype=0 geoms out of the inertia",
    "<option gravity>": "ignores option gravity",
    "armature only": "armature only with <motor>/<position>",
    "several joints in the parent": "stacked joints in the parent's frame",
    "JointModelComposite": "composite-joint J_dot v",
    "no inertia moves": "mass matrix singular (a speed with no inertia)",
    "leaves a root link": "URDF root link left free",
}


def labels(cause: str) -> set[str]:
    if "not explained" in cause:
        return {"UNEXPLAINED"}
    found = {short for words, short in SHORT.items() if words in cause}
    return found or {"UNEXPLAINED"}


def words(message: str, path: Path, shown: str) -> str:
    """An engine's message without this machine's paths: the model's shown name, the parser's own words."""
    text = " ".join(message.replace(str(path), shown).replace(str(path.parent) + "/", "").split())
    return re.sub(r"From file: \S+ in function: .*? message: ", "", text)


def gymnasium_models() -> list[tuple[str, Path]]:
    """``(shown name, path)`` of gymnasium's MuJoCo assets."""
    import gymnasium

    assets = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
    return [(path.name, path) for path in sorted(assets.glob("*.xml"))]


OTHERS = (("mujoco", "testdata/model.xml"), ("mujoco", "testdata/msh.xml"), ("mujoco", "testdata/model.urdf"),
          ("pydrake", "share/drake/examples/acrobot/Acrobot.urdf"),
          ("pydrake", "share/drake/examples/acrobot/Acrobot_no_collision.urdf"),
          ("pydrake", "share/drake/examples/pendulum/Pendulum.urdf"))
"""Models outside gymnasium, from the engines' own pip packages: (package, path inside it)."""


def other_models() -> list[tuple[str, Path]]:
    """``(shown name, path)`` of :data:`OTHERS`, found in the installed packages."""
    import importlib.util

    return [(f"{package}: {inside}", Path(importlib.util.find_spec(package).origin).parent / inside)
            for package, inside in OTHERS]


def table(models=None) -> str:
    """The markdown table: one row per model (default: gymnasium's assets), one column group per engine."""
    from relacc.errors import ModelError
    from relacc.validation.robots import compare

    lines = ["| model | relacc nv | engine | reads it (nv) | audit differences: causes "
             "| dynamics outside tolerance: causes | exit |", "|---|---|---|---|---|---|---|"]
    for shown, path in gymnasium_models() if models is None else models:
        try:
            result = compare(path, n_states=STATES, seed=SEED)
        except ModelError as exc:
            lines.append(f"| `{shown}` | - | - | no: {words(str(exc), path, shown)} | | | 2 |")
            continue
        nv = result.engines["relacc"].nv
        for k, (name, report) in enumerate((n, r) for n, r in result.engines.items() if n != "relacc"):
            first = k == 0
            head = f"| `{shown}` | {nv} |" if first else "| | |"
            if not report.loaded:
                why = words(report.error, path, shown).split(" cannot read it: ", 1)[-1]
                lines.append(f"{head} {name} | no: {why} | | | {result.exit_code if first else ''} |")
                continue
            items = [a for a in result.audit if name in a.values]
            causes = sorted(set().union(*[labels(c.split(": ", 1)[1]) for a in items for c in a.cause.split("; ")
                                          if c.startswith(name + ":")]))
            bad = {q: r[name] for q, r in result.dynamics.items() if name in r and not r[name].passed}
            dyn = sorted(set().union(*[labels(r.cause) for r in bad.values()]))
            audit = f"{len(items)}: {'; '.join(causes)}" if items else "0"
            dynamics = f"{len(bad)} of {len(result.dynamics)}: {'; '.join(dyn)}" if bad else "none"
            lines.append(f"{head} {name} | yes ({report.nv}) | {audit} | {dynamics} | "
                         f"{result.exit_code if first else ''} |")
    return "\n".join(lines)


def rewrite() -> None:
    from relacc.files import write_text

    text = DOC.read_text()
    for marker, models in (("gymnasium", None), ("others", other_models())):
        text = re.sub(rf"(<!-- compare:{marker} -->\n).*?(\n<!-- /compare:{marker} -->)",
                      lambda m: m.group(1) + table(models) + m.group(2), text, flags=re.S)
    new = text
    write_text(DOC, new)
    print(f"updated {DOC}")


if __name__ == "__main__":
    sys.exit(rewrite())
