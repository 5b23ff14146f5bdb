"""The runs of ``mpcwalk bench solvers`` beside the table of solves, timed one at a time:
the MPC tick against the closed form and the qpmpc peer and qpbenchmark itself on the
exported test set each on a fresh timing actor (:func:`~mpcwalk.sweep.timing.run_isolated`:
one CPU, single-threaded, nothing beside it), and the closed loops (LIPM and MuJoCo) with
each back-end fast enough offline as Ray tasks run one at a time
(:func:`~mpcwalk.sweep.map_tasks` with one worker)."""

from dataclasses import asdict
from pathlib import Path

import numpy as np

from mpcwalk.bench.solvers.backends import OPTI_BACKEND
from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.bench.solvers.in_loop import LoopRun
from mpcwalk.bench.solvers.results import select
from mpcwalk.sweep import map_tasks
from mpcwalk.sweep.timing import run_isolated

#: qpsolvers back-ends left out of the reduced qpbenchmark run by default
#: (JAX-based: each solve recompiles, seconds per problem).
SLOW_QPBENCHMARK_SOLVERS = ("jaxopt_osqp", "qpax")


def fast_qpsolvers(rows: list[dict], config: SolverBenchConfig, limit: float = 2e-3) -> list[str]:
    """qpsolvers back-ends whose median on the mpc family's dense QP is under ``limit``."""
    import qpsolvers

    sel = select(
        rows, family="mpc", formulation="dense", tolerance="default", start="cold", success=True
    )
    fast = []
    for solver in qpsolvers.available_solvers:
        times = [r["runtime"] for r in sel if r["solver"] == solver and "main" in r["set"]]
        if times and np.median(times) < limit:
            fast.append(solver)
    return fast


def tick_benchmark(solvers: list[str], config: SolverBenchConfig) -> list[dict]:
    """Per-tick time of every generator with these MPC back-ends (:mod:`mpcwalk.bench.ticks`)."""
    from mpcwalk.bench.ticks import run_tick_benchmark

    results = run_tick_benchmark(
        nb_steps=config.nb_steps,
        control_period=config.control_period,
        solvers=solvers,
        include_peer=True,
        progress=False,
    )
    return [asdict(r) for r in results]


def loop_candidates(rows: list[dict], config: SolverBenchConfig) -> list[tuple[str, str]]:
    """(back-end, formulation) pairs fast enough on the loop's QP (family mpc)."""
    out = []
    sel = select(rows, family="mpc", tolerance="default", success=True)
    for formulation in config.formulations:
        for backend in dict.fromkeys(r["solver"] for r in sel):
            if backend == OPTI_BACKEND:
                continue
            mine = [
                r
                for r in sel
                if r["solver"] == backend and r["formulation"] == formulation and "main" in r["set"]
            ]
            warm = [r["runtime"] for r in mine if r["start"] == "warm"]
            times = warm or [r["runtime"] for r in mine]
            if times and np.median(times) < config.loop_backends_max_time:
                out.append((backend, formulation))
    return out


def loop_pair(backend: str, formulation: str, config: SolverBenchConfig) -> list[dict]:
    """Closed loops of one (back-end, formulation): on the LIPM, and in MuJoCo (a task)."""
    from mpcwalk.bench.solvers.in_loop import run_lipm_loop, run_mujoco_loop
    from mpcwalk.bench.solvers.tolerances import tolerance_levels

    level = tolerance_levels(config.time_limit)["default"]
    runs: list[LoopRun | None] = [
        run_lipm_loop(
            backend,
            formulation,
            level,
            nb_steps=config.loop_nb_steps,
            control_period=config.control_period,
            nb_pushes=config.loop_pushes,
            push_speed=config.loop_push_speed,
            seed=config.seed,
        )
    ]
    if config.mujoco_robot:
        runs.append(
            run_mujoco_loop(
                backend,
                formulation,
                level,
                robot=config.mujoco_robot,
                nb_steps=config.loop_nb_steps,
                control_period=config.control_period,
            )
        )
    out = []
    for run in runs:
        if run is not None:
            summary = run.summary()
            summary["solve_times_us"] = [round(t * 1e6, 1) for t in run.solve_times]
            out.append(summary)
    return out


def run_loops(rows: list[dict], config: SolverBenchConfig, progress: bool) -> dict:
    """The loops of the back-ends fast enough offline, one Ray task at a time (timed)."""
    from mpcwalk.bench.solvers.in_loop import mujoco_walk_runner

    pairs = loop_candidates(rows, config)
    tasks = [(loop_pair, (backend, formulation, config)) for backend, formulation in pairs]
    runs = [
        s
        for batch in map_tasks(tasks, workers=1, progress=progress, description="loops")
        for s in batch
    ]
    return {
        "lipm": [s for s in runs if s["plant"] == "lipm"],
        "mujoco": [s for s in runs if s["plant"] == "mujoco"],
        "mujoco_available": mujoco_walk_runner() is not None,
        "mujoco_robot": config.mujoco_robot,
    }


def _qpbenchmark_batch(out_dir: Path, config: SolverBenchConfig) -> dict:
    import qpsolvers

    from mpcwalk.bench.solvers.qpbenchmark_export import run_qpbenchmark

    solvers = list(config.qpbenchmark_solvers or ())
    if config.qpbenchmark_solvers is None:
        solvers = [s for s in qpsolvers.available_solvers if s not in SLOW_QPBENCHMARK_SOLVERS]
    summary = run_qpbenchmark(
        out_dir / "qpbenchmark", solvers=solvers, time_limit=config.time_limit
    )
    import qpbenchmark

    summary["solvers"] = list(solvers)
    summary["version"] = qpbenchmark.__version__
    return summary


def run_qpbenchmark_isolated(out_dir: Path, config: SolverBenchConfig) -> dict | None:
    """qpbenchmark on the exported test set, in an isolated process (None: no solver)."""
    try:
        import qpbenchmark  # noqa: F401
    except ImportError:
        return {"error": "qpbenchmark is not installed: pip install 'mpcwalk[bench]'"}
    if config.qpbenchmark_solvers == ():
        return None
    return run_isolated(_qpbenchmark_batch, out_dir, config)
