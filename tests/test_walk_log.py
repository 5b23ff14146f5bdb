"""The walk log's joint series are in the robot's joint order, whatever MuJoCo's actuator
order."""

from types import SimpleNamespace

import mujoco
import numpy as np

from mpcwalk.robot import load_robot
from mpcwalk.walking.log import WalkLog, WalkLogRecorder


def _foot():
    return SimpleNamespace(in_contact=True, force=np.zeros(3), torque=np.zeros(3))


def _tick(robot, actuator_force):
    nj = len(robot.joint_names)
    measured = SimpleNamespace(
        com=np.zeros(3),
        com_velocity=np.zeros(3),
        cop=np.zeros(3),
        left_foot=_foot(),
        right_foot=_foot(),
        sole_positions=np.zeros((2, 3)),
        sole_yaws=np.zeros(2),
        roll=0.0,
        pitch=0.0,
        yaw=0.0,
        base_position=np.zeros(3),
        joint_positions=np.zeros(nj),
    )
    output = SimpleNamespace(
        generator=SimpleNamespace(com=np.zeros(2), zmp=np.zeros(2)),
        zmp_command=np.zeros(2),
        com_target=np.zeros(3),
        dcm_error=np.zeros(2),
        feet=SimpleNamespace(
            left=SimpleNamespace(position=np.zeros(3)), right=SimpleNamespace(position=np.zeros(3))
        ),
        joint_targets=np.zeros(nj),
        ik=SimpleNamespace(task_errors=SimpleNamespace(position_max=0.0)),
        generator_failed=False,
        generator_tick=0.0,
        ik_tick=0.0,
    )
    estimate = SimpleNamespace(time=0.0, **vars(measured))
    state = SimpleNamespace(time=0.0, oracle=measured)
    return output, state, estimate, actuator_force


def test_actuator_forces_and_limits_are_logged_in_joint_order():
    robot = load_robot("atlas-like")  # its MuJoCo actuators are not in its joint order
    model = robot.mj_model
    actuated = [
        mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, int(model.actuator_trnid[a, 0]))
        for a in range(model.nu)
    ]
    assert actuated != list(robot.joint_names)
    recorder = WalkLogRecorder(robot)
    output, state, estimate, _ = _tick(robot, None)
    recorder.append(
        output,
        state,
        estimate,
        np.arange(model.nu, dtype=float),
        mujoco_step=0.0,
        controller_tick=0.0,
    )
    log = recorder.freeze()
    assert isinstance(log, WalkLog) and log.actuator_force.shape == (1, len(robot.joint_names))
    for j, name in enumerate(log.joint_names):
        actuator = actuated.index(name)
        assert log.actuator_force[0, j] == actuator
        expected = np.abs(model.actuator_forcerange[actuator]).max()
        assert log.torque_limit[j] == (
            expected if model.actuator_forcelimited[actuator] else np.inf
        )
    np.testing.assert_array_equal(log.torque_limit, robot.servo_gains.torque_limit)
