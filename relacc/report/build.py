"""The agreement report's context, its scenes and its page (the package's docstring states what the page holds)."""

from __future__ import annotations

import datetime as dt
import os
import platform
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from jinja2 import Environment, PackageLoader, StrictUndefined, select_autoescape

from relacc import files, fixtures
from relacc.fixtures import shipped
from relacc.report.sections import SECTIONS
from relacc.validation.check import CheckReport, Harness
from relacc.validation.errata import Erratum, errata
from relacc.validation.hardcases import N_STATES as N_HARD
from relacc.validation.hardcases import Result, run_catalogue
from relacc.validation.hardsearch import Worst, hypothesis_search

DEFAULT_STATES = 2000
QUICK_STATES = 200
PHASES = {"first": 2.5, "first_alone": 2.0, "benchmarks": 6.7, "job_scale": 1.0, "parallel": 1.65, "page": 3.2,
          "page_alone": 5.2}
"""A full report's expected seconds on this project's 2-core machine with its kernels compiled, for the progress
messages' estimate (:class:`relacc.report.pool.Estimate`; measured 2026-11-29, docs/architecture.md "The report's
run"): the first phase with a second process (this one's cross-validation, and searches until the other has loaded
its kernels) and alone (the cross-validation); the two benchmarks; the jobs, their own costs (``Job.cost``) times
``job_scale``, ``parallel`` times faster on two processes than on one; the page with and without the sections drawn
while waiting."""
QUICK_PHASES = {"first": 1.0, "first_alone": 0.5, "benchmarks": 0.7, "job_scale": 0.17, "parallel": 1.65,
                "page": 3.0, "page_alone": 4.4}
"""The same for ``--quick``."""
DEFAULT_EXAMPLES = 300
QUICK_EXAMPLES = 40
DEFAULT_BENCH = (20_000, 5)
QUICK_BENCH = (2_000, 3)
DEFAULT_BATCHED = {"n_states": 20_000, "n_steps": 1000, "members": 200, "duration": 0.2, "repeats": 3}
QUICK_BATCHED = {"n_states": 2_000, "n_steps": 200, "members": 20, "duration": 0.05, "repeats": 3}
"""Sizes of the report's run of :mod:`relacc.tradeoff.batched` (recorded runs: ``benchmarks/batched.py``)."""


@dataclass(frozen=True)
class ReportContext:
    """Everything the sections read: the harness, its results and the run's metadata."""

    harness: Harness
    check: CheckReport
    errata: list[Erratum]
    hard: list[Result]
    worst: Worst
    throughput: dict
    batched: dict
    simulations: list
    tradeoff: object
    quick: bool
    created: dt.datetime
    machine: str
    drawn: dict = field(default_factory=dict)
    """Sections' data built ahead, by section ``ID`` (:func:`draw_ready`): :func:`render` uses them as they are."""

    def failures(self) -> list[str]:
        """One line per failed check the page shows: a cross-validation comparison, an erratum's corrected form, a
        hard case outside its accuracy model or not finite, the Hypothesis search's worst state when its error
        exceeds its bound (ratio above 1), a scene run (at its own step or a coarser one) where an engine's
        acceleration is not relacc's at the same states, and a scene whose engines' G2 positions at its own step
        differ by more than the page says they agree to. The page's verdict and the command's exit code are this
        list's."""
        from relacc.core.tolerances import EPS
        from relacc.report.sections.simulation import AGREEMENT_M

        out = [f"case {c.case} {c.engine}/{c.route} {c.quantity}: {c.max_error / EPS:.1f} eps"
               for c in self.check.failures]
        out += [f"{e.id}: corrected form off by {e.corrected_error:.2e}" for e in self.errata if not e.agrees]
        out += [f"hard case {r.name}, case {r.case}, {r.evaluator} {r.quantity}: "
                + (f"error / bound {r.max_ratio:.3g}" if r.finite else "not finite")
                for r in self.hard if not (r.passed and r.finite)]
        w = self.worst
        if not w.ratio <= 1.0:
            out.append(f"Hypothesis search: case {w.case}, {w.evaluator} {w.quantity}, error / bound {w.ratio:.3g} "
                       f"({w.error / EPS:.3g} eps against {w.bound / EPS:.3g} eps)")
        for e in self.simulations:
            r = e["result"]
            runs = [(r.scene.dt, r.differing)] + [(s["dt"], s["differing"]) for s in e["sweep"][1:]]
            out += [f"scene {r.scene.name} at dt = {dt:.3g} s: {name}'s acceleration off relacc's by {c['error']:.2e} "
                    f"(bound {c['bound']:.1e})" for dt, differing in runs for name, c in differing.items()]
            pos, _, _ = r.differences()
            if not pos <= AGREEMENT_M:
                out.append(f"scene {r.scene.name}: the engines' G2 positions differ by {pos:.2e} m at its own step "
                           f"(the page's claim: within {AGREEMENT_M:.0e} m)")
        return out

    @property
    def agrees(self) -> bool:
        """Every check the page shows passed (:meth:`failures` is empty)."""
        return not self.failures()


def _machine() -> str:
    from relacc.tradeoff.throughput import cpu_model

    return f"{platform.system()} {platform.machine()}, {os.cpu_count()} logical CPUs ({cpu_model()})"


def build_context(n_states: int | None = None, seed: int = 0, quick: bool = False,
                  model: str | os.PathLike | None = None, progress: Callable[[str], object] | None = None,
                  second: bool = False) -> ReportContext:
    """Run the cross-validation, the errata and every study the report shows.

    With ``second`` (``relacc report``'s default for a full report on a machine with two cores or more: see
    :func:`default_second`; from Python, a script that passes it must start under ``if __name__ == "__main__":``,
    since the second process is spawned and imports the main module) a second process
    (:mod:`relacc.report.pool`) compiles or loads the batched benchmark's and the scenes' kernels while this one does
    the throughput benchmark's, the cross-validation and the searches; then the throughput and batched benchmarks
    run alone on the machine; then the scenes, the integrator sweeps and whatever is left of the searches and the
    derivative sweep are jobs shared by both processes. Every result is the same either way (the timings aside);
    the trade-off section's times are then taken beside the other process (measured: 1-5% slower than alone).
    """
    from relacc import tradeoff as tradeoff_mod
    from relacc.report import pool
    from relacc.tradeoff import batched
    from relacc.tradeoff.throughput import run as run_benchmark

    n = n_states if n_states is not None else (QUICK_STATES if quick else DEFAULT_STATES)
    fixture = fixtures.load(model)
    plan = QUICK_PHASES if quick else PHASES
    procs = plan["parallel"] if second else 1.0  # how many times faster the jobs go
    first = plan["first"] if second else plan["first_alone"]
    profile = tradeoff_mod.QUICK if quick else tradeoff_mod.REPORT
    examples = QUICK_EXAMPLES if quick else DEFAULT_EXAMPLES
    scene_files, sweep_files = shipped.scene_paths("chain"), tradeoff_mod.scene_paths(profile)
    # expected seconds on this project's 2-core machine (the order the processes take them in)
    scene_cost = {"forced_damped": 4.1, "gimbal_spin": 2.3, "gravity_spring": 2.0, "tumbling": 1.0}
    sweep_cost = {"gravity_spring": 4.2, "gimbal_spin": 3.5, "forced_damped": 3.5, "tumbling": 0.8}
    hard_job = pool.Job("hard-case catalogue", run_catalogue, (fixture, None, N_HARD, seed), 1.7)
    search_job = pool.Job(f"Hypothesis search, {examples} examples", hypothesis_search, (fixture, examples, seed), 3.7)
    derivative_job = pool.Job("derivative sweep", tradeoff_mod.derivative_sweep, (fixture, profile, seed), 2.5)
    searches = [hard_job, derivative_job, search_job]  # the order this process takes them in while the other warms
    jobs = [pool.Job(f"scene {p.stem}", scene_entry, (p, quick), scene_cost.get(p.stem, 2.0)) for p in scene_files]
    jobs += [pool.Job(f"integrator sweep: {p.stem}", tradeoff_mod.scene_sweep, (p, profile),
                      sweep_cost.get(p.stem, 2.0)) for p in sweep_files]
    got: dict[str, Any] = {}
    work = sum(j.cost for j in jobs + searches) * plan["job_scale"]  # seconds of the jobs on one process
    say = pool.Estimate(progress or (lambda _: None), first, plan["benchmarks"] + work / procs
                        + plan["page" if second else "page_alone"])
    harness = Harness(fixture, n_states=n, seed=seed, progress=None if progress is None else say)
    with pool.Processes(second) as processes:
        # the second process compiles (or loads) the scenes' and the batched benchmark's kernels while this one does
        # the throughput benchmark's and the batched forward dynamics' (the second finds them in the cache when it
        # gets there), the cross-validation and, until the other is done, the searches and the derivative sweep
        # (what the cross-validation compiled is all they need); then the benchmarks run alone
        warm = processes.submit(pool.Job("kernels", warm_kernels, (fixture, seed)))
        if warm is not None:
            say("kernels of the benchmarks and the scenes, the second process compiling or loading its own")
            run_benchmark(WARM_STATES, 1, seed, fixture)
            batched.dynamics_rows(fixture, WARM_STATES, 1, seed)
        say("cross-validation")
        check, items = harness.check(), errata(harness)
        if warm is not None:
            for job in searches:
                if warm.done():
                    break
                say(job.label)
                got[job.label] = job.fn(*job.args)
            warm.result()
        say.add(first)
        say.drop(sum(j.cost for j in searches if j.label in got) * plan["job_scale"] / procs)  # done while warming
        n_bench, repeats = QUICK_BENCH if quick else DEFAULT_BENCH
        say(f"throughput, {n_bench} states per case")
        throughput = run_benchmark(n_bench, repeats, seed, fixture)
        sizes = dict(QUICK_BATCHED if quick else DEFAULT_BATCHED)
        say(f"dynamics and simulation against the engines' batched APIs, {sizes['n_states']} states")
        batched_result = batched.run(fixture, batched.tumbling(sizes["duration"], fixture), seed=seed,
                                     n_states=int(sizes["n_states"]), n_steps=int(sizes["n_steps"]),
                                     members=int(sizes["members"]), repeats=int(sizes["repeats"]))
        say.add(plan["benchmarks"])
        rest = [j for j in jobs + searches if j.label not in got]
        known = {"check": check, "errata": items, "throughput": throughput, "batched": batched_result}
        if hard_job.label in got and search_job.label in got:  # both done here
            known.update(hard=got[hard_job.label], worst=got[search_job.label])
        drawn: dict[str, Any] = {}
        got.update(zip((j.label for j in rest), processes.run(
            rest, progress=say, idle=[pool.Job("the sections drawn so far", draw_ready, (known, drawn))],
            finished=lambda job: say.add(job.cost * plan["job_scale"] / procs))))
    say("the page")
    simulations = [got[j.label] for j in jobs[:len(scene_files)]]
    sweeps = [got[j.label] for j in jobs[len(scene_files):]]
    hard, drows, worst = (got[j.label] for j in (hard_job, derivative_job, search_job))
    return ReportContext(
        harness=harness,
        check=check,
        errata=items,
        hard=hard,
        worst=worst,
        throughput=throughput,
        batched=batched_result,
        simulations=simulations,
        tradeoff=tradeoff_mod.assemble(drows, sweeps),
        quick=quick,
        created=dt.datetime.now(dt.timezone.utc),
        machine=_machine(),
        drawn=drawn,
    )


def draw_ready(known: dict, drawn: dict) -> None:
    """Into ``drawn``: each section's data whose ``READS`` are all in ``known`` (the context's fields known so far)."""
    from types import SimpleNamespace

    for m in SECTIONS:
        reads = getattr(m, "READS", None)
        if reads is not None and m.ID not in drawn and set(reads) <= set(known):
            drawn[m.ID] = m.build(SimpleNamespace(**{k: known[k] for k in reads}))


def default_second(quick: bool) -> bool:
    """``relacc report``'s default: a second process for a full report on a machine with two cores or more."""
    from relacc.report import pool

    return not quick and pool.cores() >= 2


WARM_STATES = 8
"""States of the benchmarks' runs that compile (or load) their kernels before they are timed."""


def warm_kernels(fixture, seed: int) -> None:
    """The kernels of the shipped scenes and of the batched benchmark compiled (or loaded from the cache): the
    bodies' kinematics without partials first (the engines' energies; nothing on the other process needs it), then
    a run of the batched benchmark too small to time, then each scene for two steps."""
    from relacc import simulate, tree_kinematics
    from relacc.simulate import scenes, subjects
    from relacc.tradeoff import batched

    loaded = [scenes.load(path) for path in shipped.scene_paths("chain")]
    first = loaded[0]
    tree_kinematics(first.subject_tree, 2, *subjects.reference_state(first, first.q, first.u), partials=False)
    batched.run(fixture, batched.tumbling(0.002, fixture), seed=seed, n_states=WARM_STATES, n_steps=2, members=2,
                repeats=1)
    for scene in loaded:
        simulate.run(scene.replace(duration=2 * scene.dt), keep=False)


SWEEP = (1, 2, 4, 8, 16)
"""Multiples of each scene's own step at which the report measures the engines' agreement."""


def scene_entry(path: str | os.PathLike, quick: bool) -> dict:
    """``{"result", "sweep"}``: a shipped scene at its own step, and its agreement at coarser steps (:data:`SWEEP`;
    each step's largest differences and the engines whose acceleration is not relacc's). Quick runs cap the scene at
    0.2 s and sweep two steps only."""
    from relacc import simulate
    from relacc.simulate import scenes

    scene = scenes.load(path)
    if quick:
        scene = scene.replace(duration=round(min(scene.duration, 0.2) / scene.dt) * scene.dt)
    result = simulate.run(scene)
    sweep = []
    for factor in (SWEEP[:2] if quick else SWEEP):
        dt = scene.dt * factor
        coarse = result if factor == 1 else simulate.run(scene.replace(
            dt=dt, duration=max(round(scene.duration / dt), 1) * dt))
        pos, vel, _ = coarse.differences()
        sweep.append({"dt": dt, "position": pos, "velocity": vel, "differing": coarse.differing})
    return {"result": result, "sweep": sweep}


def environment() -> Environment:
    """The Jinja2 environment of relacc's pages: the package's templates, autoescaped, strict."""
    return Environment(
        loader=PackageLoader("relacc", "report/templates"),
        autoescape=select_autoescape(["html", "j2"], default=True),
        undefined=StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )


def render(ctx: ReportContext) -> str:
    """The report's HTML text."""
    sections = [{"id": m.ID, "title": m.TITLE, "data": ctx.drawn[m.ID] if m.ID in ctx.drawn else m.build(ctx)}
                for m in SECTIONS]
    return environment().get_template("report.html.j2").render(sections=sections)


def build_report(out: str | os.PathLike = "reports/agreement.html", n_states: int | None = None, seed: int = 0,
                 quick: bool = False, model: str | os.PathLike | None = None,
                 progress: Callable[[str], object] | None = None, second: bool = False
                 ) -> tuple[Path, ReportContext]:
    """Run everything and write the report atomically.

    Returns:
        ``(path, ctx)``: the written file and the context it was made from.

    Raises:
        InputError: an output path that cannot be written (checked before
            the run). OutputError: the write failed; the previous file is
            unchanged. Any RelaccError of the run; nothing is written then.
    """
    path = files.check_output_file(out)
    ctx = build_context(n_states=n_states, seed=seed, quick=quick, model=model, progress=progress, second=second)
    html = render(ctx)
    path.parent.mkdir(parents=True, exist_ok=True)
    files.write_text(path, html)
    return path, ctx


__all__ = ["DEFAULT_BATCHED", "DEFAULT_BENCH", "DEFAULT_EXAMPLES", "DEFAULT_STATES", "QUICK_BATCHED", "QUICK_BENCH",
           "QUICK_EXAMPLES", "QUICK_STATES", "SWEEP", "ReportContext", "build_context", "build_report", "environment",
           "default_second", "render", "scene_entry"]
