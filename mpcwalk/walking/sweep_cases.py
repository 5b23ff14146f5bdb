"""Walks as the cases of a sweep: a case *is* a :class:`~mpcwalk.walking.specification.WalkSpec`.

The sweep engine (:mod:`mpcwalk.sweep`) runs any case that has a ``case_id`` and its
columns; a walk's specification is one: its id the hash of the specification
(:attr:`WalkSpec.case_id <mpcwalk.walking.specification.WalkSpec.case_id>`), its columns
:data:`CASE_COLUMNS` and its labels (:func:`spec_columns`), its row the measures of
:data:`WALK_COLUMNS` (:func:`run_walk_case`, on the worker's copy of the robot), and the
``mpcwalk walk`` command that walks it again alone (:func:`command_line`).
"""

from typing import Any

from mpcwalk.walking.specification import WalkSpec
from mpcwalk.walking.specification.records import (
    CASE_COLUMNS,
    command_line,
    spec_columns,
)

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

_ROBOTS: dict[str, Any] = {}


def spec_of_row(row: dict[str, Any]) -> WalkSpec:
    """The walk of a row of a results table written with :func:`spec_columns` (a named
    controller's; its labels left out; a row written before the ``actuation`` column
    walks on position servos, as every walk did then)."""
    import json

    def number(key: str, default: Any = None) -> Any:
        value = row.get(key)
        if value in (None, "", "None"):
            return default
        return float(value)

    pushes = row.get("pushes") or []
    if isinstance(pushes, str):
        pushes = json.loads(pushes)
    period = number("control_period", 0.01)
    latency = number("latency_periods")
    steps = number("nb_steps")
    return WalkSpec.build(
        str(row["robot"]),
        controller=str(row["controller"]),
        command=(number("vx", 0.0), number("vy", 0.0), number("vyaw", 0.0)),
        nb_steps=None if steps is None else int(steps),
        pushes=[tuple(p) for p in pushes],
        mass_scale=number("mass_scale", 1.0),
        com_offset=(number("com_dx", 0.0), number("com_dy", 0.0)),
        friction=number("friction"),
        noise_scale=number("noise_scale", 1.0),
        latency=None if latency is None else round(latency * period, 9),
        servo_strength=number("servo_strength", 1.0),
        ground_tilt=number("ground_tilt", 0.0),
        ground_tilt_direction=number("ground_tilt_direction", 0.0),
        ground_roughness=number("ground_roughness", 0.0),
        seed=int(number("seed", 0)),
        control_period=period,
        actuation=str(row.get("actuation") or "position"),
    )


def worker_robot(name: str) -> Any:
    """The robot called ``name``, loaded once per worker process (without meshes)."""
    if name not in _ROBOTS:
        from mpcwalk.robot.loading import load_robot

        _ROBOTS[name] = load_robot(name, visual=False)
    return _ROBOTS[name]


def run_walk_case(spec: WalkSpec) -> dict[str, Any]:
    """Walk ``spec`` on the worker's copy of its robot; its :data:`WALK_COLUMNS`.

    Raises:
        MpcwalkError: The library refused the walk (the sweep's row then holds the error).
    """
    from mpcwalk.walking.runner import run_walk

    result = run_walk(spec.replace(progress=False), robot=worker_robot(spec.robot))
    metrics = result.metrics.to_dict()
    return {key: metrics[key] for key in WALK_COLUMNS}


__all__ = [
    "CASE_COLUMNS",
    "WALK_COLUMNS",
    "command_line",
    "run_walk_case",
    "spec_columns",
    "spec_of_row",
    "worker_robot",
]
