"""Each back-end as the inverse dynamics' solver in a torque-mode walk in MuJoCo.

The walk is ``mpcwalk walk --robot R --controller mpc --actuation torque --dynamics-solver
NAME`` (the controller option ``dynamics_solver``; the back-end's registry defaults, as a
user gets them), run by the project's walk runner; its inverse dynamics is swapped, before
the walk, for one that records the result of each tick
(:func:`~mpcwalk.bench.solvers.dynamics.capture.recorded_torque_walk`, same back-end and
gains).
"""

import numpy as np

from mpcwalk.bench.solvers.dynamics.capture import recorded_torque_walk

#: The columns of an in-loop run, in the order of the report's table.
LOOP_FIELDS = (
    "backend",
    "robot",
    "steps",
    "fell",
    "fall_reason",
    "dynamics_failures",
    "nb_ticks",
    "tick_median_us",
    "tick_p99_us",
    "solve_median_us",
    "solve_p99_us",
    "real_time_factor",
    "foot_position_error_cm_max",
    "error",
)


def _percentile(values: np.ndarray, q: float) -> float:
    return float(np.percentile(values, q)) if len(values) else float("nan")


def run_dynamics_loop(
    backend: str,
    *,
    robot: str = "bioloid-like",
    nb_steps: int = 20,
    vx: float = 0.1,
    control_period: float = 0.01,
) -> dict:
    """One torque-mode walk with ``backend`` as the inverse dynamics' solver (keys:
    :data:`LOOP_FIELDS`; times in [us], the whole inverse-dynamics tick and the back-end's
    solve); an error of the set-up or the back-end ends the run as a failure, never raises."""
    run: dict = dict.fromkeys(LOOP_FIELDS) | {"backend": backend, "robot": robot}
    try:
        result, recorder = recorded_torque_walk(
            robot,
            nb_steps=nb_steps,
            vx=vx,
            control_period=control_period,
            dynamics_solver=backend,
            keep_states=False,
        )
    except Exception as error:
        run["error"] = f"{type(error).__name__}: {' '.join(str(error).split())[:140]}"
        run["fell"] = True
        return run
    metrics = result.metrics
    results = recorder.results
    ticks = np.array([r.solve_time for r in results]) * 1e6
    solves = np.array([r.qp_time for r in results]) * 1e6
    run.update(
        steps=f"{metrics.steps_completed}/{metrics.steps_planned}",
        fell=bool(metrics.fell),
        fall_reason=result.fall.reason if result.fall.fell else "",
        dynamics_failures=int(sum(not r.success for r in results)),
        nb_ticks=len(results),
        tick_median_us=_percentile(ticks, 50),
        tick_p99_us=_percentile(ticks, 99),
        solve_median_us=_percentile(solves, 50),
        solve_p99_us=_percentile(solves, 99),
        real_time_factor=metrics.real_time_factor,
        foot_position_error_cm_max=metrics.foot_position_error_cm_max,
        error="",
    )
    return run


def loop_backends(rows: list[dict], robot: str, min_success: float) -> list[str]:
    """Back-ends whose cold solves at the default level succeeded offline on at least
    ``min_success`` of the problems of ``robot``, in the order of ``rows``."""
    out = []
    for backend in dict.fromkeys(r["solver"] for r in rows):
        mine = [
            r
            for r in rows
            if r["solver"] == backend
            and r["robot"] == robot
            and r["tolerance"] == "default"
            and r["start"] == "cold"
        ]
        if mine and np.mean([r["success"] for r in mine]) >= min_success:
            out.append(backend)
    return out
