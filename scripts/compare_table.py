"""Rewrite docs/compare.md's table of gymnasium's MuJoCo assets from ``relacc compare`` (tests/test_compare.py
checks the table is current).

Run:  python scripts/compare_table.py          (needs gymnasium: pip install -e .[gymnasium])
"""

import re
import sys
from pathlib import Path

DOC = Path(__file__).resolve().parents[1] / "docs" / "compare.md"
STATES, SEED = 20, 0

SHORT = {  # a cause's words -> its label in the table
    "settotalmass": "ignores settotalmass",
    "first <body>": "reads only the first worldbody body",
    "contype=0": "leaves contype=0 geoms out of the inertia",
    "<option gravity>": "ignores option gravity",
    "armature only": "armature only with a motor",
    "several joints in the parent": "stacked joints in the parent's frame",
    "JointModelComposite": "composite-joint J_dot v",
}


def labels(cause: str) -> set[str]:
    found = {short for words, short in SHORT.items() if words in cause}
    return found or {"UNEXPLAINED"}


def table() -> str:
    """The markdown table: one row per asset, one column group per engine."""
    import gymnasium

    from relacc.errors import ModelError
    from relacc.validation.robots import compare

    assets = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
    lines = ["| model | MuJoCo nv | engine | loads (nv) | audit differences: causes "
             "| dynamics outside tolerance: causes | exit |", "|---|---|---|---|---|---|---|"]
    for path in sorted(assets.glob("*.xml")):
        try:
            result = compare(path, n_states=STATES, seed=SEED)
        except ModelError as exc:
            lines.append(f"| `{path.name}` | - | - | {exc} | | | 2 |")
            continue
        nv = result.engines["mujoco"].nv
        for k, (name, report) in enumerate((n, r) for n, r in result.engines.items() if n != "mujoco"):
            first = k == 0
            head = f"| `{path.name}` | {nv} |" if first else "| | |"
            if not report.loaded:
                why = report.error.rsplit("error: ", 1)[-1]  # the parser's words, not this machine's path
                lines.append(f"{head} {name} | no: {why} | | | {result.exit_code if first else ''} |")
                continue
            items = [a for a in result.audit if name in a.values]
            causes = sorted(set().union(*[labels(c.split(": ", 1)[1]) for a in items for c in a.cause.split("; ")
                                          if c.startswith(name + ":")]))
            bad = {q: r[name] for q, r in result.dynamics.items() if name in r and not r[name]["ok"]}
            dyn = sorted(set().union(*[labels(r["cause"]) for r in bad.values()]))
            audit = f"{len(items)}: {'; '.join(causes)}" if items else "0"
            dynamics = f"{len(bad)} of {len(result.dynamics)}: {'; '.join(dyn)}" if bad else "none"
            lines.append(f"{head} {name} | yes ({report.nv}) | {audit} | {dynamics} | "
                         f"{result.exit_code if first else ''} |")
    return "\n".join(lines)


def rewrite() -> None:
    from relacc.files import write_text

    text = DOC.read_text()
    new = re.sub(r"(<!-- compare:gymnasium -->\n).*?(\n<!-- /compare:gymnasium -->)",
                 lambda m: m.group(1) + table() + m.group(2), text, flags=re.S)
    write_text(DOC, new)
    print(f"updated {DOC}")


if __name__ == "__main__":
    sys.exit(rewrite())
