"""The inverse-dynamics stage of ``mpcwalk bench solvers`` (family ``inverse-dynamics``):
``inverse_dynamics.json.gz`` and ``inverse_dynamics.md`` in the output directory.

1. untimed, as Ray tasks one at a time: a torque-mode walk of each robot of
   ``dynamics_robots`` and the problems taken along it
   (:mod:`~mpcwalk.bench.solvers.dynamics.capture`);
2. timed, on one Ray timing actor (one CPU, nothing of the benchmark beside it): every case
   (problem x back-end x tolerance level x start,
   :mod:`~mpcwalk.bench.solvers.dynamics.solves`);
3. timed, one Ray task at a time: each back-end that succeeded offline as the solver of a
   torque walk of ``dynamics_loop_robot`` (:mod:`~mpcwalk.bench.solvers.dynamics.loops`);
4. the report (:mod:`~mpcwalk.bench.solvers.dynamics.report`).
"""

import os
import time
from dataclasses import asdict
from pathlib import Path

from mpcwalk.bench.output import machine_description
from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.bench.solvers.dynamics.capture import (
    DynamicsProblem,
    capture_walk,
    sample_dynamics_problems,
)
from mpcwalk.bench.solvers.dynamics.loops import loop_backends, run_dynamics_loop
from mpcwalk.bench.solvers.dynamics.report import write_dynamics_report, write_payload
from mpcwalk.bench.solvers.dynamics.solves import (
    dynamics_backends,
    dynamics_cases,
    run_dynamics_solves,
)
from mpcwalk.sweep import map_tasks
from mpcwalk.sweep.timing import run_isolated


def prepare_robot(robot: str, config: SolverBenchConfig) -> dict:
    """The walk of ``robot`` and its problems (a task of the preparation)."""
    walk = capture_walk(
        robot,
        nb_steps=config.dynamics_nb_steps,
        vx=config.dynamics_vx,
        control_period=config.control_period,
    )
    problems = sample_dynamics_problems(
        walk.recorder,
        robot,
        control_period=config.control_period,
        nb_per_phase=config.dynamics_nb_per_phase,
        nb_pushed=config.dynamics_nb_pushed,
        push_speed=config.dynamics_push_speed,
        warmup_ticks=config.warmup_ticks,
        seed=config.seed,
    )
    return {
        "robot": robot,
        "fell": walk.fell,
        "steps": walk.steps,
        "nb_ticks": len(walk.recorder.results),
        "problems": problems,
    }


def _problem_summary(problem: DynamicsProblem) -> dict:
    return {
        "name": problem.name,
        "robot": problem.robot,
        "tick": problem.tick,
        "time": problem.time,
        "phase": problem.phase,
        "pushed": problem.pushed,
        "push": [float(v) for v in problem.push],
        "n": problem.n,
        "m": problem.m,
        "m_eq": problem.qp.m_eq,
        "contacts": list(problem.qp.contacts),
    }


def run_dynamics_stage(
    config: SolverBenchConfig, out_dir: Path, *, progress: bool = True, command: str = ""
) -> dict:
    """Run the stage and write its two files (see the module docstring).

    Returns:
        The JSON payload (also in ``inverse_dynamics.json.gz``).
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    durations = {}
    load_before = os.getloadavg()[0]
    t0 = time.perf_counter()
    prepared = map_tasks(
        [(prepare_robot, (robot, config)) for robot in config.dynamics_robots],
        workers=1,
        progress=False,
    )
    problems = [p for walk in prepared for p in walk["problems"]]
    durations["prepare"] = time.perf_counter() - t0
    backends = dynamics_backends(config.backends)
    cases = dynamics_cases(
        problems, backends, config.levels, config.starts, config.time_limit, config.seed
    )
    t0 = time.perf_counter()
    rows = run_isolated(run_dynamics_solves, cases)
    durations["solves"] = time.perf_counter() - t0
    loops: list[dict] = []
    if config.dynamics_loop_robot:
        t0 = time.perf_counter()
        chosen = loop_backends(rows, config.dynamics_loop_robot, config.dynamics_loop_min_success)
        loops = map_tasks(
            [(_loop_task, (backend, config)) for backend in chosen],
            workers=1,
            progress=progress,
            description="torque walks",
        )
        durations["loops"] = time.perf_counter() - t0
    payload = {
        "command": command,
        "machine": machine_description(),
        "date": time.strftime("%Y-%m-%d"),
        "durations": durations,
        "load_average": {"before": load_before, "after": os.getloadavg()[0]},
        "cores": os.cpu_count(),
        "backends": backends,
        "walks": [{k: v for k, v in w.items() if k != "problems"} for w in prepared],
        "problems": [_problem_summary(p) for p in problems],
        "rows": rows,
        "loops": loops,
        "config": asdict(config),
    }
    write_payload(out_dir, payload)
    write_dynamics_report(out_dir, payload)
    return payload


def _loop_task(backend: str, config: SolverBenchConfig) -> dict:
    """One in-loop walk (a Ray task)."""
    return run_dynamics_loop(
        backend,
        robot=config.dynamics_loop_robot or "bioloid-like",
        nb_steps=config.dynamics_loop_nb_steps,
        vx=config.dynamics_vx,
        control_period=config.control_period,
    )
