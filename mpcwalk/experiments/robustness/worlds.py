"""The robustness matrix: every controller, on every robot, in worlds that are not the model.

Each robot walks a list of *worlds* (:func:`robot_worlds`): the nominal one (over a few
seeds), each factor alone at random levels stratified over its range, and random
combinations of 2 to 4 factors. The factors (:data:`FACTORS`): a random omnidirectional
command within the robot's limits; a push on the torso (direction, phase of the step,
impulse as a fraction of the LIPM's no-step capture bound in that direction); torso mass;
torso CoM offset; friction; sensor noise; latency; servo strength; ground tilt (towards a
random azimuth); rough ground (a height field). Every controller of the robot walks every
world (:func:`matrix_cases`: one :class:`~mpcwalk.walking.specification.WalkSpec` each, with the
world's seed), so that the cells of the table compare like with like. The parameters are data
(the ``config.toml`` beside this module,
:func:`~mpcwalk.experiments.robustness.config.load_matrix_config`).
"""

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from mpcwalk.experiments.robustness.config import MatrixConfig, RobotPlan
from mpcwalk.footsteps.capturability import capture_impulse_bound
from mpcwalk.sweep import Sweep
from mpcwalk.walking.specification import WalkSpec
from mpcwalk.walking.sweep_cases import WALK_COLUMNS, worker_robot

#: What a walk of the matrix measured: the sweep's walk columns and the walk's outcome
#: (walked, fell, stopped: :func:`~mpcwalk.experiments.survival.survived` reads it).
MATRIX_COLUMNS = (*WALK_COLUMNS, "outcome")

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
class World:
    """How one world of the matrix differs from the nominal walk.

    Attributes:
        group: ``"nominal"``, ``"single"`` or ``"combination"``.
        factors: The factors changed.
        level: The single factor's level (:data:`LEVEL_UNITS`), None otherwise.
        seed: Seed of the walk (sensor noise, bumps).
        changes: Fields of a :class:`~mpcwalk.walking.specification.WalkSpec` (the latency in control
            periods, ``latency_periods``), the command as a fraction of
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


def world_case(robot_name: str, plan: RobotPlan, controller: str, world: World, config) -> WalkSpec:
    """The walk (:class:`~mpcwalk.walking.specification.WalkSpec`) of ``controller`` in ``world``."""
    from mpcwalk.walking.controller_builder import walk_timing
    from mpcwalk.walking.specification import ControllerSpec, PlanSpec

    robot = worker_robot(robot_name)
    own = walk_timing(ControllerSpec.named(controller).generator, robot.gait, PlanSpec())
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
    if "latency_periods" in changes:
        changes["latency"] = round(changes.pop("latency_periods") * config.control_period, 9)
    return WalkSpec.build(
        robot_name,
        controller=controller,
        command=command,
        nb_steps=nb_steps,
        pushes=pushes,
        seed=world.seed,
        control_period=config.control_period,
        labels=labels,
        **changes,
    )


def matrix_cases(config: MatrixConfig) -> tuple[WalkSpec, ...]:
    """Every walk of the matrix: robot by robot, world by world, controller by controller."""
    cases = []
    for index, (robot, plan) in enumerate(config.robots.items()):
        for world in robot_worlds(config, index):
            cases += [world_case(robot, plan, c, world, config) for c in plan.controllers]
    return tuple(cases)


def run_matrix_walk(spec: WalkSpec) -> dict[str, Any]:
    """Walk ``spec`` (in a worker); its :data:`MATRIX_COLUMNS`.

    Raises:
        MpcwalkError: The library refused the walk (the sweep's row then holds the error).
    """
    from mpcwalk.walking.runner import run_walk

    result = run_walk(spec.replace(progress=False), robot=worker_robot(spec.robot))
    metrics = result.metrics.to_dict()
    return {key: metrics[key] for key in MATRIX_COLUMNS}


def matrix_sweep(config: MatrixConfig) -> Sweep:
    """The matrix as a sweep of the engine (its walks, run by :func:`run_matrix_walk`)."""
    return Sweep(
        name="robustness-matrix",
        cases=matrix_cases(config),
        runner=run_matrix_walk,
        columns=MATRIX_COLUMNS,
        settings=config.settings(),
        timeout=config.timeout,
    )


__all__ = [
    "FACTORS",
    "LEVEL_UNITS",
    "MATRIX_COLUMNS",
    "World",
    "matrix_cases",
    "matrix_sweep",
    "robot_worlds",
    "run_matrix_walk",
    "world_case",
]
