"""The IK's centroidal angular-momentum task: a commanded momentum is produced, on every
robot, from the upper body's limits read from its model."""

from dataclasses import replace

import numpy as np
import pinocchio as pin
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.momentum_task import AngularMomentumTask
from mpcwalk.ik.targets import IKTargets
from mpcwalk.ik.upper_body import upper_body_flywheel
from mpcwalk.ik.whole_body_ik import WholeBodyIK
from mpcwalk.models.flywheel import FlywheelState

ROBOTS = ["bioloid-like", "g1", "atlas-like", "talos", "romeo"]


@pytest.mark.parametrize("name", ROBOTS)
def test_a_commanded_angular_momentum_is_produced(robot_loader, name):
    """Half the momentum limit about each horizontal axis, the torso leaning with it (what
    the controller gives the IK): the step's momentum ``A_G(q) v`` is the target within 15 %,
    and much nearer it than the same lean without the task."""
    robot, dt = robot_loader(name), 0.01
    limits = upper_body_flywheel(robot)
    assert 0.0 < min(limits.max_torque) and 0.0 < min(limits.max_angle) <= 0.3
    ik, plain = WholeBodyIK(robot), WholeBodyIK(robot)
    base = IKTargets.from_configuration(robot, robot.q0)
    centroidal = pin.computeCentroidalMap(robot.model, robot.model.createData(), robot.q0)
    for axis in range(2):
        momentum = np.zeros(2)
        momentum[axis] = 0.5 * limits.max_momentum[axis]
        state = FlywheelState(np.zeros(2), momentum, np.zeros(2))
        rate = np.array([-momentum[1] / limits.inertia[1], momentum[0] / limits.inertia[0], 0.0])
        torso = pin.exp3(dt * rate) @ base.torso_rotation
        target = state.angular_momentum
        with_task = ik.solve(
            robot.q0, replace(base, torso_rotation=torso, angular_momentum=target), dt
        )
        without = plain.solve(robot.q0, replace(base, torso_rotation=torso), dt)
        produced = (centroidal[3:] @ with_task.v)[:2]
        error = np.linalg.norm(produced - target[:2])
        assert error < 0.15 * np.linalg.norm(target)
        assert error < 0.5 * np.linalg.norm((centroidal[3:] @ without.v)[:2] - target[:2])


def test_bad_task_options_are_named():
    with pytest.raises(ConfigurationError, match="inertia"):
        AngularMomentumTask((0.0, 1.0))
    with pytest.raises(ConfigurationError, match="weight"):
        AngularMomentumTask((1.0, 1.0), weight=-1.0)
