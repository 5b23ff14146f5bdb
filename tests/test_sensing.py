"""Sensor model and simulated sensors: figures, seeds, exact readings, noise statistics,
quantisation, latency, foot force/torque sensors."""

import math

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError, SimulationModelError
from mpcwalk.robot.sensors import ForceTorqueReading, ImuReading, SensorReadings
from mpcwalk.sim import SensorModel, SensorSimulator, Simulation
from mpcwalk.sim.sensing.model import MAX_LATENCY

PERIOD = 0.01  # [s]


def readings(state) -> np.ndarray:
    """All readings of a simulation state as one vector."""
    sensors = state.sensors
    return np.concatenate(
        [
            sensors.imu.gyro,
            sensors.imu.accelerometer,
            sensors.joint_positions,
            *(w.force for w in sensors.wrenches),
            *(w.torque for w in sensors.wrenches),
        ]
    )


def constant_truth(nb_joints: int = 4) -> SensorReadings:
    """Readings of a robot at rest, the same every period."""
    wrench = ForceTorqueReading(np.array([1.0, -2.0, 50.0]), np.array([0.3, -0.2, 0.01]))
    return SensorReadings(
        time=0.0,
        imu=ImuReading(np.array([0.1, -0.2, 0.3]), np.array([0.2, -0.1, 9.81])),
        joint_positions=np.linspace(-0.5, 0.5, nb_joints),
        left_wrench=wrench,
        right_wrench=wrench,
    )


def only(**figures) -> SensorModel:
    """A model with the given figures, every other noise zero, no latency."""
    return SensorModel(**{**SensorModel.ideal().to_dict(), **figures})


def test_figures_of_the_small_and_the_large_robots():
    small = SensorModel.for_robot(get_robot("bioloid-like"))
    assert small == SensorModel.small_servo_humanoid()
    assert small.encoder_resolution == pytest.approx(math.radians(300.0 / 1024.0))  # AX-12
    assert SensorModel.for_robot(get_robot("atlas-like")) == SensorModel.large_robot()
    large = SensorModel()
    assert large.encoder_resolution == pytest.approx(2.0 * math.pi / 2**17)
    assert large.force_noise_std > small.force_noise_std and small.latency == large.latency == 1
    # the BMI088's gyro noise density, 0.014 deg/s/sqrt(Hz), read at 100 Hz
    assert large.gyro_std(PERIOD) == pytest.approx(math.radians(0.014) * 10.0)
    assert SensorModel.ideal().is_exact and SensorModel.ideal().latency == 0
    assert not large.is_exact


def test_scaled_multiplies_every_noise_bias_and_resolution_and_keeps_the_latency():
    model = SensorModel.small_servo_humanoid().with_latency(3)
    doubled = model.scaled(2.0)
    for name, value in model.to_dict().items():
        expected = value if name == "latency" else 2.0 * value
        assert getattr(doubled, name) == expected, name
    exact = model.scaled(0.0)
    assert exact.is_exact and exact.latency == 3
    assert exact == SensorModel.ideal().with_latency(3)


@pytest.mark.parametrize(
    ("figures", "match"),
    [
        (
            {"gyro_noise_density": -1.0},
            r"SensorModel.gyro_noise_density must be a number >= 0, got -1.0; fix it",
        ),
        ({"torque_noise_std": float("nan")}, r"torque_noise_std must be a number >= 0, got nan"),
        ({"encoder_resolution": "0.01"}, r"encoder_resolution must be a number >= 0"),
        ({"latency": 1.5}, r"latency must be a whole number of control periods, got 1.5"),
        ({"latency": -1}, rf"latency must be between 0 and {MAX_LATENCY} control periods"),
        ({"latency": MAX_LATENCY + 1}, rf"between 0 and {MAX_LATENCY} control periods"),
    ],
)
def test_bad_figures_raise_a_named_error(figures, match):
    with pytest.raises(SimulationModelError, match=match) as error:
        SensorModel(**figures)
    assert error.value.field == next(iter(figures))
    assert isinstance(error.value, ConfigurationError)


def test_bad_scale_raises():
    with pytest.raises(
        SimulationModelError, match=r"scaled\(factor\) must be a number >= 0, got -0.5"
    ):
        SensorModel().scaled(-0.5)


def test_readings_are_seeded_and_reproducible():
    robot = get_robot("bioloid-like")
    runs = {}
    for key, seed in (("a", 3), ("b", 3), ("c", 4)):
        sim = Simulation(robot, seed=seed)
        runs[key] = [sim.reset(robot.q0)] + [sim.step(robot.q0) for _ in range(10)]
    for first, second in zip(runs["a"], runs["b"]):
        np.testing.assert_array_equal(readings(first), readings(second))
    assert not np.allclose(readings(runs["a"][-1]), readings(runs["c"][-1]))
    np.testing.assert_array_equal(runs["a"][-1].q, runs["c"][-1].q)  # the truth has no noise
    # a reset walk replays the same readings
    sim = Simulation(robot, seed=3)
    sim.step(robot.q0)
    np.testing.assert_array_equal(readings(sim.reset(robot.q0)), readings(runs["a"][0]))


@pytest.mark.parametrize("name", ["bioloid-like", "g1", "talos"])
def test_ideal_readings_are_the_ground_truth(name):
    """Exact sensors read Pinocchio's angular velocity and specific force of the IMU frame,
    the joint angles, and each foot's contact wrench in its sole frame."""
    robot = get_robot(name)
    sim = Simulation(robot, sensors=SensorModel.ideal())
    rng = np.random.default_rng(0)
    frame = robot.frame_id("imu")
    for _ in range(20):
        state = sim.step(robot.q0[7:] + rng.normal(0.0, 0.05, robot.model.nq - 7))
    q, v = state.q, state.v
    a = robot.qvel_to_v(sim.data.qpos, sim.data.qacc)  # base part converted below
    a[0:3] = state.base_rotation.T @ sim.data.qacc[0:3] - np.cross(v[3:6], v[0:3])
    pin.forwardKinematics(robot.model, robot.data, q, v, a)
    rotation = pin.updateFramePlacement(robot.model, robot.data, frame).rotation
    gyro = pin.getFrameVelocity(robot.model, robot.data, frame, pin.LOCAL).angular
    acceleration = pin.getFrameClassicalAcceleration(robot.model, robot.data, frame, pin.LOCAL)
    specific_force = acceleration.linear - rotation.T @ robot.model.gravity.linear
    sensors = state.sensors
    assert sensors.time == state.time  # no latency
    # the IMU model at the last physics step is the frame's motion (measured: 3e-15 rad/s on
    # the gyro, 2e-14 m/s^2 on the accelerometer) ...
    instant = sim.ground_truth.imu_now(sim.data)
    np.testing.assert_allclose(instant[:3], gyro, rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(instant[3:], specific_force, rtol=0.0, atol=1e-12)
    # ... and the exact readings are its average over the control period (the IMU's filter)
    mean = sim.ground_truth.imu_mean
    assert mean is not None
    np.testing.assert_array_equal(sensors.imu.gyro, mean[:3])
    np.testing.assert_array_equal(sensors.imu.accelerometer, mean[3:])
    np.testing.assert_allclose(sensors.joint_positions, q[7:], rtol=0.0, atol=1e-12)
    for reading, foot, sole in zip(sensors.wrenches, state.oracle.feet, state.sole_rotations):
        np.testing.assert_allclose(sole @ reading.force, foot.force, rtol=0.0, atol=1e-9)
        np.testing.assert_allclose(sole @ reading.torque, foot.torque, rtol=0.0, atol=1e-9)


@pytest.mark.parametrize("name", ["bioloid-like", "g1"])
def test_force_torque_readings_in_the_sole_frame_give_back_the_contact_cop(name):
    """A 6-axis sensor at the sole origin: CoP = (-tau_y, tau_x) / f_z in the sole plane."""
    robot = get_robot(name)
    sim = Simulation(robot, sensors=SensorModel.ideal())
    errors = []
    for tick in range(60):
        state = sim.step(robot.q0)
        if tick < 50:  # settle into the contacts first
            continue
        for reading, foot, origin, rotation in zip(
            state.sensors.wrenches, state.oracle.feet, state.sole_positions, state.sole_rotations
        ):
            assert foot.in_contact
            fz, (tx, ty, _) = reading.force[2], reading.torque
            cop = origin + rotation @ np.array([-ty / fz, tx / fz, 0.0])
            errors.append(np.abs(cop - foot.cop)[:2].max())
    assert max(errors) < 1e-4  # [m] measured: 6.2e-5 (bioloid-like), 6.5e-5 (g1): the contact
    # points lie about 1 mm below the sole plane


def test_noise_statistics_match_the_model():
    """Over many readings the white noise has the model's standard deviations (10 %)."""
    truth = constant_truth(nb_joints=50)
    model = only(
        gyro_noise_density=2e-4,
        accelerometer_noise_density=2e-3,
        encoder_noise_std=1e-3,
        force_noise_std=0.5,
        torque_noise_std=0.02,
    )
    sensors = SensorSimulator(model, period=PERIOD, nb_joints=50, seed=1)
    sensors.reset(truth)
    samples = [sensors.read(truth) for _ in range(4000)]
    deviations = {
        "gyro": [s.imu.gyro - truth.imu.gyro for s in samples],
        "accelerometer": [s.imu.accelerometer - truth.imu.accelerometer for s in samples],
        "encoder": [s.joint_positions - truth.joint_positions for s in samples],
        "force": [s.left_wrench.force - truth.left_wrench.force for s in samples],
        "torque": [s.right_wrench.torque - truth.right_wrench.torque for s in samples],
    }
    expected = {
        "gyro": model.gyro_std(PERIOD),  # 2e-3 rad/s
        "accelerometer": model.accelerometer_std(PERIOD),  # 2e-2 m/s^2
        "encoder": model.encoder_noise_std,
        "force": model.force_noise_std,
        "torque": model.torque_noise_std,
    }
    for name, values in deviations.items():
        values = np.asarray(values)
        bound = 5.0 * expected[name] / math.sqrt(len(values))  # zero mean, 5 sigma
        assert np.abs(values.mean(axis=0)).max() < bound, name
        assert np.std(values) == pytest.approx(expected[name], rel=0.1), name  # measured <= 1.4 %


def test_biases_are_drawn_per_walk_and_random_walk():
    """The constant bias has the model's spread over walks; the random walk's spread grows
    as sqrt(time)."""
    truth = constant_truth()
    constant = only(gyro_bias_std=1e-3, accelerometer_bias_std=0.05)
    walking = only(gyro_bias_random_walk=2e-5, accelerometer_bias_random_walk=3e-3)
    biases, walked = [], []
    for seed in range(300):
        sensors = SensorSimulator(constant, period=PERIOD, nb_joints=4, seed=seed)
        first = sensors.reset(truth)
        biases.append(np.r_[first.imu.gyro - truth.imu.gyro, sensors.accelerometer_bias])
        np.testing.assert_array_equal(sensors.read(truth).imu.gyro, first.imu.gyro)  # constant
        sensors = SensorSimulator(walking, period=PERIOD, nb_joints=4, seed=seed)
        sensors.reset(truth)
        for _ in range(100):  # 1 s
            reading = sensors.read(truth)
        walked.append(np.r_[reading.imu.gyro - truth.imu.gyro, sensors.accelerometer_bias])
    biases, walked = np.asarray(biases), np.asarray(walked)
    assert np.std(biases[:, :3]) == pytest.approx(1e-3, rel=0.1)  # measured +1.9 %
    assert np.std(biases[:, 3:]) == pytest.approx(0.05, rel=0.1)  # measured +0.8 %
    # 101 readings (the reset's included) of 10 ms: sqrt(1.01 s)
    assert np.std(walked[:, :3]) == pytest.approx(2e-5 * math.sqrt(1.01), rel=0.1)  # +4.2 %
    assert np.std(walked[:, 3:]) == pytest.approx(3e-3 * math.sqrt(1.01), rel=0.1)  # +4.4 %


def test_encoders_are_quantised_to_the_resolution():
    resolution = math.radians(300.0 / 1024.0)  # AX-12
    truth = constant_truth(nb_joints=200)
    sensors = SensorSimulator(
        only(encoder_resolution=resolution), period=PERIOD, nb_joints=200, seed=0
    )
    encoders = sensors.reset(truth).joint_positions
    steps = encoders / resolution
    np.testing.assert_allclose(steps, np.round(steps), rtol=0.0, atol=1e-9)
    assert np.abs(encoders - truth.joint_positions).max() <= resolution / 2 + 1e-12
    assert np.min(np.diff(np.unique(encoders))) == pytest.approx(resolution)
    noisy = SensorSimulator(SensorModel.small_servo_humanoid(), period=PERIOD, nb_joints=200)
    steps = noisy.reset(truth).joint_positions / resolution
    np.testing.assert_allclose(steps, np.round(steps), rtol=0.0, atol=1e-9)


@pytest.mark.parametrize("latency", [1, 3])
def test_latency_delays_the_readings_by_whole_control_periods(latency):
    robot = get_robot("bioloid-like")
    model = SensorModel.for_robot(robot)
    immediate = Simulation(robot, sensors=model.with_latency(0), seed=2)
    delayed = Simulation(robot, sensors=model.with_latency(latency), seed=2)
    rng = np.random.default_rng(1)
    now = [immediate.reset(robot.q0)]
    late = [delayed.reset(robot.q0)]
    for _ in range(10):
        targets = robot.q0[7:] + rng.normal(0.0, 0.05, robot.model.nq - 7)
        now.append(immediate.step(targets))
        late.append(delayed.step(targets))
    for tick in range(len(now)):
        source = max(tick - latency, 0)  # before the latency has passed: the first reading
        assert late[tick].sensors.time == pytest.approx(now[source].time)
        np.testing.assert_array_equal(readings(late[tick]), readings(now[source]))
        np.testing.assert_array_equal(late[tick].q, now[tick].q)  # same world
    assert late[-1].sensors.time == pytest.approx(late[-1].time - latency * PERIOD)


def test_bad_simulator_arguments():
    with pytest.raises(ConfigurationError, match="period must be > 0 s"):
        SensorSimulator(SensorModel(), period=0.0, nb_joints=3)
