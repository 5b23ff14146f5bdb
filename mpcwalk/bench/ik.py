"""Per-tick time of the whole-body IK, ours beside pink, on the same tasks and motion.

Both IKs get the same tasks (CoM, both soles in SE3, torso orientation, posture towards
``q0``) with the same weights, Levenberg-Marquardt and Tikhonov damping, the same joint
position limits (gain 0.5) and velocity limits, on the same robot and the same motion: the
CoM sways sideways towards the left foot while the right foot lifts, and the torso yaws, for
2 s at 100 Hz. Each tick is timed from the configuration and the targets to the next
configuration (kinematics, task set-up, QP, integration); the tracking errors of the next
configuration are measured outside the timed part, with the same forward kinematics for both.
Ratios are taken against pink with DAQP measured in the same run.
"""

import logging
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from mpcwalk.ik import IKTargets, IKWeights, WholeBodyIK
from mpcwalk.robot import Robot, load_robot

DEFAULT_ROBOTS = ("bioloid-like", "atlas-like", "g1")
DEFAULT_PINK_SOLVERS = ("daqp", "quadprog", "proxqp")


@dataclass(frozen=True)
class IKBenchCase:
    """Result of one IK on one robot.

    Attributes:
        robot: Robot name.
        label: Row name.
        implementation: ``"mpcwalk"`` or ``"pink"``.
        solver: QP back-end.
        nb_ticks: Number of timed ticks (the first one, with lazy set-up, is left out).
        median_us: Median tick, in [us].
        p99_us: 99th percentile tick, in [us].
        ratio_to_pink: median / median of pink with DAQP on the same robot, same run.
        com_error_max_mm: Largest CoM tracking error after a tick, in [mm].
        sole_error_max_mm: Largest sole position tracking error, in [mm].
        torso_error_max_deg: Largest torso orientation error, in [deg].
        qp_ticks: Ticks that solved a QP (pink: all).
        failures: Ticks whose solve failed (configuration kept or fallback used).
    """

    robot: str
    label: str
    implementation: str
    solver: str
    nb_ticks: int
    median_us: float
    p99_us: float
    ratio_to_pink: float
    com_error_max_mm: float
    sole_error_max_mm: float
    torso_error_max_deg: float
    qp_ticks: int
    failures: int


def walking_motion(
    robot: Robot, *, duration: float = 2.0, control_period: float = 0.01, sway_period: float = 1.0
) -> list[IKTargets]:
    """Targets of one tick each: CoM swaying sideways (60 % of the way to the left foot), the
    right foot lifting (up to 15 % of the CoM height) while the CoM is on the left, torso yaw
    oscillating by 0.1 rad. ``targets[k]`` is the reference at time ``(k + 1) dt``."""
    start = IKTargets.from_configuration(robot, robot.q0)
    amplitude = 0.6 * (start.left_sole.translation[1] - start.com[1])
    lift = 0.15 * robot.com_height
    targets = []
    for k in range(1, int(round(duration / control_period)) + 1):
        phase = 2.0 * np.pi * k * control_period / sway_period
        com = start.com + np.array([0.0, amplitude * np.sin(phase), 0.0])
        right = start.right_sole.copy()
        right.translation = right.translation + np.array(
            [0.0, 0.0, lift * max(np.sin(phase), 0.0) ** 2]
        )
        yaw = 0.1 * np.sin(phase)
        torso = pin.rpy.rpyToMatrix(0.0, 0.0, yaw) @ start.torso_rotation
        targets.append(IKTargets(com, start.left_sole, right, torso))
    return targets


def _tracking(robot: Robot, q: np.ndarray, targets: IKTargets) -> np.ndarray:
    """CoM error [m], largest sole position error [m], torso orientation error [rad]."""
    left, right = robot.compute_sole_placements(q)
    torso = robot.compute_frame_placement(q, robot.torso_frame).rotation
    return np.array(
        [
            np.linalg.norm(robot.compute_com(q) - targets.com),
            max(
                np.linalg.norm(left.translation - targets.left_sole.translation),
                np.linalg.norm(right.translation - targets.right_sole.translation),
            ),
            np.linalg.norm(pin.log3(torso @ targets.torso_rotation.T)),
        ]
    )


def _run_ours(robot, motion, dt, **options):
    ik = WholeBodyIK(robot, **options)
    q, ticks, errors, qp_ticks, failures = robot.q0.copy(), [], [], 0, 0
    for targets in motion:
        start = time.perf_counter()
        result = ik.solve(q, targets, dt)
        ticks.append(time.perf_counter() - start)
        q = result.q_next
        qp_ticks += result.qp_solves
        failures += int(not result.success)
        errors.append(_tracking(robot, q, targets))
    return ticks, errors, qp_ticks, failures, ik


def _run_pink(robot, motion, dt, solver, reference_ik: WholeBodyIK):
    import pink
    from pink.limits import ConfigurationLimit, VelocityLimit
    from pink.tasks import ComTask, FrameTask, PostureTask

    model = pin.Model(robot.model)  # the free-flyer gets no position limit, as in ours
    root_nq = model.joints[1].nq
    model.lowerPositionLimit[:root_nq] = -np.inf
    model.upperPositionLimit[:root_nq] = np.inf
    weights, lm = reference_ik.weights, reference_ik.lm_damping
    left, right = robot.foot_frames
    com = ComTask(cost=weights.com, lm_damping=lm)
    feet = [
        FrameTask(frame, weights.sole_position, weights.sole_orientation, lm_damping=lm)
        for frame in (left, right)
    ]
    torso = FrameTask(reference_ik.torso_task.frame, 0.0, weights.torso_orientation, lm_damping=lm)
    posture = PostureTask(cost=weights.posture)
    posture.set_target(robot.q0)
    velocity_limit = np.full(model.nv, np.inf)
    velocity_limit[reference_ik.posture_task.root_nv :] = reference_ik.velocity_limit
    limits = [
        ConfigurationLimit(model, reference_ik.limit_gain),
        VelocityLimit(model, velocity_limit),
    ]
    tasks = [com, *feet, torso, posture]
    configuration = pink.Configuration(model, model.createData(), robot.q0)
    q, ticks, errors, failures = robot.q0.copy(), [], [], 0
    logging.disable(logging.WARNING)  # pink logs each joint it finds 1e-6 past a limit
    try:
        for targets in motion:
            start = time.perf_counter()
            configuration.update(q)
            com.set_target(targets.com)
            feet[0].set_target(targets.left_sole)
            feet[1].set_target(targets.right_sole)
            torso.set_target(pin.SE3(targets.torso_rotation, np.zeros(3)))
            try:
                v = pink.solve_ik(
                    configuration,
                    tasks,
                    dt,
                    solver=solver,
                    damping=reference_ik.damping,
                    limits=limits,
                    safety_break=False,
                )
                q = configuration.integrate(v, dt)
            except Exception:
                failures += 1
            ticks.append(time.perf_counter() - start)
            errors.append(_tracking(robot, q, targets))
    finally:
        logging.disable(logging.NOTSET)
    return ticks, errors, len(motion), failures


def run_ik_benchmark(
    robot_names: Sequence[str] = DEFAULT_ROBOTS,
    *,
    duration: float = 2.0,
    control_period: float = 0.01,
    pink_solvers: Sequence[str] | None = DEFAULT_PINK_SOLVERS,
    weights: IKWeights = IKWeights(),
    progress: bool = True,
) -> list[IKBenchCase]:
    """Time our IK and pink on every robot, same tasks, same motion, same run.

    Args:
        robot_names: Robots to load.
        duration: Length of the motion, in [s].
        control_period: IK tick, in [s].
        pink_solvers: qpsolvers back-ends for pink (None or empty: no pink; skipped when
            pink is not installed).
        weights: Task weights for both IKs.
        progress: Show a progress bar.

    Returns:
        One :class:`IKBenchCase` per robot and IK.
    """
    from qpsolvers import available_solvers
    from tqdm import tqdm

    try:
        import pink  # noqa: F401
    except ImportError:
        pink_solvers = ()
    results: list[IKBenchCase] = []
    for name in tqdm(list(robot_names), desc="robots", disable=not progress):
        robot = load_robot(name, visual=False)
        motion = walking_motion(robot, duration=duration, control_period=control_period)
        rows = []
        ticks, errors, qp_ticks, failures, ours = _run_ours(
            robot, motion, control_period, weights=weights
        )
        rows.append(
            (
                "ours (QP when a bound is active)",
                "mpcwalk",
                "daqp",
                ticks,
                errors,
                qp_ticks,
                failures,
            )
        )
        ticks, errors, qp_ticks, failures, _ = _run_ours(
            robot, motion, control_period, weights=weights, qp_only_when_needed=False
        )
        rows.append(("ours (QP every tick)", "mpcwalk", "daqp", ticks, errors, qp_ticks, failures))
        for solver in pink_solvers or ():
            if solver in available_solvers:
                ticks, errors, qp_ticks, failures = _run_pink(
                    robot, motion, control_period, solver, ours
                )
                rows.append((f"pink ({solver})", "pink", solver, ticks, errors, qp_ticks, failures))
        medians = {row[0]: float(np.median(row[3][1:])) * 1e6 for row in rows}
        reference = medians.get("pink (daqp)", float("nan"))
        for label, implementation, solver, ticks, errors, qp_ticks, failures in rows:
            timed = np.array(ticks[1:]) * 1e6
            worst = np.max(errors, axis=0)
            results.append(
                IKBenchCase(
                    robot=name,
                    label=label,
                    implementation=implementation,
                    solver=solver,
                    nb_ticks=len(timed),
                    median_us=medians[label],
                    p99_us=float(np.percentile(timed, 99)),
                    ratio_to_pink=medians[label] / reference,
                    com_error_max_mm=1e3 * worst[0],
                    sole_error_max_mm=1e3 * worst[1],
                    torso_error_max_deg=float(np.degrees(worst[2])),
                    qp_ticks=int(qp_ticks),
                    failures=int(failures),
                )
            )
    return results


def format_ik_table(results: list[IKBenchCase]) -> str:
    """Markdown table of the results."""
    lines = [
        "| robot | IK | median [us] | p99 [us] | median / pink (daqp) | CoM err max [mm] | "
        "sole err max [mm] | torso err max [deg] | QP ticks | failures |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in results:
        lines.append(
            f"| {r.robot} | {r.label} | {r.median_us:.1f} | {r.p99_us:.1f} | "
            f"{r.ratio_to_pink:.2f} | {r.com_error_max_mm:.3f} | {r.sole_error_max_mm:.3f} | "
            f"{r.torso_error_max_deg:.3f} | {r.qp_ticks}/{r.nb_ticks + 1} | {r.failures} |"
        )
    return "\n".join(lines)


def ik_report(
    results: list[IKBenchCase], *, duration: float, control_period: float, command_line: str
) -> str:
    """``ik.md``: what was timed, on which machine, the command line that reproduces it, and
    the table of the results (:func:`format_ik_table`)."""
    from mpcwalk.bench.output import machine_description

    header = (
        f"Whole-body IK tick, ours beside pink: same tasks (CoM, soles, torso orientation, "
        f"posture), weights, damping and limits; CoM sway and foot lift for {duration} s "
        f"at {1.0 / control_period:g} Hz. Machine: {machine_description()}.\n"
        f"Command: `{command_line}`\n"
    )
    return header + "\n" + format_ik_table(results) + "\n"
