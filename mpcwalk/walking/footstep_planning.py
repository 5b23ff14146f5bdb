"""Footsteps of a walk: from a velocity command (paper M eq. 5) or a ``.mdat`` path file
(paper A), in the robot's frame, with its timing and leg limits."""

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import (
    Footstep,
    FootstepPlan,
    StepTiming,
    wrap_angle,
)
from mpcwalk.footsteps.mdat import PathWaypoint, plan_from_path, read_mdat
from mpcwalk.footsteps.terrain_steps import place_on_terrain
from mpcwalk.footsteps.velocity_planner import (
    VelocityCommand,
    VelocityPlanner,
)
from mpcwalk.robot import Robot
from mpcwalk.terrain import Terrain, TerrainReach


def _path_in_robot_frame(
    waypoints: Sequence[PathWaypoint], left: Footstep, right: Footstep
) -> tuple[PathWaypoint, ...]:
    """The path moved rigidly so that its first stance sits on the robot's feet."""
    first = waypoints[0]
    yaw0 = first.right.yaw + 0.5 * float(wrap_angle(first.left.yaw - first.right.yaw))
    mid0 = 0.5 * (first.left.position + first.right.position)
    robot_yaw = right.yaw + 0.5 * float(wrap_angle(left.yaw - right.yaw))
    robot_mid = 0.5 * (left.position + right.position)
    turn = robot_yaw - yaw0
    c, s = math.cos(turn), math.sin(turn)
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

    def move(foot: Footstep) -> Footstep:  # turned about the vertical: roll and pitch kept
        return foot.moved(
            position=robot_mid + rotation @ (foot.position - mid0),
            yaw=float(wrap_angle(foot.yaw + turn)),
        )

    moved = [PathWaypoint(left, right, first.line)]
    moved += [PathWaypoint(move(w.left), move(w.right), w.line) for w in waypoints[1:]]
    return tuple(moved)


def plan_walk_footsteps(
    robot: Robot,
    *,
    command: VelocityCommand | Sequence[float] | None = None,
    path: str | Path | None = None,
    nb_steps: int | None = None,
    timing: StepTiming = StepTiming(),
    terrain: Terrain | None = None,
    reach: TerrainReach | None = None,
) -> FootstepPlan:
    """Footsteps of a walk from the robot's nominal stance.

    Args:
        robot: The robot (its soles at ``q0`` are the initial stance).
        command: Velocity command ``(vx [m/s], vy [m/s], vyaw [rad/s])``, robot frame.
        path: A ``.mdat`` path file (paper A), moved so that it starts at the robot's feet;
            landings are clamped into the robot's reachability rectangle.
        nb_steps: Steps that follow the command (a closing step is added), or the number of
            path steps to keep (None: all of them).
        timing: Step timing.
        terrain: The ground to walk (None: the flat floor): the landings are moved along
            their headings onto tops that hold the soles, within ``reach``
            (:mod:`~mpcwalk.footsteps.terrain_steps`; a path's landings alike).
        reach: What the robot's legs and soles cross (needed with ``terrain``), e.g.
            ``TerrainReach.for_leg(sole_length, sole_width, leg_length)``.

    Raises:
        ConfigurationError: Neither or both of ``command`` and ``path``; a terrain without
            its reach.
        InfeasibleCommand: The command exceeds the robot's leg limits.
        InfeasibleStep: A landing finds no place on ``terrain`` within ``reach``.
        FootstepFileError: The path file is malformed.
    """
    if command is not None and path is not None:
        raise ConfigurationError(
            "A walk needs either a velocity command (vx, vy, vyaw) or a .mdat path file, not both."
        )
    if terrain is not None and reach is None:
        raise ConfigurationError(
            "Footsteps on a terrain need the robot's reach there: pass reach="
            "TerrainReach.for_leg(sole_length, sole_width, leg_length)."
        )
    left, right = robot.initial_feet()
    limits = robot.leg_limits
    if command is None and path is None:
        command = VelocityPlanner(limits, timing).default_command()
    if command is not None:
        if nb_steps is None:
            raise ConfigurationError(
                "A walk from a velocity command needs nb_steps (or a duration)."
            )
        return VelocityPlanner(limits, timing).plan(
            command, nb_steps, initial_left=left, initial_right=right, terrain=terrain, reach=reach
        )
    if path is None:  # excluded above; narrows the type
        raise ConfigurationError("A walk without a velocity command needs a .mdat path file.")
    # a file, whatever its name (read_mdat takes a string that names no file for content)
    waypoints = _path_in_robot_frame(read_mdat(Path(path)), left, right)
    plan = plan_from_path(waypoints, rectangle=limits.rectangle(), timing=timing)
    if nb_steps is not None and nb_steps < plan.nb_steps:
        plan = FootstepPlan(plan.initial_left, plan.initial_right, plan.steps[:nb_steps], timing)
    if terrain is None or reach is None:
        return plan
    return place_on_terrain(plan, terrain, reach, limits=limits)
