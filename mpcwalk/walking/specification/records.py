"""A walk specification as a row of a sweep's table and as the ``mpcwalk walk`` command
that walks it again: :data:`CASE_COLUMNS`, :func:`spec_columns`, :func:`command_line`.

These read a specification and import nothing of the walk, so that
:class:`~mpcwalk.walking.specification.WalkSpec` can answer the sweep engine's
``to_columns()`` and print its own command line.
"""

import shlex
from typing import Any

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
    "actuation",
)


def latency_periods(spec: Any) -> int | None:
    """The latency of ``spec`` in control periods (None: the sensor model's)."""
    return spec.world.latency_periods(spec.plan.control_period)


def spec_columns(spec: Any) -> dict[str, Any]:
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
        "actuation": world.actuation,
    }
    return {**values, **dict(spec.labels)}


def _text(value: float) -> str:
    """A number as the command line reads it back exactly."""
    return repr(float(value)) if not float(value).is_integer() else f"{float(value):g}"


#: The terrain file a walk on a terrain writes beside its results, which its command reads.
TERRAIN_FILE = "terrain.toml"


def command_line(spec: Any, out: str = "walk") -> str:
    """The ``mpcwalk walk`` command that walks ``spec`` again alone (fields left at their
    defaults are left out; a controller composed by hand is given by its parts; a terrain
    as ``--terrain terrain.toml``, the terrain file written beside the walk's results)."""
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
    if "dynamics_solver" in controller.controller_options:
        words += ["--dynamics-solver", str(controller.controller_options["dynamics_solver"])]
    if controller.controller_options.get("torque_loop") is True:
        words.append("--torque-loop")
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
    if world.actuation != "position":
        words += ["--actuation", world.actuation]
    if world.ideal:
        words.append("--ideal")
    if world.state != ("oracle" if world.ideal else "estimator"):
        words += ["--state", str(world.state)]
    if tuple(world.com_offset) != (0.0, 0.0):
        words += ["--com-offset", ",".join(_text(v) for v in world.com_offset)]
    if world.terrain is not None:
        words += ["--terrain", TERRAIN_FILE]
    if plan.control_period != 0.01:
        words += ["--control-period", _text(plan.control_period)]
    if plan.terrain_cadence:
        words.append("--terrain-cadence")
    words += ["--seed", str(spec.run.seed), "--out", out]
    joined: list[str] = []  # a value starting with "-" is glued to its option
    for word in words:
        if word.startswith("-") and not word.startswith("--") and joined:
            joined[-1] = f"{joined[-1]}={word}"
        else:
            joined.append(word)
    return shlex.join(joined)


__all__ = ["CASE_COLUMNS", "TERRAIN_FILE", "command_line", "latency_periods", "spec_columns"]
