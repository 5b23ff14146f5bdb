"""Joint torque sensors and the joint torque loop: the sensors' readings in torque mode, their
noise, and the motors' gains estimated from them."""

import dataclasses
import math

import numpy as np
import pytest
from conftest import get_robot, walk
from test_sensing import constant_truth

from mpcwalk.control.torque_loop import GAIN_RANGE, TorqueLoop
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.inverse_dynamics import torque_limits
from mpcwalk.robot.sensors import SensorReadings
from mpcwalk.sim import SensorModel, SensorSimulator, Simulation
from mpcwalk.sim.model_mismatch import ModelMismatch
from mpcwalk.sim.sensing.faults import SensorFaults, readings_are_finite

PERIOD = 0.01  # [s]


def truth(nb_joints: int, torques: np.ndarray | None) -> SensorReadings:
    """Readings of a robot at rest with joint torque sensors reading ``torques``."""
    return dataclasses.replace(constant_truth(nb_joints), joint_torques=torques)


def run_motors(loop: TorqueLoop, gains, *, latency: int, seconds: float, noise: float, seed=0):
    """Drive motors of true ``gains`` with the loop: the joints need torques that sweep 20 to
    60 % of their limits; each reading (the applied torque plus noise, a share of the limit)
    reaches the loop ``latency`` periods late. Returns the needed and the applied torques."""
    rng = np.random.default_rng(seed)
    limits, nb = loop.limits, len(loop.limits)
    phases = np.linspace(0.0, 2.0, nb)
    readings: list[tuple[float, np.ndarray]] = []
    needed_all, applied_all = [], []
    for k in range(int(round(seconds / PERIOD))):
        t = (k + 1) * PERIOD  # the command of tick k is held until t, read at t
        if len(readings) > latency:
            loop.measure(*readings[-1 - latency])
        needed = limits * (0.4 + 0.2 * np.sin(2.0 * math.pi * 1.3 * t + phases))
        command = loop.command(t, needed)
        applied = gains * command
        readings.append((t, applied + noise * limits * rng.standard_normal(nb)))
        needed_all.append(needed)
        applied_all.append(applied)
    return np.array(needed_all), np.array(applied_all)


def test_the_loop_finds_each_motors_gain_through_the_latency():
    limits = np.array([100.0, 50.0, 20.0, 200.0])
    gains = np.array([0.72, 0.9, 1.25, 1.0])
    loop = TorqueLoop(limits, control_period=PERIOD)
    needed, applied = run_motors(loop, gains, latency=3, seconds=2.0, noise=0.005)
    assert loop.readings_used == pytest.approx(200 - 4, abs=1)  # every reading paired
    assert np.allclose(loop.gains, gains, rtol=0.01)
    # after a second the joints get what they need, within 1 % of their limit (without the
    # loop the weakest gets 28 % less)
    late = slice(100, None)
    error = np.abs(applied[late] - needed[late]) / limits
    assert error.max() < 0.01
    assert np.abs(needed[late] * gains - needed[late]).max(axis=0)[0] > 0.1 * limits[0]


def test_a_reading_without_its_command_is_not_used():
    loop = TorqueLoop(np.array([10.0, 10.0]), control_period=PERIOD)
    loop.measure(0.01, np.array([1.0, 1.0]))  # before any command
    loop.command(0.01, np.array([5.0, -5.0]))
    loop.measure(0.015, np.array([4.0, -4.0]))  # half a period off: another tick's
    loop.measure(0.01, None)  # no sensors
    loop.measure(0.01, np.array([np.nan, 4.0]))  # a faulty reading
    assert loop.readings_used == 0 and np.all(loop.gains == 1.0)
    loop.command(0.02, np.array([5.0, -5.0]))
    loop.measure(0.02, np.array([4.0, -4.0]))  # the reading of 0.01 is dropped with it
    assert loop.readings_used == 1 and np.all(loop.gains < 1.0)
    loop.reset()
    assert loop.readings_used == 0 and np.all(loop.gains == 1.0)


def test_commands_stay_within_the_limits_and_light_joints_keep_their_gain():
    limits = np.array([10.0, 10.0])
    loop = TorqueLoop(limits, control_period=PERIOD)
    for k in range(300):  # joint 0 asks twice its limit of a motor of gain 0.6; joint 1 a
        t = (k + 1) * PERIOD  # torque of 0.5 % of its limit on a motor of gain 0.6
        command = loop.command(t, np.array([20.0, 0.05]))
        assert np.all(np.abs(command) <= limits)
        loop.measure(t, 0.6 * command)
    # the clipped command is the regressor; the prior pulls by (0.05 * 10)^2 / 10^2 towards 1
    assert loop.gains[0] == pytest.approx((0.6 * 100.0 + 0.25) / (100.0 + 0.25), rel=1e-3)
    assert loop.gains[1] > 0.98  # 0.5 % of the limit is a hundredth of the prior's weight
    low, high = GAIN_RANGE
    for k in range(300, 600):
        t = (k + 1) * PERIOD
        loop.measure(t, 0.1 * loop.command(t, np.array([5.0, 5.0])))
    assert np.all(loop.gains == low) and high > 1.0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"torque_limits": [10.0, 0.0]}, "positive limit per joint"),
        ({"torque_limits": [10.0, float("nan")]}, "positive limit per joint"),
        ({"torque_limits": [10.0], "control_period": 0.0}, "control_period must be > 0"),
        ({"torque_limits": [10.0], "memory": -1.0}, "memory must be > 0"),
        ({"torque_limits": [10.0], "prior_share": -0.1}, "prior_share must be >= 0"),
    ],
)
def test_bad_loop_settings_are_named(kwargs, match):
    kwargs = {"control_period": PERIOD, **kwargs}
    limits = kwargs.pop("torque_limits")
    with pytest.raises(ConfigurationError, match=match):
        TorqueLoop(np.array(limits), **kwargs)


def test_joint_torque_sensors_read_what_weak_motors_apply():
    robot = get_robot("bioloid-like")
    weak = Simulation(
        robot,
        actuation="torque",
        sensors=SensorModel.ideal(),
        model_mismatch=ModelMismatch(servo_strength=0.8),
    )
    limits = torque_limits(robot)
    torques = 0.3 * limits * np.sin(np.arange(len(limits)))
    state = weak.step(torques=torques)
    assert np.allclose(state.sensors.joint_torques, 0.8 * torques, rtol=1e-9, atol=1e-12)
    assert state.sensors.time == pytest.approx(PERIOD)
    assert Simulation(robot, sensors=SensorModel.ideal()).step().sensors.joint_torques is None


def test_joint_torque_noise_is_a_share_of_the_limit_and_leaves_the_other_readings_alone():
    limits = np.array([1.0, 10.0, 100.0, np.inf])
    exact = truth(4, np.array([0.5, -5.0, 20.0, 3.0]))
    model = SensorModel.large_robot()
    with_torques = SensorSimulator(model, period=PERIOD, nb_joints=4, seed=7, torque_limits=limits)
    without = SensorSimulator(model, period=PERIOD, nb_joints=4, seed=7)
    with_torques.reset(exact)
    without.reset(dataclasses.replace(exact, joint_torques=None))
    samples = []
    for _ in range(3000):
        a = with_torques.read(exact)
        b = without.read(dataclasses.replace(exact, joint_torques=None))
        assert b.joint_torques is None
        assert np.array_equal(a.imu.gyro, b.imu.gyro)  # the same draws for the rest
        assert np.array_equal(a.joint_positions, b.joint_positions)
        assert np.array_equal(a.right_wrench.torque, b.right_wrench.torque)
        samples.append(a.joint_torques - exact.joint_torques)
    deviation = np.std(samples, axis=0)
    expected = model.joint_torque_noise * limits[:3]  # 0.5 % of each limit
    assert deviation[:3] == pytest.approx(expected, rel=0.1)
    assert deviation[3] == 0.0  # no limit, no scale: exact
    assert SensorModel.small_servo_humanoid().joint_torque_noise > model.joint_torque_noise
    with pytest.raises(ConfigurationError, match="one limit per joint"):
        SensorSimulator(model, period=PERIOD, nb_joints=4, torque_limits=limits[:2])


def test_a_nan_window_reaches_the_joint_torque_sensors():
    readings = truth(3, np.array([1.0, 2.0, 3.0]))
    faulty = SensorFaults(nan=[(0.0, 1.0)]).apply(readings)
    assert faulty is not None and np.all(np.isnan(faulty.joint_torques))
    assert not readings_are_finite(faulty)
    bad_torque = dataclasses.replace(readings, joint_torques=np.array([1.0, np.inf, 3.0]))
    assert not readings_are_finite(bad_torque) and readings_are_finite(readings)


def test_a_walk_turns_the_loop_on_with_motors_only():
    from mpcwalk.control.torque_controller import TorqueController
    from mpcwalk.footsteps import VelocityCommand, VelocityPlanner
    from mpcwalk.gait.contact_schedule import ContactSchedule
    from mpcwalk.walking.controller_builder import check_controller
    from mpcwalk.walking.specification import ControllerSpec

    spec = ControllerSpec(generator="mpc", controller_options={"torque_loop": True})
    check_controller(spec, "torque")
    with pytest.raises(ConfigurationError, match="torque_loop drive.*actuation is 'position'"):
        check_controller(spec, "position")
    words = dataclasses.replace(spec, controller_options={"torque_loop": "yes"})
    with pytest.raises(ConfigurationError, match="torque_loop must be true or false, got 'yes'"):
        check_controller(words, "torque")
    robot = get_robot("bioloid-like")
    schedule = ContactSchedule(VelocityPlanner().plan(VelocityCommand(0.1, 0.0, 0.0), nb_steps=2))
    walker = TorqueController.for_robot(robot, "mpc", schedule, torque_loop=True)
    assert walker.torque_loop is not None
    assert np.array_equal(walker.torque_loop.limits, torque_limits(robot))
    assert TorqueController.for_robot(robot, "mpc", schedule).torque_loop is None
    with pytest.raises(ConfigurationError, match="torque_loop must be true or false"):
        TorqueController.for_robot(robot, "mpc", schedule, torque_loop=1)


@pytest.mark.slow
def test_romeo_walks_on_weak_motors_with_its_joint_torque_loop():
    """romeo's motors give 76 % of their torque (the torque matrix's servo walk, seed 121): on
    the inverse dynamics' torques alone it falls at its first step; with the loop it walks
    every step."""
    world = {"actuation": "torque", "servo_strength": 0.7594, "seed": 121}
    fields = {"command": (0.15, 0.0, 0.0), "nb_steps": 8, **world}
    weak = walk("romeo", "mpc", **fields).metrics
    assert weak.fell and weak.steps_completed <= 2
    m = walk("romeo", "mpc", controller_options={"torque_loop": True}, **fields).metrics
    assert m.outcome == "walked" and m.steps_completed == m.steps_planned
    assert m.foot_position_error_cm_mean < 2.5  # measured 2.05 (0.59 at full strength)
