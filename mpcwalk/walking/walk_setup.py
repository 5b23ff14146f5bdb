"""From a walk's specification to the parts of a walk, checked before anything runs:
:func:`set_up_walk` returns a :class:`WalkSetup`.

The robot is loaded, the controller's configuration checked, the timing decided (the plan's,
else the generator's own, else the robot preset's), the footsteps planned and the contact
schedule made, the pushes checked against the robot and the walk's length; the
specification comes back *resolved*: the defaults it left to the robot spelled out, so that
the ``spec.toml`` written next to the results walks the same walk again.
"""

import dataclasses
import math
from dataclasses import dataclass

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import FootGeometry, FootstepPlan, StepTiming
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators import generator_class
from mpcwalk.models.lipm import LIPM
from mpcwalk.robot import Robot, load_robot
from mpcwalk.sim import ExternalForce
from mpcwalk.walking.controller_builder import check_controller, walk_timing
from mpcwalk.walking.footstep_planning import plan_walk_footsteps
from mpcwalk.walking.inputs import check_pushes, check_step_height
from mpcwalk.walking.outputs import check_video_path
from mpcwalk.walking.spec import WalkSpec


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
    if spec.run.video is not None:
        check_video_path(spec.run.video)
    check_controller(controller)
    timing = walk_timing(controller.generator, robot.gait, plan)
    nb_steps = plan.nb_steps
    if nb_steps is None and plan.duration is not None:
        nb_steps = max(1, int(round(plan.duration / timing.step_duration)))
    if not math.isfinite(timing.step_duration):  # pragma: no cover - checked by the plan
        raise ConfigurationError(f"step duration {timing.step_duration!r} is not finite.")
    footsteps = plan_walk_footsteps(
        robot, command=plan.command, path=plan.path, nb_steps=nb_steps, timing=timing
    )
    schedule = ContactSchedule(footsteps, FootGeometry(*robot.sole_size))
    generator_class(controller.generator).check_timing(schedule, LIPM(com_height=robot.com_height))
    pushes = check_pushes(spec.disturbances.external_forces(), robot, schedule.duration)
    resolved = spec.replace(
        step_duration=timing.step_duration,
        double_support_ratio=timing.double_support_ratio,
        step_height=robot.gait.step_height if plan.step_height is None else plan.step_height,
        state=world.state,
    )
    resolved = dataclasses.replace(resolved, robot=spec.robot)
    return WalkSetup(resolved, robot, timing, nb_steps, footsteps, schedule, pushes)


__all__ = ["WalkSetup", "set_up_walk"]
