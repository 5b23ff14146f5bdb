"""Walks in the workers of a sweep: the robots loaded once per worker, one walk per case.

:func:`run_walk_case` is the runner of a :class:`~mpcwalk.sweep.case.WalkCase`: it walks the
case with :func:`~mpcwalk.walking.runner.run_walk` on the worker's copy of the robot
(:func:`worker_robot`) and returns the columns of :data:`WALK_COLUMNS`.
"""

from typing import Any

from mpcwalk.sweep.case import WalkCase

_ROBOTS: dict[str, Any] = {}

#: What a walk of a sweep measured (keys of ``metrics.json``), in the results table.
WALK_COLUMNS = (
    "fell",
    "fall_time_s",
    "fall_reason",
    "steps_completed",
    "steps_planned",
    "time_simulated_s",
    "foot_position_error_cm_mean",
    "foot_position_error_cm_max",
    "foot_step_error_cm_max",
    "cop_margin_min_m",
    "cop_margin_p05_m",
    "distance_m",
    "yaw_change_deg",
    "mpc_failures",
    "estimator_com_error_rms_m",
    "controller_tick_us_median",
    "real_time_factor",
)


def worker_robot(name: str):
    """The robot called ``name``, loaded once per worker process (without meshes)."""
    if name not in _ROBOTS:
        from mpcwalk.robot.loading import load_robot

        _ROBOTS[name] = load_robot(name, visual=False)
    return _ROBOTS[name]


def run_walk_case(case: WalkCase) -> dict[str, Any]:
    """Walk ``case``; its :data:`WALK_COLUMNS`.

    Raises:
        MpcwalkError: The library refused the walk (the sweep's row then holds the error).
    """
    from mpcwalk.walking.runner import run_walk

    result = run_walk(worker_robot(case.robot), progress=False, **case.walk_arguments())
    metrics = result.metrics.to_dict()
    return {key: metrics[key] for key in WALK_COLUMNS}


__all__ = ["WALK_COLUMNS", "run_walk_case", "worker_robot"]
