"""Whole-body IK: task Jacobians, convergence, limits, damping, tracking, bad inputs."""

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError, FrameNotFound, SolverNotFound
from mpcwalk.ik import (
    ComTask,
    FrameTask,
    IKTargets,
    PostureTask,
    WholeBodyIK,
    update_kinematics,
)

ROBOTS = ("bioloid-like", "atlas-like", "g1")


def perturbed(robot, rng, scale=0.2):
    """q0 with random joint offsets (within the limits) and a displaced, tilted base."""
    q = robot.q0.copy()
    lower = robot.model.lowerPositionLimit[7:]
    upper = robot.model.upperPositionLimit[7:]
    q[7:] = np.clip(q[7:] + rng.uniform(-scale, scale, len(q) - 7), lower, upper)
    q[0:3] += rng.uniform(-0.05, 0.05, 3) * robot.com_height
    rotation = pin.exp3(rng.uniform(-0.1, 0.1, 3))
    q[3:7] = pin.Quaternion(rotation @ pin.Quaternion(q[3:7]).matrix()).coeffs()
    return q


def numerical_jacobian(task, model, data, q, step):
    """Central differences of the task error along each tangent direction."""
    columns = []
    for i in range(model.nv):
        direction = np.zeros(model.nv)
        direction[i] = step
        values = []
        for sign in (1.0, -1.0):
            q_moved = pin.integrate(model, q, sign * direction)
            update_kinematics(model, data, q_moved)
            values.append(task.compute_error(model, data, q_moved))
        columns.append((values[0] - values[1]) / (2.0 * step))
    update_kinematics(model, data, q)
    return np.array(columns).T


def make_tasks(robot, rng):
    model = robot.model
    com = ComTask(3.0)
    com.set_target(rng.normal(size=3))
    sole = FrameTask(model, robot.foot_frames[0], position_weight=1.0, orientation_weight=2.0)
    sole.set_target(pin.SE3(pin.exp3(rng.uniform(-1.0, 1.0, 3)), rng.normal(size=3)))
    torso = FrameTask(model, robot.torso_frame, position_weight=None, orientation_weight=1.0)
    torso.set_target(pin.SE3(pin.exp3(rng.uniform(-1.0, 1.0, 3)), np.zeros(3)))
    posture = PostureTask(model, 0.1, robot.q0)
    return com, sole, torso, posture


@pytest.mark.parametrize("name", ROBOTS)
def test_task_jacobians_match_central_differences(name):
    robot = get_robot(name)
    model, data = robot.model, robot.model.createData()
    rng = np.random.default_rng(3)
    step = 1e-6
    for _ in range(2):
        q = perturbed(robot, rng, 0.5)
        update_kinematics(model, data, q)
        for task in make_tasks(robot, rng):
            jacobian = task.compute_jacobian(model, data, q)
            assert jacobian.shape == (task.dimension, model.nv)
            numerical = numerical_jacobian(task, model, data, q, step)
            # central differences: O(step^2) truncation, O(eps / step) rounding
            scale = max(1.0, np.abs(jacobian).max())
            tolerance = 20 * (step**2 + np.finfo(float).eps / step) * scale
            assert np.abs(numerical - jacobian).max() < tolerance, task.name
            error, linearized, _ = task.compute_linearization(model, data, q, False)
            assert np.allclose(error, task.compute_error(model, data, q), atol=0.0)
            assert np.allclose(linearized, jacobian, atol=0.0)


def test_feedforward_matches_moving_target():
    robot = get_robot("bioloid-like")
    model, data = robot.model, robot.model.createData()
    rng = np.random.default_rng(5)
    q = perturbed(robot, rng)
    update_kinematics(model, data, q)
    step = 1e-6
    velocity = np.concatenate([rng.normal(size=3), rng.normal(size=3)])
    target = pin.SE3(pin.exp3(rng.uniform(-0.5, 0.5, 3)), rng.normal(size=3))
    task = FrameTask(model, robot.foot_frames[1], position_weight=1.0, orientation_weight=1.0)
    task.set_target(target, velocity)
    feedforward = task.compute_feedforward(model, data, q)
    errors = []
    for sign in (1.0, -1.0):
        moved = pin.SE3(
            pin.exp3(sign * step * velocity[3:]) @ target.rotation,
            target.translation + sign * step * velocity[:3],
        )
        task.set_target(moved)
        errors.append(task.compute_error(model, data, q))
    # the error shrinks at the feed-forward rate when the target moves
    assert np.abs(-(errors[0] - errors[1]) / (2 * step) - feedforward).max() < 1e-7


@pytest.mark.parametrize("name", ROBOTS)
def test_solve_pose_reaches_reachable_targets(name):
    robot = get_robot(name)
    ik = WholeBodyIK(robot)
    rng = np.random.default_rng(11)
    goal = perturbed(robot, rng)
    targets = IKTargets.from_configuration(robot, goal)
    result = ik.solve_pose(robot.q0, targets)
    assert result.success and result.status == "converged"
    errors = result.task_errors
    assert errors.com < 1e-6
    assert errors.left_sole_position < 1e-6 and errors.right_sole_position < 1e-6
    assert errors.orientation_max < 1e-6
    # the reported errors are those of q_next (independent forward kinematics)
    left, _ = robot.compute_sole_placements(result.q_next)
    assert np.linalg.norm(left.translation - targets.left_sole.translation) < 1e-6
    assert np.linalg.norm(robot.compute_com(result.q_next) - targets.com) < 1e-6
    joints = result.q_next[7:]
    assert np.all(joints >= robot.model.lowerPositionLimit[7:] - 1e-12)
    assert np.all(joints <= robot.model.upperPositionLimit[7:] + 1e-12)


def _knee_indices(robot):
    return [robot.model.idx_qs[robot.model.getJointId(n)] for n in ("left_knee", "right_knee")]


def test_target_beyond_reach_saturates_at_the_knee_limit():
    robot = get_robot("bioloid-like")
    ik = WholeBodyIK(robot)
    start = IKTargets.from_configuration(robot, robot.q0)
    # CoM 3 cm above what straight legs reach (0.238 m standing straight)
    high = IKTargets(
        start.com + [0.0, 0.0, 0.04], start.left_sole, start.right_sole, start.torso_rotation
    )
    lower, upper = robot.model.lowerPositionLimit[7:], robot.model.upperPositionLimit[7:]
    result = ik.solve_pose(robot.q0, high, max_iterations=100)
    assert not result.success and result.task_errors.com > 1e-3
    knees = _knee_indices(robot)
    # at the limit (approached geometrically: the Levenberg-Marquardt damping shortens steps)...
    assert np.allclose(result.q_next[knees], 0.0, atol=1e-6)
    assert np.all(result.q_next[7:] >= lower) and np.all(result.q_next[7:] <= upper)  # ...not past
    q = robot.q0.copy()
    for _ in range(150):  # loop mode: approaches the limit, never crosses it
        step = ik.solve(q, high, 0.01)
        assert step.success
        q = step.q_next
        assert np.all(q[7:] >= lower) and np.all(q[7:] <= upper)
        assert np.all(np.abs(step.v[6:]) <= ik.velocity_limit + 1e-9)
    assert np.all(q[knees] < 0.02)  # from 0.76 rad


def test_stretched_knee_target_keeps_steps_bounded():
    robot = get_robot("bioloid-like")
    q = robot.q0.copy()
    for side in ("left", "right"):
        for joint, angle in (("hip_pitch", -0.01), ("knee", 0.02), ("foot_pitch", -0.01)):
            q[robot.model.idx_qs[robot.model.getJointId(f"{side}_{joint}")]] = angle
    start = IKTargets.from_configuration(robot, q)
    beyond = IKTargets(
        start.com + [0.0, 0.0, 0.02], start.left_sole, start.right_sole, start.torso_rotation
    )

    def largest_step(**options):
        ik = WholeBodyIK(robot, velocity_limit=np.inf, damping=1e-12, **options)
        configuration, largest = q.copy(), 0.0
        for _ in range(60):
            result = ik.solve(configuration, beyond, 0.01)
            assert np.all(np.isfinite(result.q_next))
            configuration = result.q_next
            largest = max(largest, np.linalg.norm(result.v) * 0.01)
        return largest

    lm_damping = 1.0
    bound = 1.0 / (2.0 * np.sqrt(lm_damping))  # Levenberg-Marquardt bound on ||dq||
    assert largest_step(lm_damping=lm_damping) < bound
    assert largest_step(lm_damping=0.0) > 2.0 * bound  # undamped: the step blows up


def _sway(robot, t):
    """CoM swaying sideways and right foot lifting: position and velocity at time t."""
    start = IKTargets.from_configuration(robot, robot.q0)
    amplitude, lift, omega = 0.5 * start.left_sole.translation[1], 0.1 * robot.com_height, 2 * np.pi
    com = start.com + [0.0, amplitude * np.sin(omega * t), 0.0]
    com_velocity = np.array([0.0, amplitude * omega * np.cos(omega * t), 0.0])
    right = start.right_sole.copy()
    right.translation = right.translation + [0.0, 0.0, lift * (1 - np.cos(omega * t))]
    right_velocity = np.array([0.0, 0.0, lift * omega * np.sin(omega * t), 0.0, 0.0, 0.0])
    return start, com, com_velocity, right, right_velocity


@pytest.mark.parametrize("name", ("bioloid-like", "g1"))
def test_loop_tracks_a_moving_target_with_bounded_lag(name):
    robot = get_robot(name)
    ik, dt = WholeBodyIK(robot), 0.01
    lags = {}
    for mode in ("next", "feedforward", "current"):
        q, worst = robot.q0.copy(), 0.0
        for k in range(100):
            t = k * dt
            if mode == "next":  # references of the next tick
                start, com, _, right, _ = _sway(robot, t + dt)
                targets = IKTargets(com, start.left_sole, right, start.torso_rotation)
            else:  # references of now, with (or without) their velocities
                start, com, com_v, right, right_v = _sway(robot, t)
                with_velocity = mode == "feedforward"
                targets = IKTargets(
                    com,
                    start.left_sole,
                    right,
                    start.torso_rotation,
                    com_velocity=com_v if with_velocity else None,
                    right_sole_velocity=right_v if with_velocity else None,
                )
            result = ik.solve(q, targets, dt)
            assert result.success
            q = result.q_next
            start, com, _, right, _ = _sway(robot, t + dt)
            reached = IKTargets(com, start.left_sole, right, start.torso_rotation)
            worst = max(worst, ik.errors(q, reached).position_max)
        lags[mode] = worst
    assert lags["next"] < 1e-3 * robot.com_height
    assert lags["feedforward"] < 1e-3 * robot.com_height
    assert lags["current"] > 5.0 * lags["feedforward"]  # one tick of lag without feed-forward


def test_unconstrained_and_qp_paths_agree_and_solvers_agree():
    robot = get_robot("bioloid-like")
    q = robot.q0.copy()
    for elbow in ("left_elbow", "right_elbow"):  # away from their limit: no active bound
        q[robot.model.idx_qs[robot.model.getJointId(elbow)]] = -0.5
    start = IKTargets.from_configuration(robot, q)
    moved = IKTargets(
        start.com + [0.001, 0.001, -0.001],
        start.left_sole,
        start.right_sole,
        pin.exp3(np.array([0.0, 0.0, 0.01])),
    )
    auto = WholeBodyIK(robot, posture_reference=q).solve(q, moved, 0.01)
    assert auto.status == "unconstrained"
    for solver in ("daqp", "quadprog"):
        forced = WholeBodyIK(
            robot, solver=solver, qp_only_when_needed=False, posture_reference=q
        ).solve(q, moved, 0.01)
        assert forced.status == "qp"
        assert np.abs(forced.v - auto.v).max() < 1e-6
    # an active bound: both QP back-ends give the same clipped step
    fast = IKTargets(
        start.com + [0.0, 0.0, -0.03], start.left_sole, start.right_sole, start.torso_rotation
    )
    steps = [WholeBodyIK(robot, solver=s).solve(robot.q0, fast, 0.01) for s in ("daqp", "quadprog")]
    assert steps[0].status == "qp" and steps[0].qp_solves == 1
    assert np.abs(np.abs(steps[0].v[6:]).max() - 6.0) < 1e-9  # at the velocity limit
    assert np.abs(steps[0].v - steps[1].v).max() < 1e-5


def test_failed_qp_falls_back_without_raising(monkeypatch):
    robot = get_robot("bioloid-like")
    ik = WholeBodyIK(robot)
    start = IKTargets.from_configuration(robot, robot.q0)
    fast = IKTargets(
        start.com + [0.0, 0.0, -0.03], start.left_sole, start.right_sole, start.torso_rotation
    )
    monkeypatch.setattr(ik, "_solve_qp", lambda *args: None)
    result = ik.solve(robot.q0, fast, 0.01)
    assert not result.success and result.status == "fallback"
    assert np.all(np.abs(result.v[6:]) <= ik.velocity_limit + 1e-12)
    monkeypatch.setattr(
        "mpcwalk.ik.whole_body_ik.lapack.dposv", lambda H, g: (H, np.full(len(g), np.nan), 0)
    )
    kept = ik.solve(robot.q0, fast, 0.01)
    assert kept.status == "kept" and np.array_equal(kept.q_next, robot.q0)
    assert np.all(kept.v == 0.0)


def test_bad_inputs_raise_named_errors():
    robot = get_robot("bioloid-like")
    with pytest.raises(FrameNotFound, match="'no_such_frame' not found.*left_sole"):
        WholeBodyIK(robot, torso_frame="no_such_frame")
    with pytest.raises(FrameNotFound):
        FrameTask(robot.model, "no_such_frame")
    with pytest.raises(SolverNotFound, match="no_such_solver"):
        WholeBodyIK(robot, solver="no_such_solver")
    with pytest.raises(ConfigurationError, match="velocity_limit"):
        WholeBodyIK(robot, velocity_limit=-1.0)
    with pytest.raises(ConfigurationError, match="limit_gain"):
        WholeBodyIK(robot, limit_gain=0.0)
    start = IKTargets.from_configuration(robot, robot.q0)
    with pytest.raises(ConfigurationError, match="com must be an array of 3"):
        IKTargets(np.zeros(2), start.left_sole, start.right_sole, np.eye(3))
    with pytest.raises(ConfigurationError, match="4x4"):
        IKTargets(np.zeros(3), np.eye(3), start.right_sole, np.eye(3))
    with pytest.raises(ConfigurationError, match="not a rotation"):
        IKTargets(np.zeros(3), start.left_sole, start.right_sole, 2.0 * np.eye(3))
    with pytest.raises(ConfigurationError, match="left_sole_velocity"):
        IKTargets(
            np.zeros(3),
            start.left_sole,
            start.right_sole,
            np.eye(3),
            left_sole_velocity=np.zeros(3),
        )
    ik = WholeBodyIK(robot)
    with pytest.raises(ConfigurationError, match="q must be 25 finite numbers"):
        ik.solve(robot.q0[:-1], start, 0.01)
    with pytest.raises(ConfigurationError, match="dt must be a positive"):
        ik.solve(robot.q0, start, 0.0)
    with pytest.raises(ConfigurationError, match="IKTargets"):
        ik.solve(robot.q0, {"com": np.zeros(3)}, 0.01)
    # 4x4 arrays are accepted for the soles
    as_matrix = IKTargets(
        start.com, start.left_sole.homogeneous, start.right_sole.homogeneous, start.torso_rotation
    )
    assert np.allclose(as_matrix.left_sole.homogeneous, start.left_sole.homogeneous)


def test_from_gait_builds_flat_feet_and_yaw():
    from mpcwalk.footsteps.footstep import FootGeometry, Footstep, FootstepPlan, Side, StepTiming
    from mpcwalk.gait.contact_schedule import ContactSchedule
    from mpcwalk.gait.swing_foot import SwingFootTrajectory

    plan = FootstepPlan(
        Footstep(Side.LEFT, np.array([0.0, 0.04, 0.0]), 0.0),
        Footstep(Side.RIGHT, np.array([0.0, -0.04, 0.0]), 0.0),
        [Footstep(Side.RIGHT, np.array([0.05, -0.04, 0.0]), 0.2)],
        StepTiming(),
    )
    trajectory = SwingFootTrajectory(ContactSchedule(plan, FootGeometry()))
    t = 1.25  # middle of the first step's single support
    feet = trajectory.foot_poses(t)
    assert not feet.right.in_contact and feet.right.position[2] > 0.03  # swinging
    targets = IKTargets.from_gait(
        np.array([0.0, 0.0, 0.23]),
        feet,
        trajectory.torso_yaw(t),
        torso_yaw_rate=trajectory.torso_yaw_rate(t),
    )
    assert np.allclose(targets.right_sole.translation, feet.right.position)
    assert np.allclose(targets.right_sole.rotation, pin.exp3(np.array([0.0, 0.0, feet.right.yaw])))
    assert np.allclose(targets.right_sole_velocity[:3], feet.right.linear_velocity)
    assert np.isclose(targets.right_sole_velocity[5], feet.right.yaw_rate)
    yaw = trajectory.torso_yaw(t)
    assert np.allclose(targets.torso_rotation, pin.exp3(np.array([0.0, 0.0, yaw])))
    assert targets.has_velocities


def test_benchmark_runs_ours_and_pink_on_the_same_problem():
    from mpcwalk.bench.ik import format_ik_table, run_ik_benchmark
    from mpcwalk.cli import build_parser

    pytest.importorskip("pink")
    results = run_ik_benchmark(
        ["bioloid-like"], duration=0.3, pink_solvers=("daqp",), progress=False
    )
    labels = [r.label for r in results]
    assert labels == ["ours (QP when a bound is active)", "ours (QP every tick)", "pink (daqp)"]
    ours, _, pink = results
    assert ours.nb_ticks == 29 and ours.failures == 0 and pink.failures == 0
    assert pink.ratio_to_pink == 1.0
    # same tasks, weights and limits: the same motion to a small fraction of the errors
    assert abs(ours.com_error_max_mm - pink.com_error_max_mm) < 0.05 * pink.com_error_max_mm
    assert abs(ours.sole_error_max_mm - pink.sole_error_max_mm) < 0.05 * pink.sole_error_max_mm
    assert "| bioloid-like | pink (daqp) |" in format_ik_table(results)
    args = build_parser().parse_args(["bench", "ik", "--robots", "g1", "--no-pink"])
    assert args.robots == "g1" and args.no_pink and callable(args.run)
