"""Swing-foot and torso-yaw trajectories (paper M eq. 19-23)."""

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming, wrap_angle
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.swing_foot import FeetState, SwingFootTrajectory

Z_STEP = 0.04  # [m] paper M, Table 1
TIMING = StepTiming(
    step_duration=0.5, double_support_ratio=0.2, initial_duration=0.5, final_duration=0.5
)
T, T_B, T_E = 0.5, 0.05, 0.45  # [s]
WALK_START = 0.5  # [s]


def make_plan(left_yaw=0.0, right_yaw=0.0, step_yaws=(0.2, 0.4, 0.6)):
    steps = (
        Footstep(Side.RIGHT, (0.10, -0.05, 0.00), step_yaws[0]),
        Footstep(Side.LEFT, (0.20, 0.05, 0.00), step_yaws[1]),
        Footstep(Side.RIGHT, (0.30, -0.05, 0.02), step_yaws[2]),  # onto a 2 cm platform
    )
    return FootstepPlan(
        Footstep(Side.LEFT, (0.0, 0.05, 0.0), left_yaw),
        Footstep(Side.RIGHT, (0.0, -0.05, 0.0), right_yaw),
        steps,
        TIMING,
    )


@pytest.fixture(scope="module")
def trajectory():
    return SwingFootTrajectory(ContactSchedule(make_plan()), step_height=Z_STEP)


def step_start(k):
    return WALK_START + k * T


def test_standing_before_and_after_the_walk(trajectory):
    plan = trajectory.schedule.plan
    for t, stance in ((0.1, plan.stance(0)), (trajectory.schedule.duration - 0.1, plan.stance(3))):
        state = trajectory.foot_poses(t)
        assert isinstance(state, FeetState)
        assert state.contact_sides == (Side.LEFT, Side.RIGHT) and state.swing_side is None
        for side in Side:
            np.testing.assert_array_equal(state[side].position, stance[side].position)
            assert state[side].yaw == stance[side].yaw
            np.testing.assert_array_equal(state[side].linear_velocity, np.zeros(3))
            assert state[side].yaw_rate == 0.0


@pytest.mark.parametrize("k", [0, 1, 2])
def test_swing_foot_goes_from_lift_to_landing_pose_at_rest(trajectory, k):
    plan = trajectory.schedule.plan
    landing = plan.steps[k]
    lift = plan.stance(k)[landing.side]
    t0 = step_start(k)
    # Opening double support and lift-off: at the lift pose, at rest.
    for t in (t0, t0 + 0.5 * T_B, t0 + T_B):
        foot = trajectory.foot_poses(t)[landing.side]
        np.testing.assert_allclose(foot.position, lift.position, rtol=0.0, atol=1e-15)
        assert foot.yaw == pytest.approx(lift.yaw, abs=1e-15)
        np.testing.assert_allclose(foot.linear_velocity, 0.0, atol=1e-14)
        assert foot.yaw_rate == pytest.approx(0.0, abs=1e-14)
    # Touch-down and closing double support: exactly at the landing pose, at rest.
    for t in (t0 + T_E, t0 + 0.5 * (T_E + T)):
        state = trajectory.foot_poses(t)
        foot = state[landing.side]
        assert foot.in_contact and state.swing_side is None
        np.testing.assert_array_equal(foot.position, landing.position)
        assert foot.yaw == landing.yaw
        np.testing.assert_array_equal(foot.linear_velocity, np.zeros(3))
    # Just before touch-down: within O(dt^2) of the landing pose, velocity O(dt).
    dt = 1e-4  # [s]
    foot = trajectory.foot_poses(t0 + T_E - dt)[landing.side]
    rate = np.pi / (T_E - T_B)  # [1/s] angular frequency of the cosines
    scale = np.linalg.norm(landing.position - lift.position) + 4.0 * Z_STEP
    assert not foot.in_contact
    assert np.linalg.norm(foot.position - landing.position) <= 0.5 * rate**2 * dt**2 * scale
    assert np.linalg.norm(foot.linear_velocity) <= rate**2 * dt * scale


@pytest.mark.parametrize("k", [0, 1, 2])
def test_peak_height_at_mid_single_support_and_fixed_stance(trajectory, k):
    plan = trajectory.schedule.plan
    landing = plan.steps[k]
    lift = plan.stance(k)[landing.side]
    support = plan.support_foot(k)
    t0 = step_start(k)
    ground_mid = 0.5 * (lift.position[2] + landing.position[2])
    mid = trajectory.foot_poses(t0 + 0.5 * (T_B + T_E))
    assert mid.swing_side is landing.side and mid.contact_sides == (landing.side.other,)
    assert mid[landing.side].position[2] == pytest.approx(ground_mid + Z_STEP, abs=1e-15)
    np.testing.assert_allclose(
        mid[landing.side].position[:2], 0.5 * (lift.xy + landing.xy), atol=1e-15
    )
    assert mid[landing.side].linear_velocity[2] == pytest.approx(
        np.pi / (T_E - T_B) * (landing.position[2] - lift.position[2]) * 0.5, abs=1e-14
    )
    heights, clearance = [], []
    for t in np.linspace(t0, t0 + T, 201):
        state = trajectory.foot_poses(t)
        stance_foot = state[support.side]
        assert stance_foot.in_contact
        np.testing.assert_array_equal(stance_foot.position, support.position)
        assert stance_foot.yaw == support.yaw
        np.testing.assert_array_equal(stance_foot.linear_velocity, np.zeros(3))
        z = state[landing.side].position[2]
        heights.append(z)
        clearance.append(z - min(lift.position[2], landing.position[2]))
    assert max(heights) <= max(lift.position[2], landing.position[2]) + Z_STEP + 1e-15
    assert min(clearance) >= 0.0


def test_velocities_match_finite_differences(trajectory):
    eps = 1e-5  # [s]
    width = T_E - T_B
    delta_max = 0.12  # [m] and [rad]: largest horizontal move, height change and yaw change
    third = 0.5 * (np.pi / width) ** 3 * delta_max + 0.5 * (2 * np.pi / width) ** 3 * Z_STEP
    tolerance = third * eps**2 / 6.0 + 8.0 * np.finfo(float).eps / eps
    times = []
    for k in range(3):
        t0 = step_start(k)
        times += list(np.linspace(t0 + T_B + 2 * eps, t0 + T_E - 2 * eps, 23))
        times += [t0 + 0.5 * T_B, t0 + 0.5 * (T_E + T)]
    for t in times:
        before, now, after = (trajectory.foot_poses(t + d) for d in (-eps, 0.0, eps))
        for side in Side:
            fd = (after[side].position - before[side].position) / (2 * eps)
            np.testing.assert_allclose(now[side].linear_velocity, fd, rtol=0.0, atol=tolerance)
            fd_yaw = (after[side].yaw - before[side].yaw) / (2 * eps)
            assert now[side].yaw_rate == pytest.approx(fd_yaw, abs=tolerance)
        fd_torso = (trajectory.torso_yaw(t + eps) - trajectory.torso_yaw(t - eps)) / (2 * eps)
        assert trajectory.torso_yaw_rate(t) == pytest.approx(fd_torso, abs=tolerance)


def test_torso_yaw_waypoints_and_double_support(trajectory):
    # Mean of the feet yaws at each step boundary.
    np.testing.assert_allclose(trajectory.torso_yaws, [0.0, 0.1, 0.3, 0.5], atol=1e-15)
    assert trajectory.torso_yaw(0.2) == 0.0
    for k in range(3):
        t0 = step_start(k)
        psi0, psi1 = trajectory.torso_yaws[k], trajectory.torso_yaws[k + 1]
        for t in np.linspace(t0, t0 + T_B, 5):  # no yaw in double support
            assert trajectory.torso_yaw(t) == pytest.approx(psi0, abs=1e-15)
            assert trajectory.torso_yaw_rate(t) == pytest.approx(0.0, abs=1e-14)
        for t in np.linspace(t0 + T_E, t0 + T - 1e-9, 5):
            assert trajectory.torso_yaw(t) == pytest.approx(psi1, abs=1e-15)
            assert trajectory.torso_yaw_rate(t) == 0.0
        assert trajectory.torso_yaw(t0 + 0.5 * (T_B + T_E)) == pytest.approx(
            0.5 * (psi0 + psi1), abs=1e-15
        )
    times = np.linspace(0.0, trajectory.schedule.duration, 7).reshape(7, 1)
    assert trajectory.torso_yaw(times).shape == (7, 1)
    assert trajectory.torso_yaw(trajectory.schedule.duration + 1.0) == pytest.approx(0.5)


def test_yaws_take_the_short_way_across_pi():
    # Feet at +-3.1 rad face backwards: their mean is pi, not 0.
    plan = make_plan(left_yaw=3.1, right_yaw=-3.1, step_yaws=(3.1, -3.1, -3.0))
    trajectory = SwingFootTrajectory(ContactSchedule(plan))
    wrap_gap = 6.2 - 2.0 * np.pi  # [rad] short way from -3.1 to 3.1 (about -0.083)
    assert float(wrap_angle(trajectory.torso_yaws[0] - np.pi)) == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(
        np.diff(trajectory.torso_yaws), [3.1 - np.pi, np.pi - 3.1, np.pi - 3.05], atol=1e-12
    )  # unwrapped: no 2 pi jumps
    middle = 0.5 * (T_B + T_E)
    # Right foot: lift -3.1, landing 3.1: turns by wrap_gap through -pi.
    right = trajectory.foot_poses(step_start(0) + middle)[Side.RIGHT]
    assert right.yaw == pytest.approx(-3.1 + 0.5 * wrap_gap, abs=1e-12)
    assert right.yaw_rate == pytest.approx(0.5 * np.pi / (T_E - T_B) * wrap_gap, abs=1e-12)
    # Left foot: lift 3.1, landing -3.1: turns by -wrap_gap through +pi.
    left = trajectory.foot_poses(step_start(1) + middle)[Side.LEFT]
    assert left.yaw == pytest.approx(3.1 - 0.5 * wrap_gap, abs=1e-12)
    # Right foot: lift 3.1, landing -3.0: turns by 2 pi - 6.1 (about +0.18).
    right = trajectory.foot_poses(step_start(2) + middle)[Side.RIGHT]
    assert right.yaw == pytest.approx(3.1 + 0.5 * (2.0 * np.pi - 6.1), abs=1e-12)
    yaws = trajectory.torso_yaw(np.linspace(0.0, trajectory.schedule.duration, 400))
    assert np.max(np.abs(np.diff(yaws))) < 0.05


def test_feet_state_accessors(trajectory):
    state = trajectory.foot_poses(step_start(0) + 0.2)
    assert state["left"] is state.left and state[Side.RIGHT] is state.right
    assert state.step_index == 0 and state.swing_side is Side.RIGHT
    transform = state.left.transform
    np.testing.assert_allclose(transform[:3, :3].T @ transform[:3, :3], np.eye(3), atol=1e-15)
    np.testing.assert_array_equal(transform[:3, 3], state.left.position)
    with pytest.raises(ValueError):
        state.left.position[0] = 1.0  # read-only


def test_bad_arguments_raise():
    schedule = ContactSchedule(make_plan())
    with pytest.raises(ConfigurationError, match="non-negative number of metres"):
        SwingFootTrajectory(schedule, step_height=-0.01)
    with pytest.raises(ConfigurationError, match="needs a ContactSchedule"):
        SwingFootTrajectory(make_plan())
    with pytest.raises(ConfigurationError, match="finite number of seconds"):
        SwingFootTrajectory(schedule).foot_poses(float("nan"))


def test_ctraj_profile_lifts_then_lowers_with_quintic_timing():
    """Paper A's profile: lift-off pose -> apex above the middle of the step -> landing
    pose, zero velocity at all three, velocities equal to finite differences."""
    from mpcwalk.footsteps.footstep import FootstepPlan as Plan

    left, right = Footstep(Side.LEFT, [0.0, 0.1]), Footstep(Side.RIGHT, [0.0, -0.1])
    plan = Plan(
        left,
        right,
        [Footstep(Side.RIGHT, [0.3, -0.1], 0.2)],
        StepTiming(step_duration=2.0, double_support_ratio=0.5),
    )
    schedule = ContactSchedule(plan)
    traj = SwingFootTrajectory(schedule, step_height=0.1, profile="ctraj")
    t_b, t_e = schedule.walk_start + schedule.t_b, schedule.walk_start + schedule.t_e
    eps = 1e-6
    start, apex, end = (traj.foot_poses(t).right for t in (t_b + eps, 0.5 * (t_b + t_e), t_e - eps))
    np.testing.assert_allclose(start.position, [0.0, -0.1, 0.0], atol=1e-9)
    np.testing.assert_allclose(apex.position, [0.15, -0.1, 0.1], atol=1e-12)
    np.testing.assert_allclose(end.position, [0.3, -0.1, 0.0], atol=1e-9)
    assert apex.yaw == pytest.approx(0.1, abs=1e-12)
    for state in (start, apex, end):
        assert np.abs(state.linear_velocity[2]) < 1e-6
    assert (
        np.linalg.norm(start.linear_velocity) < 1e-6 and np.linalg.norm(end.linear_velocity) < 1e-6
    )
    h = 1e-5
    for t in np.linspace(t_b + 0.05, t_e - 0.05, 17):
        fd = (traj.foot_poses(t + h).right.position - traj.foot_poses(t - h).right.position) / (
            2 * h
        )
        np.testing.assert_allclose(traj.foot_poses(t).right.linear_velocity, fd, atol=1e-7)
    with pytest.raises(ConfigurationError, match="Swing profile must be one of cosine, ctraj"):
        SwingFootTrajectory(schedule, profile="spline")
