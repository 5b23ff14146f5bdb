"""Torque actuation: motors in MuJoCo, the contact loads, a walk of the torque controller."""

import numpy as np
import pytest
from conftest import get_robot, walk

from mpcwalk.control.torque_controller import contact_loads
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps import FootGeometry
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.ik.inverse_dynamics import torque_limits
from mpcwalk.sim import Simulation
from mpcwalk.walking.specification import WalkSpec, WorldSpec
from mpcwalk.walking.walk_setup import set_up_walk


def test_torque_simulation_drives_motors_with_the_torque_limits():
    robot = get_robot("bioloid-like")
    simulation = Simulation(robot, actuation="torque", sensors=None)
    model = simulation.model
    assert model.nu == robot.mj_model.nu
    assert np.all(model.actuator_biasprm == 0.0) and np.all(model.actuator_gainprm[:, 0] == 1.0)
    limits = torque_limits(robot)
    ctrl_limit = simulation._torque_ctrl(limits)  # joint order to actuator order
    assert np.allclose(model.actuator_ctrlrange[:, 1], ctrl_limit)
    torques = 0.3 * limits * np.sin(np.arange(len(limits)))
    simulation.step(torques=torques)
    assert np.allclose(simulation.data.actuator_force, simulation._torque_ctrl(torques))
    with pytest.raises(ConfigurationError, match="torques="):
        simulation.step(robot.q0[7:])
    position = Simulation(robot)
    assert np.any(position.model.actuator_biasprm[:, 1] != 0.0)  # servos: -kp
    with pytest.raises(ConfigurationError, match="joint_targets"):
        position.step(torques=torques)
    with pytest.raises(ConfigurationError, match="actuation"):
        WorldSpec(actuation="hydraulic")


def test_contact_loads_ramp_at_touch_down_and_lift_off():
    robot = get_robot("bioloid-like")
    setup = set_up_walk(
        WalkSpec.build("bioloid-like", command=(0.1, 0.0, 0.0), nb_steps=2), robot=robot
    )
    schedule: ContactSchedule = setup.schedule
    assert isinstance(schedule.foot, FootGeometry)
    single = next(ph for ph in schedule.phases if ph.single_support)
    swing = 0 if single.support_side.name == "RIGHT" else 1
    middle = 0.5 * (single.start + single.end)
    assert contact_loads(schedule, middle, 0.04)[swing] == 0.0
    assert contact_loads(schedule, middle, 0.04)[1 - swing] == 1.0
    assert contact_loads(schedule, single.start - 0.02, 0.04)[swing] == pytest.approx(0.5)
    assert contact_loads(schedule, single.end + 0.01, 0.04)[swing] == pytest.approx(0.25)
    assert contact_loads(schedule, 0.0, 0.04) == (1.0, 1.0)  # no ramp at the start
    assert contact_loads(schedule, schedule.duration, 0.04) == (1.0, 1.0)


@pytest.mark.slow
def test_small_humanoid_stands_and_walks_four_steps_on_motors():
    result = walk("bioloid-like", "mpc", command=(0.1, 0.0, 0.0), nb_steps=4, actuation="torque")
    m, log = result.metrics, result.log
    assert result.spec.world.actuation == "torque"
    assert not m.fell and m.steps_completed == m.steps_planned == 5
    assert m.foot_position_error_cm_mean < 1.0
    assert m.distance_m == pytest.approx(m.distance_planned_m, abs=0.03)
    # the motors never exceed the servos' torque limits
    limit = np.max(get_robot("bioloid-like").servo_gains.torque_limit)
    assert np.abs(log.actuator_force).max() <= limit + 1e-9
    # standing the first second: the CoM follows the generator's shift over the first support
    # foot, and the feet carry the weight
    standing = log.time < 1.0
    error = np.linalg.norm(log.com[:, :2] - log.com_reference, axis=1)
    assert error[standing].max() < 0.003
    assert error.max() < 0.01
    weight = 9.81 * get_robot("bioloid-like").total_mass
    vertical = log.foot_wrenches[standing][:, :, 2].sum(axis=1)
    assert np.median(vertical) == pytest.approx(weight, rel=0.05)
