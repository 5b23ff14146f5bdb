"""Walk a robot in MuJoCo: footsteps, controller, simulation, per-tick log, metrics.

:func:`run_walk` is the ``mpcwalk walk`` job: it plans footsteps (from a velocity command,
paper M eq. 5, or from a ``.mdat`` path file, paper A), builds a
:class:`~mpcwalk.control.controller.WalkingController` with the chosen pattern generator on the
robot's LIPM, simulates the position-controlled robot until the schedule ends or it falls,
and returns the per-tick log with the metrics of :mod:`mpcwalk.walking.metrics`.

Walking defaults come from the ``[gait]`` table of the robot's preset (step duration,
double-support ratio, swing height, leg limits, MPC horizon); arguments override them.
"""

import math
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from mpcwalk.control.controller import WalkingController
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import (
    FootGeometry,
    Footstep,
    FootstepPlan,
    StepTiming,
    wrap_angle,
)
from mpcwalk.footsteps.mdat import PathWaypoint, plan_from_path, read_mdat
from mpcwalk.footsteps.velocity_planner import (
    VelocityCommand,
    VelocityPlanner,
    as_velocity_command,
)
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.robot import Robot, load_robot
from mpcwalk.sim import ExternalForce, FallDetector, FallStatus, Simulation, SimulationUnstable
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics import compute_walk_metrics, yaw_deviation_deg
from mpcwalk.walking.result import WalkConfig, WalkResult


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

    def move(foot: Footstep) -> Footstep:
        return Footstep(
            foot.side,
            robot_mid + rotation @ (foot.position - mid0),
            float(wrap_angle(foot.yaw + turn)),
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

    Raises:
        ConfigurationError: Neither or both of ``command`` and ``path``.
        InfeasibleCommand: The command exceeds the robot's leg limits.
        FootstepFileError: The path file is malformed.
    """
    if (command is None) == (path is None):
        raise ConfigurationError(
            "A walk needs either a velocity command (vx, vy, vyaw) or a .mdat path file, "
            "not both and not neither."
        )
    left, right = robot.initial_feet()
    limits = robot.leg_limits
    if command is not None:
        if nb_steps is None:
            raise ConfigurationError(
                "A walk from a velocity command needs nb_steps (or a duration)."
            )
        return VelocityPlanner(limits, timing).plan(
            command, nb_steps, initial_left=left, initial_right=right
        )
    if path is None:  # excluded above; narrows the type
        raise ConfigurationError("A walk without a velocity command needs a .mdat path file.")
    waypoints = _path_in_robot_frame(read_mdat(path), left, right)
    plan = plan_from_path(waypoints, rectangle=limits.rectangle(), timing=timing)
    if nb_steps is not None and nb_steps < plan.nb_steps:
        plan = FootstepPlan(plan.initial_left, plan.initial_right, plan.steps[:nb_steps], timing)
    return plan


def run_walk(
    robot_name: str | Robot,
    generator: str = "mpc",
    *,
    command: VelocityCommand | Sequence[float] | None = None,
    path: str | Path | None = None,
    nb_steps: int | None = None,
    duration: float | None = None,
    step_duration: float | None = None,
    double_support_ratio: float | None = None,
    step_height: float | None = None,
    control_period: float = 0.01,
    pushes: Sequence[ExternalForce] = (),
    video: str | Path | None = None,
    progress: bool = False,
    feedback: bool = True,
    generator_options: dict | None = None,
    controller_options: dict | None = None,
    fall_detector: FallDetector | None = None,
    stabilizer=None,
    arm_swing: float = 0.0,
    yaw_reference: bool = False,
) -> WalkResult:
    """Simulate a walk of a robot in MuJoCo and measure it.

    Args:
        robot_name: Robot name (see ``mpcwalk robots``) or a loaded :class:`Robot` (load it
            with its meshes for a video).
        generator: Pattern generator name (see ``mpcwalk generators``).
        command: Velocity command ``(vx, vy, vyaw)`` in [m/s, m/s, rad/s].
        path: ``.mdat`` path file instead of a command.
        nb_steps: Number of steps (command: a closing step is added).
        duration: Walking time [s] instead of ``nb_steps``: ``round(duration / T)`` steps.
            The walk also stands still for 1 s before and after.
        step_duration: Step duration T [s] (default: the preset's, else 0.5 s).
        double_support_ratio: r_ds (default: the preset's, else 0.2).
        step_height: Swing-foot height [m] (default: the preset's, else 0.04 m).
        control_period: Controller tick [s], a multiple of the physics step.
        pushes: External forces on the robot during the walk.
        video: MP4 file to render the walk into (offscreen), or None.
        progress: Show a progress bar (off: a library is quiet).
        feedback: Close the loop on the measured CoM (see the controller).
        generator_options: Keyword arguments of the generator (override the preset's).
        controller_options: Keyword arguments of the controller (override the preset's).
        fall_detector: Fall detector (default: ``FallDetector.for_robot``).
        stabilizer: A stabilizer name (``"ankle-imu"``, ``"none"``), a
            :class:`~mpcwalk.control.stabilizers.Stabilizer`, or None.
        arm_swing: Paper M's arm movement factor s (eq. 24-25; paper M: 0.8, 0: arms still).
        yaw_reference: With ``pushes``, also simulate the same walk without them and report
            ``metrics.yaw_deviation_deg``, the largest yaw difference after the last push
            (paper M's measure of the stabilizer); doubles the cost.

    Returns:
        The walk, its log, metrics and configuration. A fall ends the run early (``result.fall``).

    Raises:
        MpcwalkError: Bad input (unknown robot or generator, infeasible command, bad file).
    """
    if command is not None:
        command = as_velocity_command(command)
    robot = (
        robot_name
        if isinstance(robot_name, Robot)
        else load_robot(robot_name, visual=video is not None)
    )
    gait = robot.gait
    period = float(gait.step_duration if step_duration is None else step_duration)
    timing = StepTiming(
        step_duration=period,
        double_support_ratio=float(
            gait.double_support_ratio if double_support_ratio is None else double_support_ratio
        ),
    )
    if nb_steps is None and duration is not None:
        if not (math.isfinite(duration) and duration > 0.0):
            raise ConfigurationError(
                f"duration must be a positive number of seconds, got {duration!r}."
            )
        nb_steps = max(1, int(round(duration / period)))
    plan = plan_walk_footsteps(robot, command=command, path=path, nb_steps=nb_steps, timing=timing)
    schedule = ContactSchedule(plan, FootGeometry(*robot.sole_size))
    options = {
        key: value
        for key, value in (("dcm_gain", gait.dcm_gain), ("observer_gain", gait.observer_gain))
        if value is not None
    }
    options.update(controller_options or {})
    if isinstance(stabilizer, str):
        from mpcwalk.control.stabilizers import make_stabilizer

        stabilizer = make_stabilizer(stabilizer)
    if arm_swing:
        options["arm_swing"] = arm_swing
    if stabilizer is not None:
        options["stabilizer"] = stabilizer
    controller = WalkingController.for_robot(
        robot,
        generator,
        schedule,
        control_period=control_period,
        feedback=feedback,
        step_height=gait.step_height if step_height is None else step_height,
        generator_options=generator_options,
        **options,
    )
    simulation = Simulation(robot, control_period=control_period, disturbances=pushes)
    detector = fall_detector or FallDetector.for_robot(robot)
    log, fall, wall_time = _simulate(
        robot, controller, simulation, detector, video, progress, f"{robot.name} {generator}"
    )
    schedule = controller.schedule  # with the footsteps a footstep-adaptive generator moved
    metrics = compute_walk_metrics(
        log,
        schedule,
        fall=fall,
        wall_time=wall_time,
        nb_generator_failures=controller.nb_generator_failures,
        closing_steps=1 if command is not None and plan.nb_steps else 0,
    )
    config = WalkConfig(
        robot=robot.name,
        generator=generator,
        command=None if command is None else (command.vx, command.vy, command.vyaw),
        path=None if path is None else str(path),
        duration_s=None if duration is None else float(duration),
        nb_steps=nb_steps,
        step_duration_s=timing.step_duration,
        double_support_ratio=timing.double_support_ratio,
        step_height_m=controller.trajectory.step_height,
        com_height_m=robot.com_height,
        control_period_s=control_period,
        stabilizer=getattr(stabilizer, "name", "none"),
        feedback=feedback,
        dcm_gain=controller.dcm_feedback.dcm_gain,
        observer_gain=controller.dcm_feedback.observer_gain,
        pushes=tuple((p.start, p.duration, *map(float, p.force)) for p in pushes),
        arm_swing=float(arm_swing),
    )
    if yaw_reference and pushes:
        reference = run_walk(
            robot,
            generator,
            command=command,
            path=path,
            nb_steps=nb_steps,
            step_duration=timing.step_duration,
            double_support_ratio=timing.double_support_ratio,
            step_height=step_height,
            control_period=control_period,
            progress=False,
            feedback=feedback,
            generator_options=generator_options,
            controller_options=controller_options,
            fall_detector=fall_detector,
            stabilizer=stabilizer,
            arm_swing=arm_swing,
        )
        after = max(p.start + p.duration for p in pushes)
        metrics = metrics.with_yaw_deviation(yaw_deviation_deg(log, reference.log, after))
    return WalkResult(robot.name, generator, schedule, log, fall, metrics, config)


def _simulate(
    robot,
    controller: WalkingController,
    simulation: Simulation,
    detector: FallDetector,
    video,
    progress: bool,
    label: str,
):
    """The control loop: (log, final fall status, loop wall time [s])."""
    from tqdm import tqdm

    recorder = None
    if video is not None:
        from mpcwalk.sim import VideoRecorder

        recorder = VideoRecorder(video, simulation.model)
    state = simulation.reset(robot.q0)
    output = controller.reset(robot.q0)
    log = WalkLog.recorder(robot, controller.schedule)
    fall = FallStatus(False, "", 0.0)
    nb_ticks = int(math.ceil(controller.schedule.duration / controller.control_period - 1e-9))
    bar = tqdm(total=nb_ticks, desc=label, unit="tick", disable=not progress, leave=False)
    start = time.perf_counter()
    try:
        if recorder is not None:
            recorder.capture(simulation.data, 0.0)
        while not controller.done:
            tick_start = time.perf_counter()
            output = controller.step(state.measurements)
            sim_start = time.perf_counter()
            try:
                state = simulation.step(output.joint_targets)
            except SimulationUnstable as error:
                fall = FallStatus(True, f"simulation diverged ({error})", simulation.time)
                break
            sim_time = time.perf_counter() - sim_start
            log.append(
                output,
                state,
                simulation.data.actuator_force,
                sim_time,
                time.perf_counter() - tick_start - sim_time,
            )
            if recorder is not None:
                recorder.capture(simulation.data, state.time)
            bar.update(1)
            fall = detector.check(state)
            if fall.fell:
                break
    finally:
        wall_time = time.perf_counter() - start
        bar.close()
        if recorder is not None:
            recorder.close()
    return log.freeze(), fall, wall_time
