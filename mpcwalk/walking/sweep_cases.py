"""Walks as the cases of a sweep: a case *is* a :class:`~mpcwalk.walking.specification.WalkSpec`.

The sweep engine (:mod:`mpcwalk.sweep`) runs any case that has a ``case_id`` and its
columns; a walk's specification is one: its id the hash of the specification
(:attr:`WalkSpec.case_id <mpcwalk.walking.specification.WalkSpec.case_id>`), its columns
:data:`CASE_COLUMNS` and its labels (:func:`spec_columns`), its row the measures of
:data:`WALK_COLUMNS` (:func:`run_walk_case`, on the worker's copy of the robot), and the
``mpcwalk walk`` command that walks it again alone (:func:`command_line`).
"""

import shlex
from typing import Any

from mpcwalk.walking.specification import WalkSpec

#: Columns of a case in a results table (then its labels, then the run's columns).
CASE_COLUMNS = (
    "case_id",
    "robot",
    "controller",
    "vx",
    "vy",
    "vyaw",
    "nb_steps",
    "pushes",
    "mass_scale",
    "com_dx",
    "com_dy",
    "friction",
    "noise_scale",
    "latency_periods",
    "servo_strength",
    "ground_tilt",
    "ground_tilt_direction",
    "ground_roughness",
    "seed",
    "control_period",
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


def latency_periods(spec: WalkSpec) -> int | None:
    """The latency of ``spec`` in control periods (None: the sensor model's)."""
    return spec.world.latency_periods(spec.plan.control_period)


def spec_columns(spec: WalkSpec) -> dict[str, Any]:
    """The case as columns of a results table (:data:`CASE_COLUMNS`, then the labels)."""
    vx, vy, vyaw = spec.plan.command or (None, None, None)
    world, dx_dy = spec.world, spec.world.com_offset
    values = {
        "case_id": spec.case_id,
        "robot": spec.robot,
        "controller": spec.controller.name,
        "vx": vx,
        "vy": vy,
        "vyaw": vyaw,
        "nb_steps": spec.plan.nb_steps,
        "pushes": [list(push) for push in spec.disturbances.pushes],
        "mass_scale": world.mass_scale,
        "com_dx": dx_dy[0],
        "com_dy": dx_dy[1],
        "friction": world.friction,
        "noise_scale": world.noise_scale,
        "latency_periods": latency_periods(spec),
        "servo_strength": world.servo_strength,
        "ground_tilt": world.ground_tilt,
        "ground_tilt_direction": world.ground_tilt_direction,
        "ground_roughness": world.ground_roughness,
        "seed": spec.run.seed,
        "control_period": spec.plan.control_period,
    }
    return {**values, **dict(spec.labels)}


def spec_of_row(row: dict[str, Any]) -> WalkSpec:
    """The walk of a row of a results table written with :func:`spec_columns` (a named
    controller's; its labels left out)."""
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
    )


def _text(value: float) -> str:
    """A number as the command line reads it back exactly."""
    return repr(float(value)) if not float(value).is_integer() else f"{float(value):g}"


def command_line(spec: WalkSpec, out: str = "walk") -> str:
    """The ``mpcwalk walk`` command that walks ``spec`` again alone (fields left at their
    defaults are left out; a controller composed by hand is given by its parts)."""
    words = ["mpcwalk", "walk", "--robot", spec.robot]
    controller, plan, world = spec.controller, spec.plan, spec.world
    if controller.name in ("custom",):
        words += ["--generator", controller.generator]
        if not controller.feedback:
            words.append("--no-feedback")
        words.append("--reaim" if "reaim" in controller.stabilizers else "--no-reaim")
        others = [s for s in controller.stabilizers if s != "reaim"]
        words += ["--stabilizer", others[0] if others else "none"]
        words += ["--swing-profile", controller.swing_profile]
        if controller.arm_swing:
            words += ["--arm-swing", _text(controller.arm_swing)]
    else:
        words += ["--controller", controller.name]
    if "solver" in controller.generator_options:
        words += ["--solver", str(controller.generator_options["solver"])]
    if plan.command is not None:
        vx, vy, vyaw = plan.command
        words += ["--vx", _text(vx), "--vy", _text(vy), "--vyaw", _text(vyaw)]
    if plan.path is not None:
        words += ["--path", plan.path]
    if plan.nb_steps is not None:
        words += ["--steps", str(plan.nb_steps)]
    if plan.duration is not None:
        words += ["--duration", _text(plan.duration)]
    for push in spec.disturbances.pushes:
        words += ["--push", ",".join(_text(v) for v in push)]
    options = (
        ("--step-duration", plan.step_duration, None),
        ("--ds-ratio", plan.double_support_ratio, None),
        ("--step-height", plan.step_height, None),
        ("--mass-scale", world.mass_scale, 1.0),
        ("--friction", world.friction, None),
        ("--noise-scale", world.noise_scale, 1.0),
        ("--latency", world.latency, None),
        ("--servo-strength", world.servo_strength, 1.0),
        ("--ground-tilt", world.ground_tilt, 0.0),
        ("--ground-tilt-direction", world.ground_tilt_direction, 0.0),
        ("--ground-roughness", world.ground_roughness, 0.0),
    )
    for option, value, default in options:
        if value != default and value is not None:
            words += [option, _text(value)]
    if world.ideal:
        words.append("--ideal")
    if world.state != ("oracle" if world.ideal else "estimator"):
        words += ["--state", str(world.state)]
    if tuple(world.com_offset) != (0.0, 0.0):
        words += ["--com-offset", ",".join(_text(v) for v in world.com_offset)]
    if plan.control_period != 0.01:
        words += ["--control-period", _text(plan.control_period)]
    words += ["--seed", str(spec.run.seed), "--out", out]
    joined: list[str] = []  # a value starting with "-" is glued to its option
    for word in words:
        if word.startswith("-") and not word.startswith("--") and joined:
            joined[-1] = f"{joined[-1]}={word}"
        else:
            joined.append(word)
    return shlex.join(joined)


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
