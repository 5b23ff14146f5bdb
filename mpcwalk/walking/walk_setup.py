"""From a walk's specification to the parts of a walk, checked before anything runs:
:func:`set_up_walk` returns a :class:`WalkSetup`.

The robot is loaded, the controller's configuration checked, the timing decided (the plan's,
else the generator's own, else the robot preset's), the footsteps planned and the contact
schedule made, the pushes checked against the robot and the walk's length; the
specification comes back *resolved*: the defaults it left to the robot spelled out, so that
the ``spec.toml`` written next to the results walks the same walk again. A terrain must fit
the robot (its rises within its legs' reach, its treads longer than its soles:
:func:`~mpcwalk.terrain.check_terrain`) and leave its initial stance on the level ground.
"""

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError, TerrainError
from mpcwalk.footsteps.cadence import cadence_stretch
from mpcwalk.footsteps.footstep import FootGeometry, FootstepPlan, StepTiming
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators import generator_class
from mpcwalk.models.lipm import LIPM
from mpcwalk.robot import Robot, load_robot
from mpcwalk.sim import ExternalForce
from mpcwalk.terrain import Terrain, TerrainReach, check_terrain
from mpcwalk.walking.controller_builder import check_controller, walk_timing
from mpcwalk.walking.footstep_planning import plan_walk_footsteps
from mpcwalk.walking.outputs import check_video_path
from mpcwalk.walking.specification import WalkSpec
from mpcwalk.walking.specification.plan import MAX_STEP_DURATION

#: Largest push force, in multiples of the robot's weight.
MAX_PUSH_WEIGHTS = 100.0


def check_step_height(robot: Robot, step_height: Any) -> None:
    """The swing height (None: the preset's) lifts the foot and stays below half the CoM
    height of ``robot`` (the plan checked its type and sign)."""
    if step_height is not None:
        checked_number(
            "step_height",
            step_height,
            low=0.0,
            high=0.5 * robot.com_height,
            low_inclusive=False,
            unit="m",
            fix=f"the swing foot must lift (> 0) and stay below half the CoM height of "
            f"{robot.name}",
        )


def check_pushes(pushes: Any, robot: Robot, walk_end: float) -> list[ExternalForce]:
    """Pushes as :class:`ExternalForce`, within the walk and of a physical size."""
    if isinstance(pushes, (str, bytes)) or not isinstance(pushes, Sequence):
        raise ConfigurationError(
            f"pushes must be a list of ExternalForce, got {pushes!r}; e.g. "
            "pushes=[parse_push('3.0,0.1,10,0,0')]."
        )
    limit = MAX_PUSH_WEIGHTS * robot.total_mass * 9.81
    checked = []
    for push in pushes:
        if not isinstance(push, ExternalForce):
            raise ConfigurationError(
                f"Each push must be an ExternalForce, got {push!r}; build it with "
                f"mpcwalk.sim.parse_push({str(push)!r}) or ExternalForce(start, duration, force)."
            )
        force = float((push.force**2).sum() ** 0.5)
        if force > limit:
            raise ConfigurationError(
                f"A push of {force:.3g} N is beyond {MAX_PUSH_WEIGHTS:g} times the weight of "
                f"{robot.name} ({limit:.3g} N): no robot survives it and the simulation only "
                "diverges; use a smaller force."
            )
        if push.start >= walk_end:
            raise ConfigurationError(
                f"A push starts at {push.start:g} s, after the walk's end at {walk_end:g} s: it "
                "would never act; start it earlier or walk longer."
            )
        checked.append(push)
    return checked


def check_walk_terrain(robot: Robot, terrain: Terrain | None) -> None:
    """The terrain fits ``robot`` (:func:`~mpcwalk.terrain.check_terrain` with the reach of
    its legs) and its initial soles, with a margin of a tenth of their length, stand on the
    level ground at 0 m (None: the level floor).

    Raises:
        TerrainError: What does not fit, the limit in the message.
    """
    if terrain is None:
        return
    length, width = robot.sole_size
    check_terrain(terrain, TerrainReach.for_leg(length, width, robot.leg_length), robot.name)
    along, across = np.meshgrid(  # [m] sole frame: the sole, a tenth of its length more
        np.linspace(-0.6 * length, 0.6 * length, 5), np.linspace(-0.5 * width, 0.5 * width, 5)
    )
    for foot in robot.initial_feet():
        c, s = np.cos(foot.yaw), np.sin(foot.yaw)
        x = foot.xy[0] + c * along - s * across
        y = foot.xy[1] + s * along + c * across
        if np.abs(terrain.height(x, y)).max() > 1e-9:
            first = terrain.features[0]
            raise TerrainError(
                f"The terrain does not leave {robot.name} its initial stance on the level "
                f"ground: {type(first).__name__} at {first.start:g} m lies under its soles, "
                f"which reach x = {float(x.max()):.3f} m with a margin; start the first feature "
                f"at {float(x.max()) + 0.01:.2f} m or beyond."
            )


@dataclass(frozen=True)
class WalkSetup:
    """A walk ready to run.

    Attributes:
        spec: The specification, resolved (timing, swing height and state source spelled
            out).
        robot: The robot.
        timing: The step timing.
        nb_steps: Steps of the plan asked for (from ``duration`` when the plan gave that).
        plan: The footsteps.
        schedule: Their contact phases.
        pushes: The pushes, checked.
    """

    @property
    def step_height(self) -> float:
        """The swing-foot height [m] (resolved: never None)."""
        return float(self.spec.plan.step_height or self.robot.gait.step_height)

    @property
    def state_source(self) -> str:
        """Where the controller's state comes from (resolved: never None)."""
        return str(self.spec.world.state)

    spec: WalkSpec
    robot: Robot
    timing: StepTiming
    nb_steps: int | None
    plan: FootstepPlan
    schedule: ContactSchedule
    pushes: list[ExternalForce]


def _at_terrain_cadence(
    footsteps: FootstepPlan, robot: Robot, plan: Any, nb_steps: int | None
) -> tuple[FootstepPlan, dict[str, Any]]:
    """The footsteps with every step lengthened by the terrain cadence
    (:func:`~mpcwalk.footsteps.cadence.cadence_stretch`), and the changes of the resolved
    specification that walk them again (the divided command, the number of steps); the
    footsteps as they are and no change when no step needs it.

    Raises:
        ConfigurationError: The lengthened steps would last beyond the longest step.
    """
    timing = footsteps.timing
    stretch = cadence_stretch(footsteps, robot.leg_limits.max_step_forward)
    if stretch * timing.step_duration > MAX_STEP_DURATION:
        raise ConfigurationError(
            f"The terrain cadence would lengthen the steps of {timing.step_duration:g} s "
            f"by {stretch:.2f} to {stretch * timing.step_duration:.3g} s, beyond "
            f"{MAX_STEP_DURATION:g} s; walk without --terrain-cadence, or with shorter "
            "steps (--step-duration)."
        )
    if stretch <= 1.0 + 1e-9:
        return footsteps, {}
    timing = replace(timing, step_duration=stretch * timing.step_duration)
    changes: dict[str, Any] = {"nb_steps": nb_steps, "duration": None}
    if plan.command is not None:
        changes["command"] = tuple(v / stretch for v in plan.command)
    return replace(footsteps, timing=timing), changes


def set_up_walk(spec: WalkSpec, robot: Robot | None = None) -> WalkSetup:
    """The walk of ``spec`` on ``robot`` (None: ``spec.robot`` loaded, with its meshes when
    the walk is filmed).

    Raises:
        MpcwalkError: Bad input (unknown robot or generator, infeasible command, bad file,
            a push after the walk's end...), before anything is simulated.
    """
    controller, plan, world = spec.controller, spec.plan, spec.world
    world.latency_periods(plan.control_period)  # whole control periods, checked now
    if robot is None:
        robot = load_robot(spec.robot, visual=spec.run.video is not None)
    check_step_height(robot, plan.step_height)
    check_walk_terrain(robot, world.terrain)
    if spec.run.video is not None:
        check_video_path(spec.run.video)
    check_controller(controller, world.actuation)
    timing = walk_timing(controller.generator, robot.gait, plan)
    nb_steps = plan.nb_steps
    if nb_steps is None and plan.duration is not None:
        nb_steps = max(1, int(round(plan.duration / timing.step_duration)))
    terrain = world.terrain if world.terrain is not None and not world.terrain.is_flat else None
    reach = None
    if terrain is not None:
        length, width = robot.sole_size
        reach = TerrainReach.for_leg(length, width, robot.leg_length)
    footsteps = plan_walk_footsteps(
        robot,
        command=plan.command,
        path=plan.path,
        nb_steps=nb_steps,
        timing=timing,
        terrain=terrain,
        reach=reach,
    )
    cadence: dict[str, Any] = {}
    if plan.terrain_cadence and terrain is not None:
        footsteps, cadence = _at_terrain_cadence(footsteps, robot, plan, nb_steps)
        timing = footsteps.timing
    schedule = ContactSchedule(footsteps, FootGeometry(*robot.sole_size))
    generator_class(controller.generator).check_timing(schedule, LIPM(com_height=robot.com_height))
    pushes = check_pushes(spec.disturbances.external_forces(), robot, schedule.duration)
    resolved = spec.replace(
        **cadence,
        terrain_cadence=False,
        step_duration=timing.step_duration,
        double_support_ratio=timing.double_support_ratio,
        step_height=robot.gait.step_height if plan.step_height is None else plan.step_height,
        state=world.state,
    )
    return WalkSetup(resolved, robot, timing, nb_steps, footsteps, schedule, pushes)


__all__ = ["WalkSetup", "check_walk_terrain", "set_up_walk"]
