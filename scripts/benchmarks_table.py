"""Write docs/benchmarks.md's table of the latest recorded run of every benchmark, from benchmarks/results/ (the
history: every run, each with its machine, date and commit); tests/test_readme.py checks the table is current.

Run:  python scripts/benchmarks_table.py
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from relacc.fixtures.shipped import latest_recorded

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
DOC = ROOT / "docs" / "benchmarks.md"
MARKS = ("<!-- latest-runs -->\n", "\n<!-- /latest-runs -->")


def _span(values, fmt="{:.1f}") -> str:
    values = sorted(values)
    low, high = fmt.format(values[0]), fmt.format(values[-1])
    return low if low == high else f"{low}-{high}"


def _throughput(d) -> str:
    rows = [r for r in d["rows"] if r["output"] == "acceleration" and r["who"] not in ("relacc", "relacc-1-thread",
                                                                                        "relacc-reference")]
    engines = sorted({r["who"] for r in rows})
    return "G2's acceleration, relacc's batch over each engine's loop from Python: " + "; ".join(
        f"{e} {_span([r['relacc_speedup_over_this'] for r in rows if r['who'] == e])}x (cases 1-3)" for e in engines)


def _batched(d) -> str:
    import sys

    sys.path.insert(0, str(ROOT))
    from relacc.engines import anchors
    from relacc.tradeoff.batched import ratios

    r = ratios(d)
    return (f"the note's chain at {r['threads']} threads, relacc faster than: the batched forward dynamics "
            f"({anchors('batched_forward')[0]}, relacc's slowest case) {r['dynamics']:.1f}x; ensembles "
            f"({anchors('rollout')[0]}) {r['ensemble']:.1f}x; a step per call ({anchors('step')[0]}) {r['step']:.1f}x; "
            f"one state's compiled loop {r['step_loop']:.1f}x")


def _trees(d) -> str:
    parts = []
    for model, entry in d["ratios"].items():
        aba = [v for k, v in entry.items() if k.startswith("dynamics vs")]
        if aba:
            parts.append(f"{model} {aba[0][0]:.1f}x")
    return "relacc's forward dynamics faster than the batched anchor (abaInParallel): " + ", ".join(parts)


def _gym_models(d) -> str:
    ratios = [r["abaInParallel_us"]["median"] / r["relacc_us"]["median"] for r in d["rows"]
              if r.get("abaInParallel_us") and r.get("relacc_us")]
    return (f"relacc's forward dynamics faster than abaInParallel on {len(d['rows'])} gymnasium models: "
            f"{_span(ratios)}x")


def _single(d) -> str:
    calls = ", ".join(f"{r['model']} {r['relacc']['median_us']:.1f} us against pin.aba's "
                      f"{r['pinocchio_aba']['median_us']:.1f}" + (f" ({r['ratio']:.2f}x)" if "ratio" in r else "")
                      for r in d["one_call"])
    runs = ", ".join(f"{r['scene']} {r['ratio_to_mujoco']:.1f}x mujoco.rollout" for r in d["one_trajectory"])
    return f"one state's forward dynamics: {calls}; one trajectory: {runs}"


def _threads(d) -> str:
    rows = [r for r in d["rows"] if r["states"] >= 1000] or d["rows"]
    return f"all cores over one thread, {len(d['rows'])} calls and batch sizes: {_span([r['ratio'] for r in rows])}x " \
           "(batches of 1,000 states or more)"


def _lanes(d) -> str:
    return ", ".join(f"{r['layout']} {r['gflops']:.1f} GFlop/s" for r in d["rows"]) + f" ({d['links']}-link chain)"


def _chain_form(d) -> str:
    text = ("the chain's fused kernel over the tree kernels on its tree, a step: "
            f"{_span([r['ratio_of_medians'] for r in d['rows']])}x faster")
    fd = [r for r in d.get("forward", []) if r["effects"] == "gravity"]
    if fd:
        text += ("; its forward dynamics over the lanes kernel's, gravity alone, a batch: "
                 f"{_span([r['tree_batch_us'] / r['chain_batch_us'] for r in fd])}x; one state's G2 kinematics "
                 f"{_span([r['note_g2_single_us'] for r in fd])} us")
    return text


def _tiers(d) -> str:
    return "the test command: " + "; ".join(f"{r['tier']} {r['seconds']:.0f} s ({r['counts'].get('passed', 0)} passed)"
                                             for r in d["rows"])


def _kernels_ab(d) -> str:
    rows = {(r["case"], r["checkout"], r["what"]): r["median_ns"] for r in d["rows"]}
    return "the note's G2 kernels over another checkout's, one thread: " + "; ".join(
        f"{what} {_span([rows[(c, 'old', what)] / rows[(c, 'new', what)] for c in (1, 2, 3)], '{:.2f}')}x"
        for what in ("every output", "acceleration"))


def _cluster(d) -> str:
    return "states per second on Dask: " + ", ".join(
        f"{n} worker{'s' if int(n) > 1 else ''} {w['states_per_second']:,.0f}" for n, w in d["workers"].items())


def _ensembles(d) -> str:
    return f"{d['scene']}, {d['members']} members: " + ", ".join(
        f"{r['engine']} {r['median_steps_per_s']:,.0f} steps/s ({r['threads']} thread{'s' if r['threads'] > 1 else ''})"
        for r in d["rows"])


def _first_run(d) -> str:
    return ", ".join(f"{k} {v:.0f} s" if v >= 10 else f"{k} {v:.1f} s" for k, v in d["seconds"].items())


def _compile_seconds(d) -> str:
    return "first compilation on a cold numba cache: " + ", ".join(
        f"{k} {v['seconds']:.0f} s ({len(v['kernels'])} kernels)" for k, v in d["commands"].items() if v["kernels"])


def _waits(d) -> str:
    calls = ", ".join(f"{Path(r['model'].split()[-1]).name} {r['median_s']:.1f} s"
                      + (f" ({r['files']} files, {r['median_s_per_file']:.2f} s a file)" if "files" in r else "")
                      for r in d["compare"])
    slow = max(d["simulate"], key=lambda r: r["best_s"])
    return (f"relacc compare as a command: {calls} (median); slowest engine run of a chain scene: {slow['engine']} "
            f"{slow['scene']} {slow['best_s']:.1f} s ({slow['steps']} steps)")


def _flops(d) -> str:
    rows = ", ".join(f"{r['model']} {r['flops']:,} flops a state at {r['gflops']:.1f} GFlop/s "
                     f"({r['fraction_of_peak']:.2f} of peak)"
                     for r in d["rows"])
    return f"the lanes kernel on one thread against the {d['peak_gflops']:.0f} GFlop/s FMA peak: {rows}"


BENCHMARKS = {"throughput": ("benchmarks/throughput.py", _throughput), "batched": ("benchmarks/batched.py", _batched),
              "trees": ("benchmarks/trees.py", _trees), "gym-models": ("benchmarks/gym_models.py", _gym_models),
              "single": ("benchmarks/single.py", _single), "threads": ("benchmarks/threads.py", _threads),
              "lanes": ("benchmarks/lanes.py", _lanes), "chain-form": ("benchmarks/chain_form.py", _chain_form),
              "cluster": ("benchmarks/cluster.py", _cluster), "ensembles": ("benchmarks/ensembles.py", _ensembles),
              "first-run": ("benchmarks/first_run.py", _first_run), "waits": ("benchmarks/waits.py", _waits),
              "flops": ("benchmarks/flops.py", _flops), "kernels-ab": ("benchmarks/kernels_ab.py", _kernels_ab),
              "tiers": ("benchmarks/tiers.py", _tiers),
              "compile-seconds": ("benchmarks/first_compile.py", _compile_seconds)}
"""Each benchmark's result prefix, its script and its headline."""


def latest(prefix: str) -> Path:
    """The latest recorded run of a benchmark: the latest date, then the highest run number."""
    found = latest_recorded(prefix, RESULTS)
    if found is None:
        raise SystemExit(f"no recorded run of {prefix} in {RESULTS}")
    return found


def _machine(d) -> tuple[str, str, str]:
    m = d.get("machine", d)
    cpus = f", {m['logical_cpus']} CPUs" if m.get("logical_cpus") else ""
    return (m.get("date", ""), f"{m.get('cpu', '')}{cpus}",
            m.get("relacc_commit") or m.get("commit") or "-")


def table() -> str:
    lines = ["| benchmark | latest run | date | machine | commit | headline (medians) |", "|---|---|---|---|---|---|"]
    for prefix, (script, headline) in BENCHMARKS.items():
        path = latest(prefix)
        d = json.loads(path.read_text())
        date, machine, commit = _machine(d)
        lines.append(f"| [`{script}`](../{script}) | `{path.name}` | {date} | {machine} | `{commit}` | "
                     f"{headline(d)} |")
    return "\n".join(lines)


def main() -> None:
    text = DOC.read_text()
    start, end = MARKS
    text = re.sub(rf"({re.escape(start)}).*?({re.escape(end)})", lambda m: m.group(1) + table() + m.group(2), text,
                  flags=re.S)
    DOC.write_text(text)
    print(f"updated {DOC}")


if __name__ == "__main__":
    main()
