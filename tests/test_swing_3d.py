"""Feet on tilted treads: the swing interpolates roll and pitch like the yaw, a stance foot keeps
its tilt, the IK targets take the full sole rotation (bit for bit the yaw's when flat)."""

import math

import numpy as np
import pinocchio as pin
import pytest
from plans import velocity_schedule

from mpcwalk.control.gait_reference import GaitTargets
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.swing_foot import SwingFootTrajectory
from mpcwalk.ik.targets import IKTargets

PITCH = math.radians(10.0)


def _pitched_landing_schedule() -> ContactSchedule:
    """Step 0: the right foot from level ground onto a tread 5 cm up, pitched 10 deg (toes
    down) and rolled 4 deg; step 1: the left foot, level, while the right one supports."""
    left = Footstep(Side.LEFT, [0.0, 0.1, 0.0])
    right = Footstep(Side.RIGHT, [0.0, -0.1, 0.0])
    landing = Footstep(Side.RIGHT, [0.15, -0.1, 0.05], 0.2, math.radians(4.0), PITCH)
    steps = (landing, left.moved(position=[0.15, 0.1, 0.0]))
    return ContactSchedule(FootstepPlan(left, right, steps, StepTiming(step_duration=1.0)))


@pytest.mark.parametrize("profile", ["cosine", "ctraj"])
def test_swing_from_level_to_a_pitched_landing_ends_at_its_rotation(profile):
    schedule = _pitched_landing_schedule()
    trajectory = SwingFootTrajectory(schedule, 0.04, profile)
    landing = schedule.plan.steps[0]
    t0 = schedule.walk_start
    lift_off = trajectory.foot_poses(t0 + schedule.t_b + 1e-9)[Side.RIGHT]
    assert not lift_off.in_contact
    np.testing.assert_allclose(lift_off.rotation, np.eye(3), atol=1e-7)
    touchdown = trajectory.foot_poses(t0 + schedule.t_e - 1e-9)[Side.RIGHT]
    np.testing.assert_allclose(touchdown.rotation, landing.rotation_matrix, atol=1e-7)
    np.testing.assert_allclose(touchdown.position, landing.position, atol=1e-7)
    # the roll and pitch follow the yaw's law: the same fraction of the way at every time
    for t in np.linspace(t0 + schedule.t_b, t0 + schedule.t_e, 9)[1:-1]:
        foot = trajectory.foot_poses(float(t))[Side.RIGHT]
        fraction = foot.yaw / landing.yaw
        assert 0.0 < fraction < 1.0
        assert foot.pitch == pytest.approx(fraction * PITCH, abs=1e-12)
        assert foot.roll == pytest.approx(fraction * landing.roll, abs=1e-12)
        assert foot.pitch_rate == pytest.approx(foot.yaw_rate / landing.yaw * PITCH, abs=1e-12)
        # the angular velocity is the derivative of the rotation: [w]x = dR/dt R^T
        dt = 1e-6
        before = trajectory.foot_poses(float(t) - dt)[Side.RIGHT].rotation
        after = trajectory.foot_poses(float(t) + dt)[Side.RIGHT].rotation
        skew = (after - before) / (2 * dt) @ foot.rotation.T
        omega = np.array([skew[2, 1], skew[0, 2], skew[1, 0]])
        np.testing.assert_allclose(foot.angular_velocity, omega, atol=1e-6)
    # on the ground the foot sits on its tread, and keeps its tilt while it supports step 1
    for t in (t0 + 0.95, t0 + 1.5, schedule.duration):
        stance = trajectory.foot_poses(t)[Side.RIGHT]
        assert stance.in_contact and (stance.roll, stance.pitch) == (landing.roll, PITCH)
        np.testing.assert_array_equal(stance.rotation, landing.rotation_matrix)
        np.testing.assert_array_equal(stance.angular_velocity, np.zeros(3))


def test_a_restarted_swing_keeps_its_tilt_and_reaches_the_new_landing():
    schedule = _pitched_landing_schedule()
    trajectory = SwingFootTrajectory(schedule, 0.04)
    t = schedule.walk_start + 0.5
    before = trajectory.foot_poses(t)[Side.RIGHT]
    moved = schedule.plan.steps[0].moved(position=[0.2, -0.12, 0.05], pitch=-PITCH)
    follower = SwingFootTrajectory(schedule.with_steps([moved, schedule.plan.steps[1]]), 0.04)
    follower.restart_swing(t, before)
    now = follower.foot_poses(t)[Side.RIGHT]
    assert (now.roll, now.pitch, now.yaw) == pytest.approx(
        (before.roll, before.pitch, before.yaw), abs=1e-12
    )
    end = follower.foot_poses(schedule.walk_start + schedule.t_e - 1e-9)[Side.RIGHT]
    np.testing.assert_allclose(end.rotation, moved.rotation_matrix, atol=1e-7)


def _old_ik_sole(foot) -> pin.SE3:
    """The IK sole target of the yaw alone (before the soles had roll and pitch)."""
    c, s = np.cos(foot.yaw), np.sin(foot.yaw)
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return pin.SE3(rotation, np.array(foot.position, dtype=float))


def _old_transform(foot) -> np.ndarray:
    c, s = np.cos(foot.yaw), np.sin(foot.yaw)
    out = np.eye(4)
    out[:2, :2] = [[c, -s], [s, c]]
    out[:3, 3] = foot.position
    return out


@pytest.mark.parametrize("profile", ["cosine", "ctraj"])
def test_flat_walks_give_bit_identical_ik_targets(profile):
    schedule = velocity_schedule((0.1, 0.0, 0.3), 6)  # turning: yaws and yaw rates not zero
    trajectory = SwingFootTrajectory(schedule, 0.04, profile)
    for t in np.arange(0.0, schedule.duration, 0.013):
        feet, yaw = trajectory.references(float(t))
        targets = GaitTargets(feet, np.array([0.01, 0.0]), float(yaw)).ik_targets(0.0, 0.3)
        gait = IKTargets.from_gait(np.zeros(3), feet, float(yaw))
        for side, sole, velocity in (
            (Side.LEFT, targets.left_sole, gait.left_sole_velocity),
            (Side.RIGHT, targets.right_sole, gait.right_sole_velocity),
        ):
            foot = feet[side]
            assert foot.is_flat
            old = _old_ik_sole(foot)
            assert sole.rotation.tobytes() == old.rotation.tobytes()
            assert sole.translation.tobytes() == old.translation.tobytes()
            assert foot.transform.tobytes() == _old_transform(foot).tobytes()
            old_velocity = np.concatenate([foot.linear_velocity, [0.0, 0.0, foot.yaw_rate]])
            assert velocity.tobytes() == old_velocity.tobytes()


def test_ik_targets_take_the_tilted_soles_rotation():
    schedule = _pitched_landing_schedule()
    trajectory = SwingFootTrajectory(schedule, 0.04)
    landing = schedule.plan.steps[0]
    for t in (schedule.walk_start + 0.97, schedule.walk_start + 1.5):
        feet, yaw = trajectory.references(t)
        targets = GaitTargets(feet, np.zeros(2), float(yaw)).ik_targets(0.0, 0.3)
        np.testing.assert_allclose(targets.right_sole.rotation, landing.rotation_matrix, atol=1e-15)
        np.testing.assert_array_equal(targets.right_sole.translation, landing.position)
        np.testing.assert_array_equal(
            IKTargets.from_gait(np.zeros(3), feet, yaw).right_sole.rotation, landing.rotation_matrix
        )
        # the torso stays upright
        assert targets.torso_rotation[2, 2] == 1.0
