"""The simulated ground: tilted (gravity turned into the slope's frame) and rough (MuJoCo
height field), from `run_walk` and `mpcwalk walk`."""

import json
import math

import mujoco
import numpy as np
import pytest
from conftest import get_robot, walk

from mpcwalk.cli import main as cli_main
from mpcwalk.control.stabilizers.balance import make_balance
from mpcwalk.control.stabilizers.balance_options import BalanceOptions
from mpcwalk.estimation.estimator import Estimator
from mpcwalk.estimation.gravity_tilt import GravityTilt
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.ground import FIELD_NAME, Ground, clear_radius
from mpcwalk.sim import Simulation
from mpcwalk.walking.specification import read_spec


def test_bad_grounds_are_named():
    with pytest.raises(ConfigurationError, match="tilt"):
        Ground(tilt=30.0)
    with pytest.raises(ConfigurationError, match="roughness"):
        Ground(roughness=-0.01)
    with pytest.raises(ConfigurationError, match="seed"):
        Ground(seed=-1)


def test_a_tilt_turns_gravity_and_the_imu_reads_it():
    robot = get_robot("bioloid-like")
    ground = Ground(tilt=5.0, tilt_direction=90.0)
    simulation = Simulation(robot, ground=ground)
    g = simulation.model.opt.gravity
    assert np.linalg.norm(g) == pytest.approx(9.81)
    assert math.degrees(math.atan2(-g[1], -g[2])) == pytest.approx(5.0)  # downhill: -y
    assert g[0] == pytest.approx(0.0, abs=1e-12)
    state = simulation.reset(robot.q0)
    for _ in range(20):
        state = simulation.step(robot.q0[7:])
    accelerometer = state.sensors.imu.accelerometer  # specific force, IMU frame
    assert abs(accelerometer[1]) > 0.5  # about g sin(5 deg) = 0.85 m/s^2 sideways


def test_a_rough_ground_has_bumps_beyond_the_start_and_the_same_seed_the_same_bumps():
    robot = get_robot("bioloid-like")
    ground = Ground(roughness=0.01, seed=3)
    heights = ground.heights(clear_radius(robot))
    assert 0.0 <= heights.min() and heights.max() <= 0.01 + 1e-12
    assert heights.max() > 0.008
    centre = heights.shape[0] // 2
    assert heights[centre, centre] == 0.0  # the initial stance stays flat
    assert np.array_equal(heights, Ground(roughness=0.01, seed=3).heights(clear_radius(robot)))
    assert not np.array_equal(heights, Ground(roughness=0.01, seed=4).heights(clear_radius(robot)))
    simulation = Simulation(robot, ground=ground)
    geom = mujoco.mj_name2id(simulation.model, mujoco.mjtObj.mjOBJ_GEOM, FIELD_NAME)
    assert simulation.model.geom_conaffinity[geom] == 1  # the soles touch it
    flat = Simulation(robot)
    assert flat.model.geom_conaffinity[geom] != 1  # dormant on the level floor


@pytest.mark.slow
def test_mpc_walks_up_a_slope_and_over_bumps_from_the_command_line(tmp_path):
    out = tmp_path / "walk"
    code = cli_main(
        [
            "walk",
            "--robot",
            "bioloid-like",
            "--controller",
            "mpc",
            "--vx",
            "0.1",
            "--steps",
            "4",
            "--ground-tilt",
            "3",
            "--ground-roughness",
            "0.004",
            "--out",
            str(out),
            "--no-progress",
        ]
    )
    metrics = json.loads((out / "metrics.json").read_text())
    assert code == 0 and not metrics["fell"]
    world = metrics["config"]["model_mismatch"]
    assert world["ground_tilt_deg"] == 3.0 and world["ground_roughness_m"] == 0.004
    ground = read_spec(out / "spec.toml").world  # the ground, to walk on it again
    assert (ground.ground_tilt, ground.ground_roughness) == (3.0, 0.004)


@pytest.mark.parametrize("tilt", [0.0, 4.0])
def test_the_estimator_reads_gravity_s_tilt_under_a_robot_standing_on_it(tilt):
    """The soles set the estimator's world (the ground's); gravity's tilt in it is read
    from the accelerometer: exactly zero on the level floor (within its deadband), the
    ground's slope towards its uphill azimuth on a tilted one, as the ground truth gives it."""
    robot = get_robot("bioloid-like")
    simulation = Simulation(robot, ground=Ground(tilt=tilt, tilt_direction=60.0), seed=0)
    state = simulation.reset(robot.q0)
    estimator = Estimator(robot, control_period=simulation.control_period)
    estimate = estimator.reset(state.sensors, robot.q0)
    for _ in range(200):  # 2 s: the average of 0.2 to 0.5 s, then the smoothing
        state = simulation.step(robot.q0[7:])
        estimate = estimator.update(state.sensors)
    uphill = math.tan(math.radians(tilt)) * np.array([0.5, math.sqrt(3.0) / 2.0])
    assert state.oracle.ground_tilt == pytest.approx(uphill, abs=1e-12)  # the ground truth
    if tilt == 0.0:
        assert np.array_equal(estimate.ground_tilt, np.zeros(2))
    else:
        # 5 % off with this seed; 5 to 18 % over the sensor noise of seeds 0 to 7
        assert np.linalg.norm(estimate.ground_tilt - uphill) < 0.2 * np.linalg.norm(uphill)


@pytest.mark.slow
def test_g1_walks_on_a_ground_tilted_4_deg_leaning_into_gravity():
    """The robustness matrix's world where g1 stopped after 2 of its 9 steps: its ZMP lay
    4.8 cm downhill of its CoM, past its 3.5 cm half sole. The balance stabilizer keeps the
    CoM z_c tan(theta) uphill of the plan (BalanceOptions.ground_tilt), from the tilt the
    estimator reads."""
    metrics = walk(
        "g1",
        "mpc",
        command=(0.1, 0.0, 0.0),
        nb_steps=8,
        seed=126,
        ground_tilt=3.9745,
        ground_tilt_direction=51.6,
    ).metrics
    assert not metrics.fell and not metrics.stop_reason
    assert metrics.steps_completed == metrics.steps_planned == 9
    assert metrics.foot_position_error_cm_mean < 5.0  # measured 2.35 cm


def test_balance_options_come_from_a_walk_specification_table():
    stabilizer = make_balance({"ground_tilt": False, "integral_gain": 1.0}, "mpc")
    assert stabilizer is not None and stabilizer.options.ground_tilt is False
    assert stabilizer.options.integral_gain == 1.0
    with pytest.raises(ConfigurationError, match="no option 'tilt'.*ground_tilt"):
        make_balance({"tilt": True}, "mpc")
    with pytest.raises(ConfigurationError, match="ground_tilt must be True or False"):
        BalanceOptions(ground_tilt=1)


def test_gravity_tilt_options_are_checked_and_a_level_start_stays_exactly_level():
    with pytest.raises(ConfigurationError, match="tilt_time_constant"):
        GravityTilt(time_constant=0.0)
    with pytest.raises(ConfigurationError, match="tilt_deadband_deg"):
        GravityTilt(deadband_deg=25.0)
    tilt = GravityTilt()
    up, still, normals = np.array([0.1, 0.0, 9.81]), np.zeros(3), np.tile([0.0, 0.0, 1.0], (2, 1))
    for _ in range(100):  # 0.6 deg of tilt (an accelerometer bias): under the deadband
        tilt.update(up, still, normals, np.array([0.5, 0.5]), 1.0, True, 0.01)
    assert tilt.value is None and tilt.raw[0] == pytest.approx(0.1 / 9.81)


def test_gravity_as_read_is_vertical_on_a_level_floor_and_downhill_on_a_slope():
    # the estimator predicts the base's acceleration with it: on a slope, gravity less only
    # its vertical part left g tan(theta) of horizontal acceleration in the prediction
    level, tilted = GravityTilt(), GravityTilt()
    normals = np.tile([0.0, 0.0, 1.0], (2, 1))
    for _ in range(300):  # 3 s standing: the start's average, then the smoothing
        level.update(np.array([0.1, 0.0, 9.81]), np.zeros(3), normals, np.ones(2), 1.0, True, 0.01)
        tilted.update(np.array([0.6, 0.0, 9.79]), np.zeros(3), normals, np.ones(2), 1.0, True, 0.01)
    assert np.array_equal(level.gravity(9.81), [0.0, 0.0, -9.81])  # within the deadband
    t = tilted.value
    assert t is not None and t[0] == pytest.approx(0.6 / 9.79, rel=1e-3)  # 3.5 deg uphill +x
    g = tilted.gravity(9.81)
    assert np.linalg.norm(g) == pytest.approx(9.81, rel=1e-12)
    assert g[:2] / g[2] == pytest.approx(t, rel=1e-12)  # the tilt it reads: g_xy / g_z
    assert g[0] < 0.0  # downhill
