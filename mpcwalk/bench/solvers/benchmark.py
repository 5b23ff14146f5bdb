"""``mpcwalk bench solvers``: every QP back-end on the walking QPs, offline and in the loop.

Stages, in order, so that nothing else of this benchmark runs while solves
are timed:

1. untimed, as Ray tasks, ``prep_workers`` at a time (:func:`~mpcwalk.sweep.map_tasks`):
   the reference walks, the problems sampled from them
   (:mod:`~mpcwalk.bench.solvers.problems.sampling`), a feasibility check of each
   (Clarabel on the sparse formulation; infeasible problems are dropped and listed), and
   the export of the qpbenchmark test set
   (:mod:`~mpcwalk.bench.solvers.peers.qpbenchmark_export`);
2. timed, on ``timing_workers`` Ray timing actors (default 1; one CPU each, one case at a
   time: :mod:`mpcwalk.sweep.timing`): every case (problem x formulation x back-end x
   tolerance level x start) through
   :class:`~mpcwalk.bench.solvers.solves.timed.TimedSolves`; rows go to ``results.csv.gz``;
3. timed, one at a time: per-tick time of every generator with the qpmpc peer
   (:mod:`~mpcwalk.bench.solvers.peers.ticks`) on a timing actor, then the in-loop walks,
   one Ray task at a time (:mod:`~mpcwalk.bench.solvers.loops.candidates`);
4. qpbenchmark itself on the exported set (reduced: a subset of solvers), on a timing actor
   (:mod:`~mpcwalk.bench.solvers.peers.qpbenchmark_run`);
5. the inverse-dynamics stage (family ``inverse-dynamics``): the whole-body inverse
   dynamics' QP of torque control, offline and in the loop, into ``inverse_dynamics.md``
   and ``.json`` (:mod:`~mpcwalk.bench.solvers.dynamics.stage`); with no other family, it
   runs alone;
6. the report and its figures (:mod:`~mpcwalk.bench.solvers.report.document`).
"""

import json
import shutil
import time
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from mpcwalk.bench.output import machine_description
from mpcwalk.bench.solvers.backends.registry import (
    KNOWN_SLOW_BACKENDS,
    OPTI_BACKEND,
    benchmark_backends,
    is_applicable,
    supports_warm_start,
)
from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.bench.solvers.dynamics.report import (
    DYNAMICS_FILE,
    DYNAMICS_REPORT,
    read_payload,
    write_dynamics_report,
)
from mpcwalk.bench.solvers.dynamics.stage import run_dynamics_stage
from mpcwalk.bench.solvers.loops.candidates import run_loops
from mpcwalk.bench.solvers.peers.qpbenchmark_run import run_qpbenchmark_isolated
from mpcwalk.bench.solvers.peers.ticks import fast_qpsolvers, tick_benchmark
from mpcwalk.bench.solvers.problems.families import WalkingProblem, get_family
from mpcwalk.bench.solvers.problems.sampling import reference_walk, sample_problems
from mpcwalk.bench.solvers.results import RESULTS_FILE, write_results
from mpcwalk.bench.solvers.solves.cases import SolverCase
from mpcwalk.bench.solvers.solves.timed import TimedSolves
from mpcwalk.bench.solvers.tolerances import select_levels
from mpcwalk.sweep import map_tasks
from mpcwalk.sweep.timing import run_isolated


def _reference_found(problem: WalkingProblem) -> bool:
    """Whether Clarabel (or another interior-point back-end) solves the problem."""
    import qpsolvers

    from mpcwalk.qp.solvers.registry import make_solver

    family = get_family(problem.family)
    qp = family.build_qp(problem.horizon, "sparse", problem.control_period)
    family.update_qp(qp, problem.state, problem.time, problem.schedule())
    name = next(
        (s for s in ("clarabel", "piqp", "proxqp") if s in qpsolvers.available_solvers),
        "osqp-direct",
    )
    return bool(make_solver(name).solve(qp).success)


def prepare_walk(family: str, walk: str, config: SolverBenchConfig) -> dict:
    """Reference walk, problems and their feasibility for one family and walk."""
    ref = reference_walk(family, walk, config.nb_steps, config.control_period)
    main_horizon = get_family(family).parameters.horizon
    sweep = family == config.sweep_family and walk == config.sweep_walk
    horizons = sorted({main_horizon} | (set(config.sweep_horizons) if sweep else set()))
    problems = sample_problems(
        ref,
        horizons,
        nb_nominal=config.nb_nominal,
        nb_pushed=config.nb_pushed,
        push_speed=config.push_speed,
        warmup_ticks=config.warmup_ticks,
        control_period=config.control_period,
        seed=config.seed,
    )
    nominal = list(dict.fromkeys(p.tick for p in problems if not p.pushed))
    pushed = list(dict.fromkeys(p.tick for p in problems if p.pushed))
    sweep_keys = {(t, False) for t in nominal[: config.sweep_nb_nominal]}
    sweep_keys |= {(t, True) for t in pushed[: config.sweep_nb_pushed]}
    kept: list[tuple[WalkingProblem, str]] = []
    dropped: list[tuple[WalkingProblem, str]] = []
    for p in problems:
        tags = ["main"] if p.horizon == main_horizon else []
        tags += ["sweep"] if sweep and (p.tick, p.pushed) in sweep_keys else []
        if not tags:
            continue
        (kept if _reference_found(p) else dropped).append((p, "+".join(tags)))
    return {
        "family": family,
        "walk": walk,
        "kept": kept,
        "dropped": dropped,
        "reference_failures": ref.nb_failures,
    }


def export_chunk(chunk: list, out_dir: Path, time_limit: float) -> list[str]:
    """Export some problems of the qpbenchmark test set (a task of the preparation)."""
    from mpcwalk.bench.solvers.peers.qpbenchmark_export import export_test_set

    return export_test_set(chunk, out_dir, time_limit=time_limit)


def make_cases(
    problems: list[tuple[WalkingProblem, str]], config: SolverBenchConfig, backends: list[str]
) -> list[SolverCase]:
    """Every case, by increasing horizon, cold before warm, shuffled otherwise
    (seeded) so that a drift of the machine's load spreads over all back-ends."""
    main_levels = select_levels(config.levels, config.time_limit)
    main_starts, sweep_starts = config.starts, config.sweep_starts
    sweep_levels = select_levels(config.sweep_levels, config.time_limit)
    sampled: dict[str, str] = {}  # family -> the one problem given to known slow back-ends
    for problem, tag in problems:
        if "main" in tag.split("+") and not problem.pushed:
            sampled.setdefault(problem.family, problem.name)
    cases = []
    for problem, tag in problems:
        tags = tag.split("+")
        levels = dict(main_levels) if "main" in tags else {}
        starts = list(main_starts) if "main" in tags else []
        if "sweep" in tags:
            levels.update(sweep_levels)
            starts += [s for s in sweep_starts if s not in starts]
        for formulation in config.formulations:
            for backend in backends:
                if not is_applicable(backend, formulation):
                    continue
                if backend == OPTI_BACKEND and problem.horizon > config.opti_max_horizon:
                    continue
                slow = backend in KNOWN_SLOW_BACKENDS
                if slow and sampled.get(problem.family) != problem.name:
                    continue
                for level in levels.values():
                    if slow and level.name != "default":
                        continue
                    for start in starts:
                        if start == "warm" and (slow or not supports_warm_start(backend)):
                            continue
                        cases.append(SolverCase(problem, formulation, backend, level, start, tag))
    rng = np.random.default_rng(config.seed)
    order = rng.permutation(len(cases))
    rank = np.empty(len(cases), dtype=int)
    rank[order] = np.arange(len(cases))
    return [
        cases[i]
        for i in sorted(
            range(len(cases)),
            key=lambda i: (cases[i].problem.horizon, cases[i].start == "warm", rank[i]),
        )
    ]


def run_solver_benchmark(
    config: SolverBenchConfig,
    out_dir: Path,
    *,
    progress: bool = True,
    command: str = "",
    loops: bool = True,
    qpbenchmark_run: bool = True,
) -> dict:
    """Run the benchmark and write ``results.csv.gz``, ``report.md`` and figures.

    Returns:
        A summary: paths, row count, durations of the stages [s].
    """
    from mpcwalk.bench.solvers.report.document import write_report

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    if not config.mpc_families:  # the inverse-dynamics stage alone
        t0 = time.perf_counter()
        payload = run_dynamics_stage(config, out_dir, progress=progress, command=command)
        return {
            "results": out_dir / DYNAMICS_FILE,
            "report": out_dir / DYNAMICS_REPORT,
            "rows": len(payload["rows"]),
            "durations": {"inverse-dynamics": time.perf_counter() - t0},
        }
    shutil.rmtree(out_dir / "qpbenchmark", ignore_errors=True)  # no stale problems or results
    durations: dict[str, float] = {}
    backends = list(config.backends) if config.backends else benchmark_backends()
    t0 = time.perf_counter()
    walks = [
        (f, w)
        for f in dict.fromkeys(config.mpc_families + (config.sweep_family,))
        for w in dict.fromkeys(config.walks + (config.sweep_walk,))
        if (f in config.mpc_families and w in config.walks)
        or (f == config.sweep_family and w == config.sweep_walk)
    ]
    prepared = map_tasks(
        [(prepare_walk, (f, w, config)) for f, w in walks],
        workers=config.prep_workers,
        progress=False,
    )
    problems = [item for p in prepared for item in p["kept"]]
    export = [
        (p, f)
        for p, tag in problems
        for f in config.formulations
        if p.horizon <= config.export_max_horizon
    ]
    chunks = [export[i :: config.prep_workers] for i in range(config.prep_workers)]
    exported = map_tasks(
        [
            (export_chunk, (chunk, out_dir / "qpbenchmark", config.time_limit))
            for chunk in chunks
            if chunk
        ],
        workers=config.prep_workers,
        progress=False,
    )
    nb_exported = sum(len(names) for names in exported)
    durations["prepare"] = time.perf_counter() - t0

    cases = make_cases(problems, config, backends)
    t0 = time.perf_counter()
    rows = TimedSolves(config.timing_workers).run(cases, progress=progress, desc="solves")
    durations["solves"] = time.perf_counter() - t0
    write_results(rows, out_dir / RESULTS_FILE)

    extras: dict = {
        "prepared": [
            {k: v for k, v in p.items() if k not in ("kept", "dropped")}
            | {"nb_kept": len(p["kept"]), "dropped": [q.name for q, _ in p["dropped"]]}
            for p in prepared
        ],
        "nb_exported": nb_exported,
        "backends": backends,
    }
    if config.ticks:
        t0 = time.perf_counter()
        extras["ticks"] = run_isolated(tick_benchmark, fast_qpsolvers(rows, config), config)
        durations["ticks"] = time.perf_counter() - t0
    if loops:
        t0 = time.perf_counter()
        extras["loops"] = run_loops(rows, config, progress)
        durations["loops"] = time.perf_counter() - t0
    if qpbenchmark_run and nb_exported:
        t0 = time.perf_counter()
        extras["qpbenchmark"] = run_qpbenchmark_isolated(out_dir, config)
        durations["qpbenchmark"] = time.perf_counter() - t0
    if config.dynamics:
        t0 = time.perf_counter()
        run_dynamics_stage(config, out_dir, progress=progress, command=command)
        durations["inverse-dynamics"] = time.perf_counter() - t0
    extras["durations"] = durations
    extras["machine"] = machine_description()
    extras["command"] = command
    extras["config"] = asdict(config)
    (out_dir / "extras.json").write_text(
        json.dumps(extras, separators=(",", ":"), default=str) + "\n"
    )
    write_report(out_dir, rows, config, extras)
    return {
        "results": out_dir / RESULTS_FILE,
        "report": out_dir / "report.md",
        "rows": len(rows),
        "durations": durations,
    }


def rewrite_report(out_dir: Path) -> Path:
    """Write ``report.md`` and the figures again from ``results.csv.gz`` and
    ``extras.json`` of a finished run (no solve is made), and ``inverse_dynamics.md`` from
    its payload when the run has one (alone when it is all the run has)."""
    from mpcwalk.bench.solvers.report.document import write_report
    from mpcwalk.bench.solvers.results import read_results

    out_dir = Path(out_dir)
    if (out_dir / DYNAMICS_FILE).exists():
        dynamics = write_dynamics_report(out_dir, read_payload(out_dir))
        if not (out_dir / "extras.json").exists():  # the inverse-dynamics stage alone
            return dynamics
    extras = json.loads((out_dir / "extras.json").read_text())
    fields: dict[str, Any] = {
        k: tuple(v) if isinstance(v, list) else v for k, v in extras.get("config", {}).items()
    }
    config = SolverBenchConfig(**fields)
    return write_report(out_dir, read_results(out_dir / RESULTS_FILE), config, extras)
