"""Whole-loop timing of walks in MuJoCo, per robot and generator, with the IK
beside pink on the same tasks (issue figures: real-time factor, generator tick,
IK tick, MuJoCo step), and the floor of each robot's loop: the same robot in the same
simulation with its actuators holding the nominal posture and no controller
(:func:`physics_floor`).

Each walk runs in this process, one after the other, with the same settings as
``mpcwalk walk``; the IK comparison is :func:`mpcwalk.bench.ik.run_ik_benchmark`
in the same run.
"""

import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from mpcwalk.bench.ik import IKBenchCase

#: The walks the robots/MuJoCo issue asks for: (robot, generator, command (vx, vy, vyaw),
#: number of steps, step duration or None for the preset's).
TURN = 0.349066  # [rad/s] 20 deg/s, paper M's turning walk
DEFAULT_WALKS = (
    ("bioloid-like", "analytic", (0.1, 0.0, 0.0), 20, None),
    ("bioloid-like", "preview", (0.1, 0.0, 0.0), 20, None),
    ("bioloid-like", "mpc", (0.1, 0.0, 0.0), 20, None),
    ("bioloid-like", "analytic", (0.1, 0.0, TURN), 20, None),
    ("bioloid-like", "preview", (0.1, 0.0, TURN), 20, None),
    ("bioloid-like", "mpc", (0.1, 0.0, TURN), 20, None),
    ("atlas-like", "mpc", (0.2, 0.0, 0.0), 10, 1.0),
    ("g1", "mpc", (0.2, 0.0, 0.0), 10, None),
)


@dataclass(frozen=True)
class LoopCase:
    """Timing of one walk.

    Attributes:
        robot: Robot name.
        generator: Pattern generator.
        command: Velocity command (vx [m/s], vy [m/s], vyaw [rad/s]).
        step_duration_s: Step duration, in [s].
        fell: Whether the robot fell.
        steps_completed: Steps landed.
        time_simulated_s: Simulated time, in [s].
        real_time_factor: Simulated time / wall time of the whole loop.
        generator_tick_us: Median generator tick, in [us].
        ik_tick_us: Median IK tick, in [us].
        controller_tick_us: Median whole controller tick (generator, trajectories, IK,
            feedback and stabilizers), in [us].
        estimator_tick_us: Median estimator tick (the state from the sensor readings), in
            [us].
        mujoco_step_us: Median physics time per control period (with sensors), in [us].
        distance_m: Distance travelled by the CoM, in [m].
        distance_planned_m: Distance between the start and end midpoints of the plan, in [m].
        yaw_change_deg: Yaw of the base at the end, in [deg].
        foot_position_error_cm_mean: Landed against planned footsteps, world frame, in [cm].
        foot_position_error_cm_max: In [cm].
        foot_yaw_error_deg_max: In [deg].
        cop_margin_p05_m: 5th percentile of the measured CoP margin, in [m].
        physics_floor_rtf: Real-time factor of MuJoCo alone on this robot (its actuators
            holding the nominal posture, no controller, no sensors): the limit of the loop.
        simulation_floor_rtf: Same with the simulation's ground truth and sensor readings of
            every control period (what the loop's simulation side costs without a controller).
    """

    robot: str
    generator: str
    command: tuple[float, float, float]
    step_duration_s: float
    fell: bool
    steps_completed: int
    time_simulated_s: float
    real_time_factor: float
    generator_tick_us: float
    ik_tick_us: float
    controller_tick_us: float
    estimator_tick_us: float
    mujoco_step_us: float
    distance_m: float
    distance_planned_m: float
    yaw_change_deg: float
    foot_position_error_cm_mean: float
    foot_position_error_cm_max: float
    foot_yaw_error_deg_max: float
    cop_margin_p05_m: float
    physics_floor_rtf: float = float("nan")
    simulation_floor_rtf: float = float("nan")

    @property
    def controller_overhead_us(self) -> float:
        """The controller's tick less its generator and its IK (the estimator runs beside
        the controller and is timed apart): the controller's own work (trajectories,
        feedback, stabilizers, feed-forward, fault checks), in [us]."""
        return self.controller_tick_us - self.generator_tick_us - self.ik_tick_us


@dataclass(frozen=True)
class PhysicsFloor:
    """The loop's floor on one robot: simulated time over wall time.

    Attributes:
        robot: Robot name.
        physics_rtf: MuJoCo's steps alone (``mj_step`` per physics step, the actuators
            holding the nominal posture).
        simulation_rtf: :meth:`mpcwalk.sim.Simulation.step` (the same steps, plus the ground
            truth and the sensor readings of each control period).
        physics_us: Median wall time of the physics steps of one control period, in [us].
        simulation_us: Median wall time of one :meth:`~mpcwalk.sim.Simulation.step`, in [us].
    """

    robot: str
    physics_rtf: float
    simulation_rtf: float
    physics_us: float
    simulation_us: float


def physics_floor(
    robot_name: str, *, duration: float = 5.0, control_period: float = 0.01
) -> PhysicsFloor:
    """Time MuJoCo alone on ``robot_name`` standing with its actuators holding ``q0``.

    Args:
        robot_name: Robot to load.
        duration: Simulated time of each of the two runs [s].
        control_period: Control period [s] (the physics step is the robot's).
    """
    import mujoco

    from mpcwalk.robot import load_robot
    from mpcwalk.sim import Simulation

    robot = load_robot(robot_name, visual=False)
    simulation = Simulation(robot, control_period=control_period, seed=0)
    nb_ticks = int(round(duration / control_period))
    simulation.reset(robot.q0)
    model, data, substeps = simulation.model, simulation.data, simulation.nb_substeps
    physics = np.empty(nb_ticks)
    start = time.perf_counter()
    for k in range(nb_ticks):
        tick = time.perf_counter()
        mujoco.mj_step(model, data, substeps)
        physics[k] = time.perf_counter() - tick
    physics_wall = time.perf_counter() - start
    simulation.reset(robot.q0)
    targets = robot.q0[7:]
    steps = np.empty(nb_ticks)
    start = time.perf_counter()
    for k in range(nb_ticks):
        tick = time.perf_counter()
        simulation.step(targets)
        steps[k] = time.perf_counter() - tick
    simulation_wall = time.perf_counter() - start
    simulated = nb_ticks * control_period
    return PhysicsFloor(
        robot=robot_name,
        physics_rtf=simulated / physics_wall,
        simulation_rtf=simulated / simulation_wall,
        physics_us=float(np.median(physics) * 1e6),
        simulation_us=float(np.median(steps) * 1e6),
    )


def run_loop_benchmark(walks=DEFAULT_WALKS, *, progress: bool = True) -> list[LoopCase]:
    """Run every walk and collect its metrics and timing.

    Args:
        walks: ``(robot, generator, command, nb_steps, step_duration)`` tuples.
        progress: Show a progress bar over the walks.
    """
    from tqdm import tqdm

    from mpcwalk.walking.runner import run_walk
    from mpcwalk.walking.specification import WalkSpec

    floors: dict[str, PhysicsFloor] = {}
    cases = []
    for robot, generator, command, nb_steps, step_duration in tqdm(
        walks, desc="walks", disable=not progress
    ):
        spec = WalkSpec.build(
            robot,
            generator=generator,
            command=command,
            nb_steps=nb_steps,
            step_duration=step_duration,
        )
        result = run_walk(spec)
        m, config = result.metrics, result.config
        if robot not in floors:
            floors[robot] = physics_floor(robot, control_period=float(config.control_period_s))
        floor = floors[robot]
        cases.append(
            LoopCase(
                robot=robot,
                generator=generator,
                command=(float(command[0]), float(command[1]), float(command[2])),
                step_duration_s=float(config.step_duration_s),
                fell=bool(m.fell),
                steps_completed=int(m.steps_completed),
                time_simulated_s=float(m.time_simulated_s),
                real_time_factor=float(m.real_time_factor or 0.0),
                generator_tick_us=float(m.generator_tick_us_median or 0.0),
                ik_tick_us=float(m.ik_tick_us_median or 0.0),
                controller_tick_us=float(m.controller_tick_us_median or 0.0),
                estimator_tick_us=float(m.estimator_tick_us_median or 0.0),
                mujoco_step_us=float(m.mujoco_step_us_median or 0.0),
                distance_m=float(m.distance_m),
                distance_planned_m=float(m.distance_planned_m),
                yaw_change_deg=float(m.yaw_change_deg),
                foot_position_error_cm_mean=float(m.foot_position_error_cm_mean or 0.0),
                foot_position_error_cm_max=float(m.foot_position_error_cm_max or 0.0),
                foot_yaw_error_deg_max=float(m.foot_yaw_error_deg_max or 0.0),
                cop_margin_p05_m=float(m.cop_margin_p05_m or 0.0),
                physics_floor_rtf=floor.physics_rtf,
                simulation_floor_rtf=floor.simulation_rtf,
            )
        )
    return cases


def format_loop_table(cases: Sequence[LoopCase]) -> str:
    """Markdown tables of the walks: what they did, then what they cost."""
    lines = [
        "| robot | generator | command (vx, vy, vyaw) | T [s] | fell | steps | distance (planned) [m] "
        "| yaw [deg] | foot error mean / max [cm] | foot yaw error max [deg] | CoP margin p5 [cm] |",
        "|---|---|---|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    for c in cases:
        lines.append(
            f"| {c.robot} | {c.generator} | {c.command[0]:g}, {c.command[1]:g}, {c.command[2]:.2f} | "
            f"{c.step_duration_s:g} | {'yes' if c.fell else 'no'} | {c.steps_completed} | "
            f"{c.distance_m:.3f} ({c.distance_planned_m:.3f}) | {c.yaw_change_deg:.1f} | "
            f"{c.foot_position_error_cm_mean:.2f} / {c.foot_position_error_cm_max:.2f} | "
            f"{c.foot_yaw_error_deg_max:.2f} | {100 * c.cop_margin_p05_m:.2f} |"
        )
    lines += [
        "",
        "| robot | generator | command | real-time factor | floor: physics / simulation "
        "(real-time factor) | estimator [us] | generator [us] | IK [us] | controller [us] | "
        "controller overhead [us] | MuJoCo and sensors [us] |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for c in cases:
        lines.append(
            f"| {c.robot} | {c.generator} | {c.command[0]:g}, {c.command[1]:g}, {c.command[2]:.2f} | "
            f"{c.real_time_factor:.1f} | {c.physics_floor_rtf:.0f} / {c.simulation_floor_rtf:.0f} | "
            f"{c.estimator_tick_us:.0f} | {c.generator_tick_us:.0f} | {c.ik_tick_us:.0f} | "
            f"{c.controller_tick_us:.0f} | {c.controller_overhead_us:.0f} | "
            f"{c.mujoco_step_us:.0f} |"
        )
    return "\n".join(lines)


def loop_report(
    cases: Sequence[LoopCase], ik: "Sequence[IKBenchCase]", *, command_line: str
) -> str:
    """``loop.md``: what was timed, on which machine, the command line that reproduces it,
    the walks (:func:`format_loop_table`) and the IK beside pink on the same robots
    (:func:`~mpcwalk.bench.ik.format_ik_table`)."""
    from mpcwalk.bench.ik import format_ik_table
    from mpcwalk.bench.output import machine_description

    return (
        f"The walks of the robots/MuJoCo issue in MuJoCo, control period 10 ms, one process, "
        f"walks one after the other, on the estimated state with the default sensor noise and "
        f"latency; medians per tick. Floor: the same robot standing in the same simulation, "
        f"its actuators holding the nominal posture, no controller: MuJoCo's steps alone, "
        f"then with the ground truth and sensor readings of each period. Controller overhead: "
        f"the controller's tick less its generator and its IK (the estimator runs beside it, "
        f"timed apart). Machine: {machine_description()}.\n"
        f"Command: `{command_line}`\n\n"
        + format_loop_table(cases)
        + "\n\nIK tick, ours beside pink on the same tasks, robot and motion (same run):\n\n"
        + format_ik_table(list(ik))
        + "\n"
    )


def loop_payload(cases: Sequence[LoopCase], ik: "Sequence[IKBenchCase]") -> dict[str, list]:
    """``loop.json``: every walk (with its controller overhead) and every IK row."""
    walks = [{**asdict(c), "controller_overhead_us": c.controller_overhead_us} for c in cases]
    return {"walks": walks, "ik": [asdict(r) for r in ik]}
