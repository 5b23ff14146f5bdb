"""The terrain in the simulated world: the robots' leg lengths, the scene's boxes, a robot
standing on a terrain, and the fall detector measuring heights from the ground under it."""

import pytest
from conftest import get_robot

from mpcwalk.robot import robot_names

NAMES = robot_names()


@pytest.mark.parametrize("name", NAMES)
def test_every_robot_has_two_hips_and_a_leg_length_below_its_com_height(name):
    robot = get_robot(name)
    left, right = robot.hip_joints
    assert left != right
    model = robot.model
    for hip, sole in zip(robot.hip_joints, robot.foot_frames):
        joint = model.frames[model.getFrameId(sole)].parentJoint
        chain = []
        while joint > 0:
            chain.append(model.names[joint])
            joint = model.parents[joint]
        assert hip in chain  # the hip carries its sole
        assert model.names[model.parents[model.getJointId(hip)]] == chain[-1]  # off the base
    assert 0.6 * robot.com_height < robot.leg_length < 1.0 * robot.com_height


def test_the_small_humanoid_has_a_leg_of_about_two_decimetres():
    assert get_robot("bioloid-like").leg_length == pytest.approx(0.215, abs=0.002)
