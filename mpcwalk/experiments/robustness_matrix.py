"""The robustness matrix: every controller, on every robot, in worlds that are not the model.

Each robot walks a list of *worlds* (:func:`robot_worlds`): the nominal one (over a few
seeds), each factor alone at random levels stratified over its range, and random
combinations of 2 to 4 factors. The factors (:data:`FACTORS`): a random omnidirectional
command within the robot's limits; a push on the torso (direction, phase of the step,
impulse as a fraction of the LIPM's no-step capture bound in that direction); torso mass;
torso CoM offset; friction; sensor noise; latency; servo strength; ground tilt (towards a
random azimuth); rough ground (a height field). Every controller of the robot walks every
world (:func:`matrix_cases`: one :class:`~mpcwalk.sweep.WalkCase` each, with the world's
seed), so that the cells of the table compare like with like. The parameters are data
(``experiments/robustness/matrix.toml``, :func:`load_matrix_config`).
"""

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.push_sweep import capture_impulse_bound
from mpcwalk.experiments.robustness_config import read_toml_mode
from mpcwalk.robot.package_data import EXPERIMENT_DATA, package_data_dir
from mpcwalk.sweep import WALK_COLUMNS, Sweep, WalkCase, run_walk_case, worker_robot

DEFAULT_MATRIX = package_data_dir(EXPERIMENT_DATA) / "robustness" / "matrix.toml"

#: The factors, in table order.
FACTORS = (
    "command",
    "push",
    "mass",
    "com",
    "friction",
    "noise",
    "latency",
    "servo",
    "tilt",
    "roughness",
)

#: What the level of each factor is, for the tables.
LEVEL_UNITS = {
    "command": "largest share of a limit",
    "push": "impulse / no-step capture bound",
    "mass": "torso mass factor",
    "com": "CoM offset [m]",
    "friction": "friction coefficient",
    "noise": "noise factor",
    "latency": "latency [control periods]",
    "servo": "servo strength factor",
    "tilt": "slope [deg]",
    "roughness": "largest bump [m]",
}


@dataclass(frozen=True)
class RobotPlan:
    """A robot's part of the matrix: its controllers, nominal command and steps."""

    controllers: tuple[str, ...]
    command: tuple[float, float, float]
    nb_steps: int


@dataclass(frozen=True)
class MatrixConfig:
    """The matrix (see ``experiments/robustness/matrix.toml`` for each entry)."""

    robots: Mapping[str, RobotPlan]
    ranges: Mapping[str, Any]
    slow_controllers: Mapping[str, int] = field(default_factory=dict)
    levels: int = 3
    combinations: int = 10
    combination_size: tuple[int, int] = (2, 4)
    nominal_seeds: tuple[int, ...] = (0,)
    seed: int = 0
    timeout: float = 900.0
    control_period: float = 0.01
    mode: str = "full"

    def settings(self) -> dict[str, Any]:
        """The parameters as JSON (the sweep's fingerprint)."""
        return {
            "robots": {name: vars(plan) for name, plan in self.robots.items()},
            "ranges": dict(self.ranges),
            "slow_controllers": dict(self.slow_controllers),
            "levels": self.levels,
            "combinations": self.combinations,
            "combination_size": list(self.combination_size),
            "nominal_seeds": list(self.nominal_seeds),
            "seed": self.seed,
            "timeout": self.timeout,
            "control_period": self.control_period,
            "mode": self.mode,
        }


def load_matrix_config(path: str | Path = DEFAULT_MATRIX, *, mode: str = "full") -> MatrixConfig:
    """Read the matrix from TOML; ``mode="quick"`` applies its ``[quick]`` table.

    Raises:
        ConfigurationError: Another mode, or a malformed table.
    """
    data, quick = read_toml_mode(path, mode)
    try:
        robots = {
            name: RobotPlan(
                tuple(quick.get("controllers", plan["controllers"])),
                tuple(float(v) for v in plan["command"]),  # type: ignore[arg-type]
                int(quick.get("nb_steps", plan["nb_steps"])),
            )
            for name, plan in data["robots"].items()
            if name in quick.get("robots", data["robots"])
        }
        ranges = dict(data["factors"])
        ranges.update({k: v for k, v in quick.items() if k in ranges})
        low, high = data.get("combination_size", (2, 4))
        return MatrixConfig(
            robots=robots,
            ranges=ranges,
            slow_controllers={k: int(v) for k, v in data.get("slow_controllers", {}).items()},
            levels=int(quick.get("levels", data.get("levels", 3))),
            combinations=int(quick.get("combinations", data.get("combinations", 10))),
            combination_size=(int(low), int(high)),
            nominal_seeds=tuple(quick.get("nominal_seeds", data.get("nominal_seeds", [0]))),
            seed=int(data.get("seed", 0)),
            timeout=float(data.get("timeout", 900.0)),
            control_period=float(data.get("control_period", 0.01)),
            mode=mode,
        )
    except (KeyError, TypeError, ValueError) as error:
        raise ConfigurationError(f"Malformed matrix file {path}: {error!r}.") from None


@dataclass(frozen=True)
class World:
    """How one world of the matrix differs from the nominal walk.

    Attributes:
        group: ``"nominal"``, ``"single"`` or ``"combination"``.
        factors: The factors changed.
        level: The single factor's level (:data:`LEVEL_UNITS`), None otherwise.
        seed: Seed of the walk (sensor noise, bumps).
        changes: Fields of :class:`~mpcwalk.sweep.WalkCase`, the command as a fraction of
            the robot's limits (``command_share``) and the push as ``push`` = (direction
            [deg], phase [share of the step], impulse share).
    """

    group: str
    factors: tuple[str, ...]
    level: float | None
    seed: int
    changes: Mapping[str, Any]


def _draw(factor: str, u: float, rng: np.random.Generator, ranges) -> tuple[dict, float]:
    """The changes of ``factor`` at the stratified draw ``u`` in [0, 1), and its level."""

    def span(key: str) -> float:
        low, high = ranges[key]
        return round(float(low + u * (high - low)), 4)

    if factor == "command":
        share = np.round(rng.uniform(-1.0, 1.0, 3) * float(ranges["command_fraction"]), 3)
        return {"command_share": tuple(float(s) for s in share)}, float(np.abs(share).max())
    if factor == "push":
        direction = round(float(rng.uniform(0.0, 360.0)), 1)
        phase = round(float(rng.uniform(0.0, 1.0)), 3)
        fraction = span("push_fraction")
        return {"push": (direction, phase, fraction)}, fraction
    if factor == "com":
        low, high = ranges["com_offset"]
        angle = rng.uniform(0.0, 2.0 * math.pi)
        radius = u * max(abs(low), abs(high))
        offset = (round(radius * math.cos(angle), 4), round(radius * math.sin(angle), 4))
        return {"com_offset": offset}, round(math.hypot(*offset), 4)
    if factor == "latency":
        low, high = ranges["latency_periods"]
        periods = int(low + min(int(u * (high - low + 1)), high - low))
        return {"latency_periods": periods}, float(periods)
    if factor == "tilt":
        slope = span("ground_tilt")
        azimuth = round(float(rng.uniform(0.0, 360.0)), 1)
        return {"ground_tilt": slope, "ground_tilt_direction": azimuth}, slope
    key = {
        "mass": "mass_scale",
        "friction": "friction",
        "noise": "noise_scale",
        "servo": "servo_strength",
        "roughness": "ground_roughness",
    }[factor]
    value = span(key)
    return {key: value}, value


def robot_worlds(config: MatrixConfig, robot_index: int) -> list[World]:
    """The worlds of one robot (the ``robot_index``-th of the config: its own draws)."""
    rng = np.random.default_rng([config.seed, robot_index])
    worlds = [World("nominal", (), None, int(seed), {}) for seed in config.nominal_seeds]
    next_seed = 100
    for factor in FACTORS:
        for i in range(config.levels):
            changes, level = _draw(factor, (i + rng.uniform()) / config.levels, rng, config.ranges)
            worlds.append(World("single", (factor,), level, next_seed, changes))
            next_seed += 1
    low, high = config.combination_size
    for _ in range(config.combinations):
        size = int(rng.integers(low, high + 1))
        factors = tuple(sorted(rng.choice(FACTORS, size, replace=False), key=FACTORS.index))
        changes = {}
        for factor in factors:
            changes.update(_draw(factor, float(rng.uniform()), rng, config.ranges)[0])
        worlds.append(World("combination", factors, None, next_seed, changes))
        next_seed += 1
    return worlds


def _limits(robot) -> tuple[tuple[float, float], float, float]:
    """(vx backward, vx forward), |vy|, |vyaw| bounds of the robot's planner [m/s, rad/s]."""
    lim, T = robot.leg_limits, robot.gait.step_duration
    lateral = (lim.half_stance_width - lim.y_sep + 0.5 * lim.max_step_lateral) / T
    yaw = 0.5 * (lim.max_step_yaw + lim.max_step_yaw_inward) / T
    return (lim.max_step_backward / T, lim.max_step_forward / T), lateral, yaw


def world_case(robot_name: str, plan: RobotPlan, controller: str, world: World, config):
    """The :class:`~mpcwalk.sweep.WalkCase` of ``controller`` in ``world``."""
    from mpcwalk.walking.controller_resolution import default_timing
    from mpcwalk.walking.controllers import controller_config

    robot = worker_robot(robot_name)
    own = default_timing(controller_config(controller).generator, robot.gait, None, None)
    slowdown = own.step_duration / robot.gait.step_duration
    nb_steps = config.slow_controllers.get(controller, plan.nb_steps)
    changes = dict(world.changes)
    command = plan.command
    if "command_share" in changes:
        (back, forward), lateral, yaw = _limits(robot)
        sx, sy, syaw = changes.pop("command_share")
        command = (sx * (forward if sx > 0 else back), sy * lateral, syaw * yaw)
    command = tuple(round(c / slowdown, 5) for c in command)
    pushes: tuple[tuple[float, float, float, float, float], ...] = ()
    if "push" in changes:
        direction, phase, fraction = changes.pop("push")
        duration = float(config.ranges["push_duration"])
        bound = capture_impulse_bound(
            math.radians(direction),
            mass=robot.total_mass,
            com_height=robot.com_height,
            half_length=0.5 * robot.sole_size[0],
            half_width=0.5 * robot.sole_size[1],
        )
        force = fraction * bound / duration
        step = min(int(config.ranges["push_step"]), nb_steps - 1)
        start = 1.0 + (step + phase) * own.step_duration
        angle = math.radians(direction)
        pushes = (
            (
                round(start, 4),
                duration,
                round(force * math.cos(angle), 4),
                round(force * math.sin(angle), 4),
                0.0,
            ),
        )
    labels = (
        ("group", world.group),
        ("factor", "+".join(world.factors) or "nominal"),
        ("level", world.level),
    )
    return WalkCase(
        robot_name,
        controller,
        command=command,
        nb_steps=nb_steps,
        pushes=pushes,
        seed=world.seed,
        control_period=config.control_period,
        labels=labels,
        **changes,
    )


def matrix_cases(config: MatrixConfig) -> tuple[WalkCase, ...]:
    """Every walk of the matrix: robot by robot, world by world, controller by controller."""
    cases = []
    for index, (robot, plan) in enumerate(config.robots.items()):
        for world in robot_worlds(config, index):
            cases += [world_case(robot, plan, c, world, config) for c in plan.controllers]
    return tuple(cases)


def matrix_sweep(config: MatrixConfig) -> Sweep:
    """The matrix as a sweep of the engine (its walks, run by
    :func:`~mpcwalk.sweep.run_walk_case`)."""
    return Sweep(
        name="robustness-matrix",
        cases=matrix_cases(config),
        runner=run_walk_case,
        columns=WALK_COLUMNS,
        settings=config.settings(),
        timeout=config.timeout,
    )


__all__ = [
    "DEFAULT_MATRIX",
    "FACTORS",
    "LEVEL_UNITS",
    "MatrixConfig",
    "RobotPlan",
    "World",
    "load_matrix_config",
    "matrix_cases",
    "matrix_sweep",
    "robot_worlds",
    "world_case",
]
