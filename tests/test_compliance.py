"""Servo feed-forward: compliant position servos hold a one-foot stance in MuJoCo."""

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from mpcwalk.control.servo_feedforward import ServoFeedforward
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik import IKTargets, WholeBodyIK
from mpcwalk.robot import ServoGains
from mpcwalk.sim import Simulation


@pytest.fixture(scope="module")
def robot():
    return get_robot("bioloid-like")


def one_foot_stance(robot):
    """Configurations: CoM above the left sole (both feet down), then the right foot lifted."""
    ik = WholeBodyIK(robot)
    left, right = robot.compute_sole_placements(robot.q0)
    com = robot.compute_com(robot.q0)
    com[:2] = left.translation[:2]
    lifted = right.copy()
    lifted.translation[2] += 0.02
    shifted = ik.solve_pose(robot.q0, IKTargets(com, left, right, np.eye(3))).q_next
    raised = ik.solve_pose(shifted, IKTargets(com, left, lifted, np.eye(3))).q_next
    return shifted, raised


def hold(robot, shifted, raised, feedforward):
    """Shift the weight over 1 s, lift the right foot, hold 0.5 s: the final state."""
    simulation = Simulation(robot, control_period=0.01)
    state = simulation.reset(robot.q0)
    for i in range(150):
        share = min(1.0, i / 100)
        q = robot.q0 + share * (shifted - robot.q0) if i < 100 else shifted
        weights = (0.5 + 0.5 * share, 0.5 - 0.5 * share)
        if i >= 100:
            q, weights = raised, (1.0, 0.0)
        offsets = 0.0 if feedforward is None else feedforward.compute_offsets(q, weights)
        state = simulation.step(q[7:] + offsets)
    return state


def test_feedforward_makes_the_servos_hold_a_one_foot_stance(robot):
    shifted, raised = one_foot_stance(robot)
    feedforward = ServoFeedforward(robot)
    held = hold(robot, shifted, raised, feedforward)
    sagged = hold(robot, shifted, raised, None)
    error_held = np.abs(held.oracle.joint_positions - raised[7:]).max()
    error_sagged = np.abs(sagged.oracle.joint_positions - raised[7:]).max()
    # kp = 50 N m/rad servos: 1.6 mrad held, 17 mrad (1 deg) sagged, measured
    assert error_held < 0.005  # [rad]
    assert error_sagged > 0.01 and error_sagged > 5.0 * error_held
    assert not held.oracle.right_foot.in_contact
    target = robot.compute_com(raised)[:2]
    assert np.linalg.norm(held.oracle.com[:2] - target) < 0.005


def test_servo_parameters_come_from_the_mujoco_actuators(robot):
    feedforward = ServoFeedforward(robot)
    np.testing.assert_allclose(feedforward.stiffness, 50.0)
    np.testing.assert_allclose(feedforward.torque_limit, 1.5)
    np.testing.assert_allclose(feedforward.damping, 0.5 + 0.02)  # servo kv + joint damping
    torques = feedforward.compute_torques(robot.q0, (0.5, 0.5))
    offsets = feedforward.compute_offsets(robot.q0, (0.5, 0.5))
    np.testing.assert_allclose(offsets, torques / 50.0)
    # standing symmetric: mirrored joints carry mirrored torques, the knees the most
    names = robot.joint_names
    knee = torques[names.index("left_knee")]
    assert knee == pytest.approx(torques[names.index("right_knee")], rel=1e-9)
    assert abs(knee) == pytest.approx(np.abs(torques).max())


def test_servo_gains_are_read_from_mujoco_once_at_load(robot):
    gains = robot.servo_gains
    assert gains.stiffness.shape == gains.damping.shape == (len(robot.joint_names),)
    np.testing.assert_array_equal(
        np.sort(gains.stiffness), np.sort(robot.mj_model.actuator_gainprm[:, 0])
    )
    with pytest.raises(ValueError):  # read-only: the robot's servos are what MuJoCo has
        gains.stiffness[0] = 1.0


def test_robot_without_position_actuators_is_refused(robot):
    n = len(robot.joint_names)
    unactuated = ServoGains(np.full(n, np.inf), np.zeros(n), np.full(n, np.inf))
    with pytest.raises(ConfigurationError, match="no position actuator"):
        ServoFeedforward(dataclasses.replace(robot, servo_gains=unactuated))
