"""Walk a robot in MuJoCo: :func:`run_walk` runs a :class:`~mpcwalk.walking.specification.WalkSpec`.

The ``mpcwalk walk`` job, in four steps, each its own function:

1. **set up** (:func:`~mpcwalk.walking.walk_setup.set_up_walk`): the robot, the timing, the
   footsteps (from a velocity command, paper M eq. 5, or a ``.mdat`` path file, paper A) and
   the contact schedule, every input checked before anything runs;
2. **build** (:func:`~mpcwalk.walking.controller_builder.build_controller`): the controller
   of the specification, the simulation of the world it walks in, the estimator;
3. **run** (:class:`~mpcwalk.walking.control_loop.ControlLoop`): the controller walks on what
   the robot senses, the simulator's ground truth feeding the metrics (or the controller
   behind ``state="oracle"``), until the schedule ends, the robot falls or the controller
   stops the walk;
4. **measure** (:func:`~mpcwalk.walking.metrics.compute_walk_metrics`) and **record**
   (:class:`~mpcwalk.walking.result.WalkConfig`, and the resolved specification itself).
"""

import dataclasses
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mpcwalk.control.controller import WalkingController
from mpcwalk.control.torque_controller import state_delay
from mpcwalk.estimation.estimator import Estimator
from mpcwalk.footsteps.velocity_planner import VelocityCommand
from mpcwalk.robot import Robot
from mpcwalk.sim import FallDetector, Simulation
from mpcwalk.sim.sensing.model import SensorModel
from mpcwalk.walking.control_loop import ControlLoop, LoopOutcome, with_outcome
from mpcwalk.walking.controller_builder import build_controller
from mpcwalk.walking.metrics import compute_walk_metrics, yaw_deviation_deg
from mpcwalk.walking.result import WalkConfig, WalkResult
from mpcwalk.walking.specification import ControllerSpec, WalkSpec
from mpcwalk.walking.walk_setup import WalkSetup, set_up_walk


def run_walk(
    spec: WalkSpec | str | Robot,
    *,
    controller: str | ControllerSpec | None = None,
    command: VelocityCommand | Sequence[float] | None = None,
    path: str | Path | None = None,
    nb_steps: int | None = None,
    duration: float | None = None,
    robot: Robot | None = None,
    observer: Callable[[float, np.ndarray], None] | None = None,
    fall_detector: FallDetector | None = None,
    on_controller: Callable[[WalkingController], None] | None = None,
) -> WalkResult:
    """Simulate a walk of a robot in MuJoCo and measure it.

    Either a whole specification, ``run_walk(spec)``, or its short form for the common
    case, ``run_walk("bioloid-like", controller="mpc", command=(0.1, 0, 0), nb_steps=8)``
    (any other field: ``run_walk(WalkSpec.build("bioloid-like", noise_scale=2.0, ...))``).
    The short form's keywords given beside a specification change those fields of it.

    Args:
        spec: The walk, or a robot name (a loaded :class:`Robot` is taken as ``robot``).
        controller: A named controller (``mpcwalk controllers``) or a
            :class:`~mpcwalk.walking.specification.ControllerSpec`.
        command: Velocity command ``(vx, vy, vyaw)`` in [m/s, m/s, rad/s].
        path: ``.mdat`` path file instead of a command.
        nb_steps: Number of steps (command: a closing step is added).
        duration: Walking time [s] instead of ``nb_steps``.
        robot: The loaded robot of ``spec.robot`` (a sweep worker's copy, a modified robot);
            None: loaded from the specification.
        observer: Called after every tick with the time [s] and MuJoCo's ``qpos`` (a live
            view, :class:`~mpcwalk.viewer.live.LiveView`).
        fall_detector: Fall detector (default: ``FallDetector.for_robot`` on the walk's
            terrain).
        on_controller: Called once with the controller of the walk when it is built,
            before it is reset and the walk starts (to look inside it: the solver benchmark
            records the inverse dynamics' QPs and solve times through it).

    Returns:
        The walk, its log, metrics, configuration and resolved specification. A fall ends
        the run early (``result.fall``).

    Raises:
        MpcwalkError: Bad input (unknown robot or generator, infeasible command, bad file),
            before anything runs.
    """
    if isinstance(spec, Robot):
        robot = spec
        spec = spec.name
    short: dict[str, Any] = {
        key: value
        for key, value in (
            ("command", command),
            ("path", path),
            ("nb_steps", nb_steps),
            ("duration", duration),
        )
        if value is not None
    }
    if controller is not None:
        short["controller"] = controller
    if not isinstance(spec, WalkSpec):
        spec = WalkSpec.build(spec, **short)
    elif short:
        spec = spec.replace(**short)
    setup = set_up_walk(spec, robot)
    result = _walk(
        setup, observer=observer, fall_detector=fall_detector, on_controller=on_controller
    )
    disturbances = setup.spec.disturbances
    if disturbances.yaw_reference and disturbances.pushes and not result.metrics.interrupted:
        undisturbed = setup.spec.replace(
            pushes=(),
            sensor_nan=(),
            sensor_dropout=(),
            yaw_reference=False,
            progress=False,
            video=None,
        )
        reference = _walk(set_up_walk(undisturbed, setup.robot), fall_detector=fall_detector)
        after = max(push.start + push.duration for push in setup.pushes)
        metrics = result.metrics.with_yaw_deviation(
            yaw_deviation_deg(result.log, reference.log, after)
        )
        result = dataclasses.replace(result, metrics=metrics)
    return result


def _walk(
    setup: WalkSetup,
    *,
    observer: Callable[[float, np.ndarray], None] | None = None,
    fall_detector: FallDetector | None = None,
    on_controller: Callable[[WalkingController], None] | None = None,
) -> WalkResult:
    """Build, run, measure and record the walk of ``setup``."""
    spec, robot = setup.spec, setup.robot
    plan, world, run = spec.plan, spec.world, spec.run
    period = plan.control_period
    estimator = (
        Estimator(  # tuned to the robot's data sheet, whatever the world's sensors do
            robot,
            control_period=period,
            encoder_resolution=SensorModel.for_robot(robot).encoder_resolution,
            terrain=world.terrain,  # the robot's map of the ground
        )
        if world.state == "estimator"
        else None
    )
    walker = build_controller(
        robot,
        spec.controller,
        setup.schedule,
        control_period=period,
        step_height=setup.step_height,
        terrain=world.terrain,
        actuation=world.actuation,
        state_delay=state_delay(
            period,
            latency=world.to_config(robot, period, run.seed)["latency_s"],
            velocity_cutoff=(
                None if estimator is None else estimator.joint_velocities.cutoff_frequency
            ),
        ),
    )
    if on_controller is not None:
        on_controller(walker)
    simulation = Simulation(
        robot,
        control_period=period,
        pushes=setup.pushes,
        sensors=world.sensor_model(robot, period),
        model_mismatch=world.model_mismatch,
        seed=run.seed,
        ground=world.ground(seed=run.seed),
        terrain=world.terrain,
        actuation=world.actuation,
    )
    detector = fall_detector or FallDetector.for_robot(robot, terrain=world.terrain)
    faults = spec.disturbances.sensor_faults
    outcome = ControlLoop(robot, walker, simulation, estimator, detector, faults).run(
        video=run.video,
        progress=run.progress,
        label=f"{robot.name} {spec.controller.generator}",
        observer=observer,
    )
    schedule = setup.schedule
    if walker.heading_hold is None:  # with the footsteps a footstep-adaptive generator moved
        schedule = walker.schedule
    # else the plan as commanded: the heading hold turned the footsteps to reach it
    metrics = compute_walk_metrics(
        outcome.log,
        schedule,
        fall=outcome.fall,
        wall_time=outcome.wall_time,
        nb_generator_failures=walker.nb_generator_failures,
        closing_steps=1 if plan.command is not None and setup.plan.nb_steps else 0,
        state_source=setup.state_source,
        terrain=world.terrain,
        com_height=robot.com_height,
    )
    metrics = with_outcome(metrics, outcome, walker.faults)
    if walker.notes:  # what the controller left out of its specification (arms to swing)
        metrics = dataclasses.replace(metrics, warnings=(*walker.notes, *metrics.warnings))
    config = _config(setup, walker, outcome)
    generator = spec.controller.generator
    return WalkResult(
        robot.name, generator, schedule, outcome.log, outcome.fall, metrics, config, spec
    )


def _config(setup: WalkSetup, walker, outcome: LoopOutcome) -> WalkConfig:
    """The ``config`` block of ``metrics.json``: how the walk was set up, as it ran."""
    spec, robot = setup.spec, setup.robot
    plan, controller = spec.plan, spec.controller
    stabilizer = walker.stabilizer
    return WalkConfig(
        robot=robot.name,
        generator=controller.generator,
        command=plan.command,
        path=plan.path,
        duration_s=plan.duration,
        nb_steps=setup.nb_steps,
        step_duration_s=setup.timing.step_duration,
        double_support_ratio=setup.timing.double_support_ratio,
        step_height_m=walker.trajectory.step_height,
        com_height_m=robot.com_height,
        control_period_s=plan.control_period,
        stabilizer=getattr(stabilizer, "name", "none"),
        balance=walker.balance is not None,
        feedback=controller.feedback,
        dcm_gain=walker.dcm_feedback.dcm_gain,
        observer_gain=walker.dcm_feedback.observer_gain,
        pushes=tuple((p.start, p.duration, *map(float, p.force)) for p in setup.pushes),
        arm_swing=float(controller.arm_swing),
        **spec.world.to_config(robot, plan.control_period, spec.run.seed),
    )


__all__ = ["run_walk"]
