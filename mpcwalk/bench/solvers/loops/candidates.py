"""The closed loops of ``mpcwalk bench solvers``: the back-ends fast enough offline
(:func:`loop_candidates`), each in the loop on the LIPM and in MuJoCo
(:mod:`mpcwalk.bench.solvers.loops.plants`), as Ray tasks run one at a time
(:func:`~mpcwalk.sweep.map_tasks` with one worker), after the table of solves."""

import numpy as np

from mpcwalk.bench.solvers.backends.registry import OPTI_BACKEND
from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.bench.solvers.loops.plants import LoopRun
from mpcwalk.bench.solvers.results import select
from mpcwalk.sweep import map_tasks


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
    from mpcwalk.bench.solvers.loops.plants import run_lipm_loop, run_mujoco_loop
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
    from mpcwalk.bench.solvers.loops.plants import mujoco_walk_runner

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
