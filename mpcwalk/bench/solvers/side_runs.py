"""The runs of ``mpcwalk bench solvers`` beside the table of solves, each in a fresh
single-threaded process: the MPC tick against the closed form and the qpmpc peer, the closed
loops (LIPM and MuJoCo) with each back-end fast enough offline, and qpbenchmark itself on the
exported test set."""

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict
from pathlib import Path

import numpy as np

from mpcwalk.bench.solvers.backends import OPTI_BACKEND
from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.bench.solvers.in_loop import LoopRun
from mpcwalk.bench.solvers.results import select
from mpcwalk.walking.processes import single_thread_environment

#: qpsolvers back-ends left out of the reduced qpbenchmark run by default
#: (JAX-based: each solve recompiles, seconds per problem).
SLOW_QPBENCHMARK_SOLVERS = ("jaxopt_osqp", "qpax")


def _silence_stdout() -> None:  # pragma: no cover - runs in the child
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)


def run_isolated(function, *args, **kwargs):
    """Call ``function`` in a fresh single-threaded process (timed work)."""
    context = multiprocessing.get_context("spawn")
    with single_thread_environment():
        with ProcessPoolExecutor(1, mp_context=context, initializer=_silence_stdout) as pool:
            return pool.submit(function, *args, **kwargs).result()


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


def _loop_batch(
    pairs: list[tuple[str, str]], config: SolverBenchConfig, progress: bool = False
) -> dict[str, list[dict]]:
    """Closed loops of each (back-end, formulation): on the LIPM, and in MuJoCo."""
    from tqdm import tqdm

    from mpcwalk.bench.solvers.in_loop import run_lipm_loop, run_mujoco_loop
    from mpcwalk.bench.solvers.tolerances import tolerance_levels

    level = tolerance_levels(config.time_limit)["default"]
    out: dict[str, list[dict]] = {"lipm": [], "mujoco": []}
    for backend, formulation in tqdm(pairs, desc="loops", disable=not progress):
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
        for run in runs:
            if run is None:
                continue
            summary = run.summary()
            summary["solve_times_us"] = [round(t * 1e6, 1) for t in run.solve_times]
            out[run.plant].append(summary)
    return out


def run_loops(rows: list[dict], config: SolverBenchConfig, progress: bool) -> dict:
    """The loops of the back-ends fast enough offline, in an isolated process."""
    from mpcwalk.bench.solvers.in_loop import mujoco_walk_runner

    pairs = loop_candidates(rows, config)
    runs = run_isolated(_loop_batch, pairs, config, progress) if pairs else {}
    return {
        "lipm": runs.get("lipm", []),
        "mujoco": runs.get("mujoco", []),
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
