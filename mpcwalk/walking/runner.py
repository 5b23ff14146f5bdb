"""Walk a robot in MuJoCo: footsteps, controller, simulation, per-tick log, metrics.

:func:`run_walk` is the ``mpcwalk walk`` job: it plans footsteps (from a velocity command,
paper M eq. 5, or from a ``.mdat`` path file, paper A), builds a
:class:`~mpcwalk.control.controller.WalkingController` with the chosen pattern generator on the
robot's LIPM, simulates the position-controlled robot until the schedule ends or it falls,
and returns the per-tick log with the metrics of :mod:`mpcwalk.walking.metrics`.

The controller walks on what the robot senses (:mod:`mpcwalk.walking.control_loop`): the
sensor readings of the simulation, noisy and delayed as the robot's sensor model says, go
through the estimator; the ground truth feeds the metrics, or the controller behind
``state="oracle"``. The sensors, the state source and the perturbation of the simulated
robot are options (:class:`~mpcwalk.walking.world_options.WorldOptions`).

Walking defaults come from the ``[gait]`` table of the robot's preset (step duration,
double-support ratio, swing height, leg limits, MPC horizon); arguments override them.
"""

import math
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from mpcwalk.control.controller import WalkingController
from mpcwalk.estimation.estimator import Estimator
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import (
    FootGeometry,
)
from mpcwalk.footsteps.velocity_planner import (
    VelocityCommand,
    as_velocity_command,
)
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators import generator_class
from mpcwalk.models.lipm import LIPM
from mpcwalk.robot import Robot, load_robot
from mpcwalk.sim import ExternalForce, FallDetector, Simulation
from mpcwalk.sim.perturbation import Perturbation
from mpcwalk.sim.sensor_faults import SensorFaults
from mpcwalk.sim.sensor_model import SensorModel
from mpcwalk.walking.control_loop import ControlLoop, with_outcome
from mpcwalk.walking.controller_resolution import default_timing, resolve_controller
from mpcwalk.walking.footstep_planning import plan_walk_footsteps
from mpcwalk.walking.inputs import check_options, check_pushes, check_walk_numbers
from mpcwalk.walking.metrics import compute_walk_metrics, yaw_deviation_deg
from mpcwalk.walking.outputs import check_video_path
from mpcwalk.walking.result import WalkConfig, WalkResult
from mpcwalk.walking.world_options import WorldOptions


def run_walk(
    robot_name: str | Robot,
    generator: str | None = None,
    *,
    controller: str | None = None,
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
    feedback: bool | None = None,
    generator_options: dict | None = None,
    controller_options: dict | None = None,
    fall_detector: FallDetector | None = None,
    stabilizer=None,
    arm_swing: float | None = None,
    yaw_reference: bool = False,
    noise_scale: float = 1.0,
    latency: float | None = None,
    ideal: bool = False,
    state: str | None = None,
    perturbation: Perturbation | None = None,
    mass_scale: float | None = None,
    com_offset: tuple[float, float] | None = None,
    friction: float | None = None,
    servo_strength: float | None = None,
    seed: int = 0,
    sensor_faults: SensorFaults | None = None,
    ground_tilt: float = 0.0,
    ground_tilt_direction: float = 0.0,
    ground_roughness: float = 0.0,
    observer: Callable[[float, np.ndarray], None] | None = None,
) -> WalkResult:
    """Simulate a walk of a robot in MuJoCo and measure it.

    Args:
        robot_name: Robot name (see ``mpcwalk robots``) or a loaded :class:`Robot` (load it
            with its meshes for a video).
        generator: Pattern generator name (see ``mpcwalk generators``; default ``"mpc"``).
        controller: A named controller configuration (see ``mpcwalk controllers``:
            ``paper-m``, ``paper-m-open``, ``paper-a``, ``mpc``...): its generator, feedback,
            stabilizer, arm swing, re-aiming and swing profile; then ``generator``,
            ``feedback``, ``stabilizer`` and ``arm_swing`` must not be given.
        command: Velocity command ``(vx, vy, vyaw)`` in [m/s, m/s, rad/s].
        path: ``.mdat`` path file instead of a command.
        nb_steps: Number of steps (command: a closing step is added).
        duration: Walking time [s] instead of ``nb_steps``: ``round(duration / T)`` steps.
            The walk also stands still for 1 s before and after.
        step_duration: Step duration T [s] (default: the generator's own timing if it has
            one, e.g. paper A's 12 s for the static gaits, else the preset's, else 0.5 s).
        double_support_ratio: r_ds (default: the generator's, else the preset's, else 0.2).
        step_height: Swing-foot height [m] (default: the preset's, else 0.04 m).
        control_period: Controller tick [s], a multiple of the physics step.
        pushes: External forces on the robot during the walk.
        video: MP4 file to render the walk into (offscreen), or None.
        progress: Show a progress bar (off: a library is quiet).
        feedback: Close the loop on the estimated CoM (see the controller; default: on).
        generator_options: Keyword arguments of the generator (override the preset's).
        controller_options: Keyword arguments of the controller (override the preset's).
        fall_detector: Fall detector (default: ``FallDetector.for_robot``).
        stabilizer: A stabilizer name (``"ankle-imu"``, ``"none"``), a
            :class:`~mpcwalk.control.stabilizers.Stabilizer`, or None.
        arm_swing: Paper M's arm movement factor s (eq. 24-25; paper M: 0.8, 0: arms still).
        yaw_reference: With ``pushes``, also simulate the same walk without them and report
            ``metrics.yaw_deviation_deg``, the largest yaw difference after the last push
            (paper M's measure of the stabilizer); doubles the cost.
        noise_scale: Factor on the noise and bias of the robot's sensor model (0: exact
            sensors).
        latency: Sensing-to-actuation latency [s], a multiple of ``control_period`` (None:
            the sensor model's, one control period).
        ideal: Exact sensors, no latency and (unless ``state`` says otherwise) the
            controller on the ground truth: the simulator as it was before sensing.
        state: ``"estimator"`` (the controller's state is estimated from the sensors, the
            default) or ``"oracle"`` (the simulator's ground truth, for comparison).
        perturbation: How the simulated robot differs from the controller's model
            (:class:`~mpcwalk.sim.perturbation.Perturbation`), or its keywords:
        mass_scale: Factor on the torso mass of the simulated robot.
        com_offset: Shift ``(dx, dy)`` [m] of the torso's CoM of the simulated robot.
        friction: Friction coefficient of the floor contacts (None: the model's).
        servo_strength: Factor on the servos' gains and torque limits.
        seed: Seed of the sensor noise (and of the ground's bumps).
        sensor_faults: Faults injected into the sensor stream
            (:class:`~mpcwalk.sim.sensor_faults.SensorFaults`: NaN and dropped readings).
        ground_tilt: Slope of the ground [deg], up towards ``ground_tilt_direction`` [deg]
            (0: forward); ``ground_roughness``: its bumps' largest height [m]
            (:class:`~mpcwalk.robot.ground.Ground`).
        observer: Called after every tick with the time [s] and MuJoCo's ``qpos`` (a live
            view, :class:`~mpcwalk.viewer.live.LiveView`).

    Returns:
        The walk, its log, metrics and configuration. A fall ends the run early (``result.fall``).

    Raises:
        MpcwalkError: Bad input (unknown robot or generator, infeasible command, bad file).
    """
    world = WorldOptions.build(
        noise_scale=noise_scale,
        latency=latency,
        ideal=ideal,
        state=state,
        perturbation=perturbation,
        mass_scale=mass_scale,
        com_offset=com_offset,
        friction=friction,
        servo_strength=servo_strength,
        seed=seed,
        ground_tilt=ground_tilt,
        ground_tilt_direction=ground_tilt_direction,
        ground_roughness=ground_roughness,
    )
    world.latency_periods(control_period)  # a latency of whole control periods, checked now
    if command is not None:
        command = as_velocity_command(command)
    robot = (
        robot_name
        if isinstance(robot_name, Robot)
        else load_robot(robot_name, visual=video is not None)
    )
    check_walk_numbers(
        robot,
        nb_steps=nb_steps,
        duration=duration,
        step_duration=step_duration,
        double_support_ratio=double_support_ratio,
        step_height=step_height,
        control_period=control_period,
        arm_swing=arm_swing,
    )
    if video is not None:
        check_video_path(video)
    parts = resolve_controller(
        controller,
        generator=generator,
        feedback=feedback,
        stabilizer=stabilizer,
        arm_swing=arm_swing,
        generator_options=generator_options,
        controller_options=controller_options,
    )
    generator, feedback, stabilizer = parts.generator, parts.feedback, parts.stabilizer
    arm_swing, generator_options = parts.arm_swing, parts.generator_options
    controller_options = parts.controller_options
    check_options(WalkingController, controller_options, "controller")
    check_options(generator_class(generator), generator_options, f"generator '{generator}'")
    gait = robot.gait
    timing = default_timing(generator, gait, step_duration, double_support_ratio)
    period = timing.step_duration
    if nb_steps is None and duration is not None:
        if not (math.isfinite(duration) and duration > 0.0):
            raise ConfigurationError(
                f"duration must be a positive number of seconds, got {duration!r}."
            )
        nb_steps = max(1, int(round(duration / period)))
    plan = plan_walk_footsteps(robot, command=command, path=path, nb_steps=nb_steps, timing=timing)
    schedule = ContactSchedule(plan, FootGeometry(*robot.sole_size))
    generator_class(generator).check_timing(schedule, LIPM(com_height=robot.com_height))
    pushes = check_pushes(pushes, robot, schedule.duration)
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
    walker = WalkingController.for_robot(
        robot,
        generator,
        schedule,
        control_period=control_period,
        feedback=feedback,
        step_height=gait.step_height if step_height is None else step_height,
        generator_options=generator_options,
        **options,
    )
    simulation = Simulation(
        robot,
        control_period=control_period,
        disturbances=pushes,
        sensors=world.sensor_model(robot, control_period),
        perturbation=world.perturbation,
        seed=world.seed,
        ground=world.ground,
    )
    estimator = (
        Estimator(  # tuned to the robot's data sheet, whatever the world's sensors do
            robot,
            control_period=control_period,
            encoder_resolution=SensorModel.for_robot(robot).encoder_resolution,
        )
        if world.state == "estimator"
        else None
    )
    detector = fall_detector or FallDetector.for_robot(robot)
    outcome = ControlLoop(robot, walker, simulation, estimator, detector, sensor_faults).run(
        video=video, progress=progress, label=f"{robot.name} {generator}", observer=observer
    )
    log, fall = outcome.log, outcome.fall
    if walker.heading_hold is None:  # with the footsteps a footstep-adaptive generator moved
        schedule = walker.schedule
    # else the plan as commanded: the heading hold turned the footsteps to reach it
    metrics = compute_walk_metrics(
        log,
        schedule,
        fall=fall,
        wall_time=outcome.wall_time,
        nb_generator_failures=walker.nb_generator_failures,
        closing_steps=1 if command is not None and plan.nb_steps else 0,
        state_source=world.state,
    )
    metrics = with_outcome(metrics, outcome, walker.faults)
    config = WalkConfig(
        robot=robot.name,
        generator=generator,
        command=None if command is None else (command.vx, command.vy, command.vyaw),
        path=None if path is None else str(path),
        duration_s=None if duration is None else float(duration),
        nb_steps=nb_steps,
        step_duration_s=timing.step_duration,
        double_support_ratio=timing.double_support_ratio,
        step_height_m=walker.trajectory.step_height,
        com_height_m=robot.com_height,
        control_period_s=control_period,
        stabilizer=getattr(stabilizer, "name", "none"),
        balance=walker.balance is not None,
        feedback=feedback,
        dcm_gain=walker.dcm_feedback.dcm_gain,
        observer_gain=walker.dcm_feedback.observer_gain,
        pushes=tuple((p.start, p.duration, *map(float, p.force)) for p in pushes),
        arm_swing=float(arm_swing),
        **world.to_config(robot, control_period),
    )
    if yaw_reference and pushes and not outcome.interrupted:
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
            noise_scale=world.noise_scale,
            latency=world.latency,
            ideal=world.ideal,
            state=world.state,
            perturbation=world.perturbation,
            seed=world.seed,
            ground_tilt=ground_tilt,
            ground_tilt_direction=ground_tilt_direction,
            ground_roughness=ground_roughness,
        )
        after = max(p.start + p.duration for p in pushes)
        metrics = metrics.with_yaw_deviation(yaw_deviation_deg(log, reference.log, after))
    return WalkResult(robot.name, generator, schedule, log, fall, metrics, config)
