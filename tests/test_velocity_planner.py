"""Velocity footstep planner (paper M, sec. 3.1, eq. 5)."""

import itertools
import math

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError, InfeasibleCommand
from mpcwalk.footsteps.footstep import Footstep, Side, StepTiming, wrap_angle
from mpcwalk.footsteps.velocity_planner import (
    LegLimits,
    VelocityCommand,
    VelocityPlanner,
    integrate_torso,
    plan_from_velocity,
)

LIMITS = LegLimits()
T = StepTiming().step_duration


def support_frame_offsets(plan):
    """(x, outward y, outward yaw) of every landing in its support-foot frame."""
    out = []
    for k, step in enumerate(plan.steps):
        support = plan.support_foot(k)
        x, y = support.to_local(step.xy)
        yaw = float(wrap_angle(step.yaw - support.yaw))
        out.append((x, step.side.sign * y, step.side.sign * yaw))
    return np.array(out)


def assert_side_by_side(plan):
    final = plan.stance(plan.nb_steps)
    left, right = final[Side.LEFT], final[Side.RIGHT]
    assert abs(float(wrap_angle(left.yaw - right.yaw))) < 1e-12
    np.testing.assert_allclose(
        right.to_local(left.xy), [0.0, 2.0 * LIMITS.half_stance_width], atol=1e-12
    )


def test_straight_walk_advances_half_velocity_times_period_per_step():
    plan = plan_from_velocity(0.1, 0.0, 0.0, 20)
    assert plan.nb_steps == 21  # 20 walking steps + the closing one
    sides = [s.side for s in plan.steps]
    assert sides[0] is Side.RIGHT  # straight walk starts with the right foot
    assert all(a is not b for a, b in itertools.pairwise(sides))
    x = np.array([s.xy[0] for s in plan.steps[:20]])
    np.testing.assert_allclose(x, 0.05 * np.arange(1, 21), atol=1e-12)
    assert np.mean(np.diff(np.concatenate([[0.0], x]))) == pytest.approx(0.05, abs=1e-12)
    y = np.array([s.xy[1] for s in plan.steps])
    np.testing.assert_allclose(y, [0.05 * s.sign for s in sides], atol=1e-12)
    offsets = support_frame_offsets(plan)
    assert np.all(offsets[:, 1] >= 2.0 * LIMITS.y_sep - 1e-12)
    assert_side_by_side(plan)
    final = plan.stance(plan.nb_steps)
    np.testing.assert_allclose(
        0.5 * (final[Side.LEFT].xy + final[Side.RIGHT].xy), [1.0, 0.0], atol=1e-12
    )


def test_turning_walk_follows_the_commanded_yaw_rate():
    vx, vyaw, n = 0.1, math.pi / 9, 20  # paper M's turning experiment, 20 deg/s
    plan = plan_from_velocity(vx, 0.0, vyaw, n)
    assert plan.steps[0].side is Side.LEFT  # left turn: the left foot opens the stance
    torso = VelocityPlanner().torso_poses(VelocityCommand(vx, 0.0, vyaw), n)
    np.testing.assert_allclose(torso[:, 2], vyaw * T * np.arange(n + 1), atol=1e-12)
    # paper M: about 70 deg of yaw after 3.5 s of walking (7 steps)
    assert math.degrees(torso[7, 2]) == pytest.approx(70.0, abs=1e-9)
    final = plan.stance(plan.nb_steps)
    for foot in final.values():
        assert float(wrap_angle(foot.yaw - vyaw * T * n)) == pytest.approx(0.0, abs=1e-12)
    # no landing is clamped at this command, so the feet end on the exact arc
    radius, psi = vx / vyaw, vyaw * T * n
    midpoint = 0.5 * (final[Side.LEFT].xy + final[Side.RIGHT].xy)
    np.testing.assert_allclose(
        midpoint, [radius * math.sin(psi), radius * (1.0 - math.cos(psi))], atol=1e-12
    )
    offsets = support_frame_offsets(plan)
    assert np.all(offsets[:, 1] >= 2.0 * LIMITS.y_sep - 1e-12)
    assert np.all(offsets[:, 2] >= -LIMITS.max_step_yaw_inward - 1e-12)
    assert_side_by_side(plan)


@pytest.mark.parametrize("vy", [0.05, -0.05])
def test_sideways_walk_keeps_the_minimum_separation(vy):
    n = 12
    plan = plan_from_velocity(0.0, vy, 0.0, n)
    assert plan.steps[0].side is (Side.LEFT if vy > 0 else Side.RIGHT)
    offsets = support_frame_offsets(plan)
    sep, nominal = 2.0 * LIMITS.y_sep, 2.0 * LIMITS.half_stance_width
    assert np.all(offsets[:, 1] >= sep - 1e-12)
    assert np.all(offsets[:, 1] <= nominal + LIMITS.max_step_lateral + 1e-12)
    np.testing.assert_allclose(offsets[:, 0], 0.0, atol=1e-12)
    # the closing (inward) landings would come to 0.1 - 0.025 = 0.075 m: clamped to 2 y_sep
    np.testing.assert_allclose(offsets[1:n:2, 1], sep, atol=1e-12)
    assert offsets[0, 1] == pytest.approx(nominal + abs(vy) * T, abs=1e-12)
    # then each opening landing makes up the lag: the leading foot moves 2 |vy| T per cycle
    np.testing.assert_allclose(offsets[2:n:2, 1] - sep, 2.0 * abs(vy) * T, atol=1e-12)
    final = plan.stance(plan.nb_steps)
    midpoint_y = 0.5 * (final[Side.LEFT].xy[1] + final[Side.RIGHT].xy[1])
    # the last inward landing lags 2 y_sep - (2 h - |vy| T) = 0.005 m behind the model and
    # the closing step keeps it: a constant lag, never growing with n
    assert abs(midpoint_y - vy * T * n) == pytest.approx(0.005, abs=1e-12)
    assert_side_by_side(plan)


@pytest.mark.parametrize(
    "command", [(0.16, 0.0, 0.5), (0.0, 0.06, 0.0), (0.0, 0.06, 0.2), (0.0, 0.0, 0.55)]
)
def test_clamping_at_the_limits_does_not_accumulate_drift(command):
    """At the command limits some landings are clamped; the lag stays constant."""
    planner, n, h = VelocityPlanner(), 40, LIMITS.half_stance_width
    plan = planner.plan(VelocityCommand(*command), n, stop=False)
    torso = planner.torso_poses(VelocityCommand(*command), n)
    errors = []
    for k, step in enumerate(plan.steps):  # distance of each landing from its model target
        x, y, yaw = torso[k + 1]
        target = np.array([x, y]) + step.side.sign * h * np.array([-math.sin(yaw), math.cos(yaw)])
        errors.append(np.linalg.norm(step.xy - target))
    errors = np.array(errors)
    np.testing.assert_allclose(errors[2:], errors[:-2], atol=1e-9)  # periodic: no growth
    assert errors.max() < 0.012
    lower, upper = planner.rectangle.bounds(Side.LEFT)
    offsets = support_frame_offsets(plan)
    assert np.all(offsets >= lower - 1e-12) and np.all(offsets <= upper + 1e-12)


def test_initial_feet_and_first_swing_and_no_stop():
    yaw = 0.3
    heading = np.array([math.cos(yaw), math.sin(yaw)])
    left_dir = np.array([-math.sin(yaw), math.cos(yaw)])
    start = np.array([1.0, 2.0])
    left = Footstep(Side.LEFT, start + 0.05 * left_dir, yaw)
    right = Footstep(Side.RIGHT, start - 0.05 * left_dir, yaw)
    plan = VelocityPlanner().plan(
        (0.1, 0.0, 0.0), 4, initial_left=left, initial_right=right, first_swing="left", stop=False
    )
    assert plan.nb_steps == 4
    assert [s.side for s in plan.steps] == [Side.LEFT, Side.RIGHT, Side.LEFT, Side.RIGHT]
    for k, step in enumerate(plan.steps):
        expected = start + 0.05 * (k + 1) * heading + step.side.sign * 0.05 * left_dir
        np.testing.assert_allclose(step.xy, expected, atol=1e-12)
        assert step.yaw == pytest.approx(yaw, abs=1e-12)


def test_exact_integration_of_the_unicycle_model():
    command = VelocityCommand(0.0, 0.08, 0.4)  # pure sideways + turning: a circle
    poses = integrate_torso(command, (0.0, 0.0, 0.0), 30, 0.5)
    radius = 0.08 / 0.4  # moving along +y and turning left: centre at (-radius, 0)
    np.testing.assert_allclose(
        np.linalg.norm(poses[:, :2] - [-radius, 0.0], axis=1), radius, atol=1e-12
    )
    # forward Euler with a fine step converges to the same pose
    fine = np.zeros(3)
    dt = 0.5 / 2000
    for _ in range(2000 * 30):
        c, s = math.cos(fine[2]), math.sin(fine[2])
        fine += dt * np.array([-0.08 * s, 0.08 * c, 0.4])
    np.testing.assert_allclose(poses[-1], fine, atol=1e-4)


@pytest.mark.parametrize(
    "command, limit, pattern",
    [
        ((0.2, 0.0, 0.0), 0.16, r"vx=0\.2 m/s exceeds its limit \|vx\| <= 0\.16 m/s"),
        ((-0.1, 0.0, 0.0), 0.08, r"vx=-0\.1 m/s exceeds its limit \|vx\| <= 0\.08 m/s"),
        ((0.0, 0.1, 0.0), 0.06, r"vy=0\.1 m/s exceeds its limit \|vy\| <= 0\.06 m/s"),
        ((0.0, 0.0, -0.6), 0.55, r"vyaw=-0\.6 rad/s exceeds its limit \|vyaw\| <= 0\.55 rad/s"),
    ],
)
def test_infeasible_commands_name_value_and_limit(command, limit, pattern):
    with pytest.raises(InfeasibleCommand, match=pattern) as info:
        plan_from_velocity(*command, 10)
    assert info.value.limit == pytest.approx(limit, abs=1e-12)
    # just inside the limit is accepted
    inside = [c * (limit / abs(c)) * (1.0 - 1e-9) if c else 0.0 for c in command]
    assert plan_from_velocity(*inside, 4).nb_steps == 5


def test_bad_inputs_raise_configuration_errors():
    with pytest.raises(ConfigurationError, match="vx must be finite"):
        VelocityCommand(float("nan"), 0.0, 0.0)
    with pytest.raises(ConfigurationError, match="vyaw must be finite"):
        plan_from_velocity(0.1, 0.0, float("inf"), 4)
    with pytest.raises(ConfigurationError, match="nb_steps must be a non-negative integer"):
        plan_from_velocity(0.1, 0.0, 0.0, -1)
    with pytest.raises(ConfigurationError, match="y_sep <= half_stance_width"):
        LegLimits(y_sep=0.06)
    with pytest.raises(ConfigurationError, match=r"\(vx, vy, vyaw\)"):
        VelocityPlanner().plan((0.1, 0.0), 4)
    with pytest.raises(ConfigurationError, match="'left' or 'right'"):
        VelocityPlanner().plan((0.1, 0.0, 0.0), 4, first_swing="middle")


def test_standing_still_steps_in_place():
    plan = plan_from_velocity(0.0, 0.0, 0.0, 3)
    assert plan.nb_steps == 4
    for step in plan.steps:
        np.testing.assert_allclose(step.xy, [0.0, step.side.sign * 0.05], atol=1e-15)
    assert plan_from_velocity(0.0, 0.0, 0.0, 0).nb_steps == 0
