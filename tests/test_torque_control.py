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
    assert error.max() < 0.012  # measured 10.2 mm (7.8 mm before the swing's delay cap)
    weight = 9.81 * get_robot("bioloid-like").total_mass
    vertical = log.foot_wrenches[standing][:, :, 2].sum(axis=1)
    assert np.median(vertical) == pytest.approx(weight, rel=0.05)


def test_state_delay_adds_latency_period_and_the_velocity_filter_lag():
    from mpcwalk.control.torque_controller import state_delay

    assert state_delay(0.01) == pytest.approx(0.01)  # the simulator's exact state
    delay = state_delay(0.01, latency=0.01, velocity_cutoff=15.0)
    assert delay == pytest.approx(0.02 + 1.0 / (2.0 * np.pi * 15.0))  # 30.6 ms
    with pytest.raises(ConfigurationError, match="velocity_cutoff"):
        state_delay(0.01, velocity_cutoff=0.0)


def test_motors_start_with_the_readings_of_a_robot_at_rest():
    # Held by its static torques on contacts that carry no load yet, atlas-like's base drops
    # and pitches in MuJoCo's first instant: its accelerometer read (0.64, 0, 9.14) m/s^2,
    # gravity's norm within 7 %, and the estimator took a 3.9 deg pitch from it.
    from mpcwalk.estimation.estimator import Estimator

    robot = get_robot("atlas-like")
    simulation = Simulation(robot, actuation="torque", sensors=None)
    readings = simulation.reset(robot.q0).oracle.sensors  # exact readings
    assert np.allclose(readings.imu.gyro, 0.0)
    # the IMU's vertical in its own frame: gravity's specific force
    imu = simulation.data.site_xmat[simulation.ground_truth._imu_site].reshape(3, 3)
    assert np.allclose(readings.imu.accelerometer, imu.T @ [0.0, 0.0, 9.81], atol=1e-9)
    estimate = Estimator(robot, control_period=0.01).reset(readings, robot.q0)
    assert abs(estimate.pitch) < np.radians(0.01) and abs(estimate.roll) < np.radians(0.01)
    # position servos: the instantaneous readings, as before (no tilt taken from them)
    servo = Simulation(robot, sensors=None).reset(robot.q0).oracle.sensors
    assert np.linalg.norm(servo.imu.accelerometer) < 5.0  # measured 2.6 m/s^2


@pytest.mark.slow
def test_g1_walks_on_motors_without_spinning_its_soles():
    # With the posture task at 15 rad/s on a state 31 ms old, g1's joints chattered: in
    # these four steps a loaded sole spun 94 deg on the ground, the base yawed 12.9 deg, a
    # step was missed and the motors saturated on 23 % of the ticks (20 steps: a fall at
    # 11.2 s, 100 deg of yaw).
    result = walk("g1", "mpc", command=(0.1, 0.0, 0.0), nb_steps=4, actuation="torque")
    m, log = result.metrics, result.log
    assert not m.fell and m.steps_completed == m.steps_planned == 5
    assert np.degrees(np.abs(log.base_rpy[:, 2])).max() < 4.0  # measured 1.7 deg
    assert np.degrees(np.abs(log.sole_yaws)).max() < 4.0  # measured 2.3 deg
    assert m.torque_saturation_share < 0.1  # measured 0.054


def test_torque_walks_leave_out_the_capture_point_term_unless_asked():
    from mpcwalk.generators.mpc_steps import TORQUE_DCM_STEP_GAIN
    from mpcwalk.walking.controller_builder import build_controller

    robot = get_robot("bioloid-like")

    def gain(actuation: str, **options) -> float:
        spec = WalkSpec.build(
            "bioloid-like",
            controller="mpc-steps",
            nb_steps=2,
            actuation=actuation,
            generator_options=options,
        )
        setup = set_up_walk(spec, robot=robot)
        controller = build_controller(
            robot,
            spec.controller,
            setup.schedule,
            control_period=spec.plan.control_period,
            step_height=setup.step_height,
            actuation=actuation,
        )
        return controller.generator.dcm_step_gain

    assert TORQUE_DCM_STEP_GAIN == 0.0
    assert gain("torque") == TORQUE_DCM_STEP_GAIN
    assert gain("position") == 1.0  # servos keep the term
    assert gain("torque", dcm_step_gain=0.5) == 0.5  # a walk's own gain is kept


@pytest.mark.slow
def test_the_small_humanoid_steps_on_motors_with_a_late_state():
    # mpc-steps on motors with 20 ms of latency (a world of the robustness matrix): with the
    # capture-point term the estimated DCM errors, grown to the landing, moved the landings
    # back and forth; the walk turned 10.8 deg and fell at 3.59 s after 4 of 9 steps.
    result = walk(
        "bioloid-like",
        "mpc-steps",
        command=(0.1, 0.0, 0.0),
        nb_steps=8,
        latency=0.02,
        seed=120,
        actuation="torque",
    )
    m = result.metrics
    assert not m.fell and m.steps_completed == m.steps_planned == 9  # measured 9/9
    assert abs(m.yaw_change_deg) < 3.0  # measured 0.0 deg


@pytest.mark.slow
def test_g1_walks_on_motors_up_a_tilted_ground():
    # The robustness matrix's 4 deg tilt (seed 126): the estimator took its first roll and
    # pitch from the accelerometer, which on motors reads gravity at once (tilted here),
    # while its world is the soles' (the loaded soles pull roll and pitch to theirs): it
    # started 3.8 deg off its own world, its CoM 4.2 cm off (RMS), and the walk stopped
    # after one step, the MPC's solves failing. It now starts with the soles flat, as it
    # does on position servos, whose first reading does not read gravity, and predicts the
    # base's acceleration with gravity as it reads it (with the start alone it stopped after
    # 5 steps).
    result = walk(
        "g1",
        "mpc",
        command=(0.1, 0.0, 0.0),
        nb_steps=8,
        actuation="torque",
        ground_tilt=3.9745,
        ground_tilt_direction=51.6,
        seed=126,
    )
    m = result.metrics
    assert not m.fell and m.steps_completed == m.steps_planned == 9
    assert m.estimator_com_error_rms_m < 0.025  # measured 15.1 mm (42.1 mm before)
    assert abs(m.yaw_change_deg) < 3.0  # measured -0.7 deg


@pytest.mark.slow
def test_romeo_walks_on_bumps_on_motors_as_its_soles_narrow_where_they_rock():
    # The robustness matrix's 6.6 mm bumps (seed 128): a sole on bumps touches them inside
    # its outline, and the inverse dynamics, asking the CoP out to 0.9 of the half sole,
    # rolled it from bump to bump, and the matrix's walk fell at 6.8 s after 8 of its 9
    # steps (run alone, with the default, rocking_rate 0, the robot walks with landings 1.4
    # cm off: the walk is chaotic). A sole that turns faster than 1 rad/s narrowing its
    # CoP's share (down to 0.5), the robot walks with landings 0.53 cm off.
    result = walk(
        "romeo",
        "mpc",
        command=(0.15, 0.0, 0.0),
        nb_steps=8,
        actuation="torque",
        ground_roughness=0.0066,
        seed=128,
        controller_options={"rocking_rate": 1.0},
    )
    m = result.metrics
    assert not m.fell and m.steps_completed == m.steps_planned == 9
    assert m.foot_position_error_cm_mean < 1.0  # measured 0.53 cm (1.4 cm with it off)
