"""The walks of the robustness matrix: every controller, on every robot, in worlds that are
not the model.

Every controller of a robot walks every world of it
(:func:`~mpcwalk.experiments.robustness.factors.robot_worlds`; :func:`plan_matrix`: one
:class:`~mpcwalk.walking.specification.WalkSpec` each, with the world's seed), so that the
cells of the table compare like with like; a world whose terrain does not fit the robot is
skipped for it, with the reason. The parameters are data (the ``config.toml`` beside this
module, :func:`~mpcwalk.experiments.robustness.config.load_matrix_config`).
"""

import math
from dataclasses import dataclass
from typing import Any

from mpcwalk.exceptions import TerrainError
from mpcwalk.experiments.robustness.config import MatrixConfig, RobotPlan
from mpcwalk.experiments.robustness.factors import (
    FACTORS,
    LEVEL_UNITS,
    World,
    robot_worlds,
    selected_factors,
)
from mpcwalk.experiments.robustness.terrains import (
    LAYOUT_LABEL,
    MILESTONES_LABEL,
    layout_text,
    milestones,
    terrain_of,
    terrain_steps,
)
from mpcwalk.footsteps.capturability import capture_impulse_bound
from mpcwalk.sweep import Sweep
from mpcwalk.walking.specification import WalkSpec
from mpcwalk.walking.sweep_cases import WALK_COLUMNS, worker_robot

#: What a terrain walk measured besides (None on the floor).
TERRAIN_COLUMNS = (
    "landing_error_3d_cm_mean",
    "tread_margin_cm_min",
    "swing_clearance_cm_min",
    "toe_stubs",
    "com_height_error_cm_rms",
)
#: What a walk of the matrix measured: the sweep's walk columns, the walk's outcome
#: (walked, fell, stopped: :func:`~mpcwalk.experiments.survival.survived` reads it) and the
#: terrain metrics.
MATRIX_COLUMNS = (*WALK_COLUMNS, "outcome", *TERRAIN_COLUMNS)


def _limits(robot) -> tuple[tuple[float, float], float, float]:
    """(vx backward, vx forward), |vy|, |vyaw| bounds of the robot's planner [m/s, rad/s]."""
    lim, T = robot.leg_limits, robot.gait.step_duration
    lateral = (lim.half_stance_width - lim.y_sep + 0.5 * lim.max_step_lateral) / T
    yaw = 0.5 * (lim.max_step_yaw + lim.max_step_yaw_inward) / T
    return (lim.max_step_backward / T, lim.max_step_forward / T), lateral, yaw


def _push(robot, push, nb_steps: int, step_duration: float, ranges) -> tuple[float, ...]:
    """The push ``(direction [deg], phase, impulse share)`` as a walk's push (start [s],
    duration [s], force x, y, z [N])."""
    direction, phase, fraction = push
    duration = float(ranges["push_duration"])
    bound = capture_impulse_bound(
        math.radians(direction),
        mass=robot.total_mass,
        com_height=robot.com_height,
        half_length=0.5 * robot.sole_size[0],
        half_width=0.5 * robot.sole_size[1],
    )
    force = fraction * bound / duration
    step = min(int(ranges["push_step"]), nb_steps - 1)
    angle = math.radians(direction)
    return (
        round(1.0 + (step + phase) * step_duration, 4),
        duration,
        round(force * math.cos(angle), 4),
        round(force * math.sin(angle), 4),
        0.0,
    )


def world_case(robot_name: str, plan: RobotPlan, controller: str, world: World, config) -> WalkSpec:
    """The walk (:class:`~mpcwalk.walking.specification.WalkSpec`) of ``controller`` in
    ``world``. On a terrain, the walk takes the steps that carry the robot over it
    (:func:`~mpcwalk.experiments.robustness.terrains.terrain_steps`, whatever the
    controller's own count) and holds the terrain in its ``layout`` label too, the steps
    that reach and cross it in its ``terrain_steps`` label.

    Raises:
        TerrainError: The world's terrain does not fit the robot
            (:func:`~mpcwalk.walking.walk_setup.check_walk_terrain`).
    """
    from mpcwalk.walking.controller_builder import walk_timing
    from mpcwalk.walking.specification import ControllerSpec, PlanSpec
    from mpcwalk.walking.walk_setup import check_walk_terrain

    robot = worker_robot(robot_name)
    own = walk_timing(ControllerSpec.named(controller).generator, robot.gait, PlanSpec())
    slowdown = own.step_duration / robot.gait.step_duration
    nb_steps = config.slow_controllers.get(controller, plan.nb_steps)
    changes = dict(world.changes)
    labels: tuple[tuple[str, Any], ...] = (
        ("group", world.group),
        ("factor", "+".join(world.factors) or "nominal"),
        ("level", world.level),
    )
    if "terrain" in changes:
        factor, level = changes["terrain"]
        terrain = terrain_of(factor, level, robot, config.terrain)
        check_walk_terrain(robot, terrain)
        changes["terrain"] = terrain
        labels += ((LAYOUT_LABEL, layout_text(terrain)),)
    command = plan.command
    if "command_share" in changes:
        (back, forward), lateral, yaw = _limits(robot)
        sx, sy, syaw = changes.pop("command_share")
        command = (sx * (forward if sx > 0 else back), sy * lateral, syaw * yaw)
    command = tuple(round(c / slowdown, 5) for c in command)
    if "terrain" in changes:
        terrain, exit_steps = changes["terrain"], config.terrain.exit_steps
        nb_steps = terrain_steps(terrain, robot, command, own, exit_steps)
        labels += ((MILESTONES_LABEL, list(milestones(terrain, robot, command, own, exit_steps))),)
    pushes: tuple[tuple[float, ...], ...] = ()
    if "push" in changes:
        pushes = (_push(robot, changes.pop("push"), nb_steps, own.step_duration, config.ranges),)
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
        **({} if config.actuation == "position" else {"actuation": config.actuation}),
        **({"terrain_cadence": True} if config.terrain_cadence and "terrain" in changes else {}),
        **changes,
    )


@dataclass(frozen=True)
class MatrixPlan:
    """The walks of a matrix and the worlds it skipped.

    Attributes:
        cases: Every walk: robot by robot, world by world, controller by controller.
        skipped: The worlds whose terrain does not fit their robot: ``robot``, ``factor``,
            ``level``, ``seed`` and the ``reason``.
    """

    cases: tuple[WalkSpec, ...]
    skipped: tuple[dict[str, Any], ...]


def plan_matrix(config: MatrixConfig) -> MatrixPlan:
    """The walks of the matrix; a world whose terrain does not fit its robot (refused by
    :func:`~mpcwalk.walking.walk_setup.check_walk_terrain`) is skipped for that robot, with
    the reason. (A terrain that fits but on which the footstep planner finds no place for a
    landing is a walk that could not run: its row holds the error.)"""
    cases: list[WalkSpec] = []
    skipped = []
    for index, (robot, plan) in enumerate(config.robots.items()):
        for world in robot_worlds(config, index):
            try:
                cases += [world_case(robot, plan, c, world, config) for c in plan.controllers]
            except TerrainError as error:
                skipped.append(
                    {
                        "robot": robot,
                        "factor": "+".join(world.factors),
                        "level": world.level,
                        "seed": world.seed,
                        "reason": str(error),
                    }
                )
    return MatrixPlan(tuple(cases), tuple(skipped))


def matrix_cases(config: MatrixConfig) -> tuple[WalkSpec, ...]:
    """Every walk of the matrix (:func:`plan_matrix`)."""
    return plan_matrix(config).cases


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
    """The matrix as a sweep of the engine (its walks, run by :func:`run_matrix_walk`; the
    skipped worlds in its settings, ``skipped``)."""
    plan = plan_matrix(config)
    return Sweep(
        name="robustness-matrix",
        cases=plan.cases,
        runner=run_matrix_walk,
        columns=MATRIX_COLUMNS,
        settings={**config.settings(), "skipped": list(plan.skipped)},
        timeout=config.timeout,
    )


__all__ = [
    "FACTORS",
    "LEVEL_UNITS",
    "MATRIX_COLUMNS",
    "TERRAIN_COLUMNS",
    "MatrixPlan",
    "World",
    "matrix_cases",
    "matrix_sweep",
    "plan_matrix",
    "robot_worlds",
    "run_matrix_walk",
    "selected_factors",
    "world_case",
]
