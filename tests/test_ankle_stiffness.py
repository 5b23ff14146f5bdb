"""Paper M's open-loop engine on romeo: its ankle servos follow the rule of `robots init`
(kp = 3 m g l), stiff enough that the ankle's deflection under the torque the engine asks
for does not lean the robot off its reference."""

import pytest
from conftest import get_robot, walk

from mpcwalk.robot.survey.rules import leg_stiffness


def test_romeo_ankle_servos_follow_the_leg_rule():
    robot = get_robot("romeo")
    stiffness = dict(zip(robot.joint_names, robot.servo_gains.stiffness))
    rule = leg_stiffness(robot.total_mass, robot.leg_length)  # 777 N m/rad
    for side in ("left", "right"):
        for role in ("ankle_pitch", "ankle_roll"):
            joint = robot.joint_roles.joint(side, role)
            assert joint is not None
            assert stiffness[joint] == pytest.approx(rule, rel=0.01), joint


@pytest.mark.slow
def test_paper_m_walks_romeo():
    """With ankle servos of 300 N m/rad (the other joints' stiffness), romeo leant back by
    up to 5 deg at its 25.8 N m ankle torque limit and fell in its third step at 3.26 s."""
    result = walk("romeo", "paper-m", command=(0.1, 0.0, 0.0), nb_steps=5)
    m = result.metrics
    assert result.config.state_source == "estimator"
    assert not m.fell, m.fall_reason
    assert m.steps_completed == m.steps_planned == 6
    assert m.foot_position_error_cm_max < 7.0  # measured 4.61 cm
