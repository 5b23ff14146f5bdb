"""The MPC tick of ``mpcwalk bench solvers`` against the closed form and the qpmpc peer
(:mod:`mpcwalk.bench.ticks`), with the qpsolvers back-ends fast enough offline, run after
the table of solves on a fresh timing actor (:func:`~mpcwalk.sweep.timing.run_isolated`:
one CPU, single-threaded, nothing beside it)."""

from dataclasses import asdict

import numpy as np

from mpcwalk.bench.solvers.config import SolverBenchConfig
from mpcwalk.bench.solvers.results import select


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
