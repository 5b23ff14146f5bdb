"""MuJoCo simulation: standing, contact wrenches and CoP, CoM, the oracle, pushes, falls, video."""

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from mpcwalk.estimation import EstimatedState
from mpcwalk.exceptions import (
    ConfigurationError,
    PushFormatError,
    RenderingUnavailable,
    SimulationUnstable,
    VideoDependencyMissing,
)
from mpcwalk.models.support_polygon import SupportPolygon, foot_rectangle
from mpcwalk.robot import SensorReadings, robot_names
from mpcwalk.sim import (
    ExternalForce,
    FallDetector,
    SensorModel,
    Simulation,
    VideoRecorder,
    parse_push,
    quaternion_to_rpy,
    rendering,
)

NAMES = robot_names()
MAIN_ROBOTS = [name for name in ("bioloid-like", "atlas-like", "g1") if name in NAMES]


def weight(robot) -> float:
    return robot.total_mass * float(np.linalg.norm(robot.model.gravity.linear))


def support_polygon(state, robot) -> SupportPolygon:
    """Convex hull of both soles at their measured poses."""
    feet = [
        foot_rectangle(position, yaw, *robot.sole_size)
        for position, yaw in zip(state.sole_positions, state.sole_yaws)
    ]
    return SupportPolygon.union_hull(feet)


def cop_from_newton_euler(robot, sim, state, force, point):
    """Contact force and CoP implied by the whole-body dynamics (Pinocchio) at ``state``.

    Linear momentum: f = m c_ddot - F - m g. Angular momentum about the CoM gives the contact
    moment; the CoP is the point of the contact plane where its horizontal part vanishes.
    """
    q, v, data = state.q, state.v, sim.data
    a = robot.qvel_to_v(data.qpos, data.qacc)  # joint part; base part converted below
    a[0:3] = state.base_rotation.T @ data.qacc[0:3] - np.cross(v[3:6], v[0:3])
    dh = pin.computeCentroidalMomentumTimeVariation(robot.model, robot.data, q, v, a)
    com = robot.data.com[0]
    f = dh.linear - force - robot.total_mass * robot.model.gravity.linear
    moment = dh.angular - np.cross(point - com, force)
    height = com[2] - state.oracle.cop[2]
    cop_x = com[0] - (moment[1] + height * f[0]) / f[2]
    cop_y = com[1] + (moment[0] - height * f[1]) / f[2]
    return f, np.array([cop_x, cop_y])


@pytest.mark.parametrize("name", NAMES)
def test_robot_stands_with_cop_inside_both_feet_and_weight_on_the_soles(name):
    robot = get_robot(name)
    sim = Simulation(robot)
    detector = FallDetector(robot.q0[2])
    margins = []
    for _ in range(100):  # 1 s
        state = sim.step(robot.q0)
        truth = state.oracle
        assert truth.has_cop
        margins.append(support_polygon(state, robot).signed_distance(truth.cop[:2]))
        assert not detector.check(state).fell
    assert state.time == pytest.approx(1.0)
    assert min(margins) > 0.005  # [m] CoP inside the support polygon at every tick
    assert truth.left_foot.in_contact and truth.right_foot.in_contact
    total = truth.left_foot.normal_force + truth.right_foot.normal_force
    assert total == pytest.approx(weight(robot), rel=0.02)
    # the overall CoP is the force-weighted mean of the feet's CoPs (eq. 31 on all points)
    feet = truth.feet
    mean = sum(f.normal_force * f.cop for f in feet) / sum(f.normal_force for f in feet)
    np.testing.assert_allclose(truth.cop, mean, atol=1e-12)
    for side, foot in enumerate(feet):
        assert foot_rectangle(
            state.sole_positions[side], state.sole_yaws[side], *robot.sole_size
        ).contains(foot.cop[:2])
        # what a 6-axis sensor at the sole origin would compute from the wrench
        origin, (tau_x, tau_y, _) = state.sole_positions[side], foot.torque
        cop_from_wrench = origin[:2] + np.array([-tau_y, tau_x]) / foot.normal_force
        np.testing.assert_allclose(foot.cop[:2], cop_from_wrench, atol=1e-4)


@pytest.mark.parametrize("name", NAMES)
def test_com_and_its_velocity_match_pinocchio(name):
    robot = get_robot(name)
    sim = Simulation(robot)
    rng = np.random.default_rng(7)
    for _ in range(3):
        q = robot.q0.copy()
        q[0:3] += rng.uniform(-0.2, 0.2, 3)
        q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(*rng.uniform(-0.3, 0.3, 3))).coeffs()
        q[7:] += rng.uniform(-0.3, 0.3, robot.model.nq - 7)
        v = rng.normal(size=robot.model.nv)
        state = sim.reset(q, v=v)
        np.testing.assert_allclose(state.q, q, atol=1e-12)
        np.testing.assert_allclose(state.v, v, atol=1e-12)
        pin.centerOfMass(robot.model, robot.data, q, v)
        np.testing.assert_allclose(state.oracle.com, robot.data.com[0], atol=1e-9)
        np.testing.assert_allclose(state.oracle.com_velocity, robot.data.vcom[0], atol=1e-9)
    sim.reset()
    for _ in range(20):
        state = sim.step()
    np.testing.assert_allclose(state.oracle.com, robot.compute_com(state.q), atol=1e-9)


@pytest.mark.parametrize("name", MAIN_ROBOTS)
def test_contact_wrench_and_cop_obey_newton_euler_during_a_push(name):
    """Forces and CoP from the contacts = those the whole-body dynamics require."""
    robot = get_robot(name)
    force = np.array([0.02, 0.05, 0.0]) * weight(robot)
    offset = np.array([0.0, 0.0, 0.05])  # [m] above the torso frame origin
    sim = Simulation(robot, pushes=[ExternalForce(0.0, 10.0, force, point=offset)])
    torso = sim.model.body(robot.torso_frame).id
    for tick in range(30):
        state = sim.step()
        if tick % 10 == 9:
            point = sim.data.xpos[torso] + sim.data.xmat[torso].reshape(3, 3) @ offset
            f, cop = cop_from_newton_euler(robot, sim, state, force, point)
            np.testing.assert_allclose(state.oracle.total_force, f, atol=1e-6 * weight(robot))
            np.testing.assert_allclose(state.oracle.cop[:2], cop, atol=2e-4)


@pytest.mark.parametrize("name", MAIN_ROBOTS)
def test_lateral_force_shifts_the_cop_towards_the_push(name):
    robot = get_robot(name)
    shifts = {}
    for sign in (-1.0, 0.0, 1.0):
        force = [0.0, sign * 0.05 * weight(robot), 0.0]
        sim = Simulation(robot, pushes=[ExternalForce(0.0, 5.0, force)])
        cops = [sim.step().oracle.cop[1] for _ in range(100)]
        shifts[sign] = np.mean(cops[50:])  # mean over [0.5, 1] s: sways average out
    assert shifts[1.0] - shifts[0.0] > 0.01
    assert shifts[-1.0] - shifts[0.0] < -0.01


def test_cop_under_a_steady_push_matches_the_static_moment_balance():
    """At rest: m g (c_y - p_y) + F_y (h - p_z) = 0, h the height where F acts."""
    robot = get_robot("bioloid-like")
    force = 0.05 * weight(robot)
    sim = Simulation(robot, pushes=[ExternalForce(0.0, 10.0, [0.0, force, 0.0])])
    for _ in range(300):
        state = sim.step()
    truth = state.oracle
    height = sim.data.xipos[sim.model.body(robot.torso_frame).id][2] - truth.cop[2]
    expected = truth.com[1] + force * height / truth.total_force[2]
    assert truth.cop[1] == pytest.approx(expected, abs=5e-4)
    assert truth.total_force[1] == pytest.approx(-force, rel=0.02)


@pytest.mark.parametrize("name", MAIN_ROBOTS)
def test_large_push_triggers_the_fall_detector(name):
    robot = get_robot(name)
    detector = FallDetector.for_robot(robot)
    sim = Simulation(
        robot, pushes=[ExternalForce(0.2, 0.3, [0.0, 0.5 * weight(robot), 0.0], body="base")]
    )
    status = None
    for _ in range(200):
        status = detector.check(sim.step())
        if status.fell:
            break
    assert status.fell and status.time > 0.2
    assert "tilt" in status.reason or "height" in status.reason


def test_no_contact_in_the_air_leaves_the_cop_undefined():
    robot = get_robot("g1")
    lifted = robot.q0.copy()
    lifted[2] += 0.3
    truth = Simulation(robot).reset(lifted).oracle
    assert not truth.has_cop and np.all(np.isnan(truth.cop))
    for foot in truth.feet:
        assert not foot.in_contact and np.all(np.isnan(foot.cop))
        np.testing.assert_array_equal(foot.force, np.zeros(3))


def test_fall_detector_reasons_and_thresholds():
    robot = get_robot("bioloid-like")
    sim = Simulation(robot)
    detector = FallDetector(robot.q0[2], min_base_height_ratio=0.5, max_tilt_deg=45.0)
    assert not detector.check(sim.state())
    low = robot.q0.copy()
    low[2] = 0.4 * robot.q0[2]
    status = detector.check(sim.reset(low))
    assert status.fell and status.reason.startswith("base height") and status.time == 0.0
    tilted = robot.q0.copy()
    tilted[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(0.0, np.radians(50.0), 0.0)).coeffs()
    status = detector.check(sim.reset(tilted))
    assert status.fell and "tilt 50.0 deg" in status.reason
    with pytest.raises(ConfigurationError, match="min_base_height_ratio"):
        FallDetector(0.3, min_base_height_ratio=1.5)


def test_push_string_parser():
    push = parse_push(" 3.0, 0.05, 10, 5, 0 ")
    assert (push.start, push.duration, push.body) == (3.0, 0.05, "torso")
    np.testing.assert_array_equal(push.force, [10.0, 5.0, 0.0])
    bad = {
        "3.0,0.05,10,5": "4 comma-separated fields instead of 5",
        "3.0,0.05,10,five,0": "field FY is 'five', not a number",
        "3.0,nan,10,5,0": "field DURATION is 'nan', not a finite number",
        "-1,0.05,10,5,0": "start time T = -1 s is negative",
        "3.0,0,10,5,0": "DURATION = 0 s is not positive",
    }
    for text, problem in bad.items():
        with pytest.raises(PushFormatError, match="Expected 'T,DURATION,FX,FY,FZ'") as error:
            parse_push(text)
        assert problem in str(error.value) and error.value.text == text


def test_external_force_window_and_bad_bodies():
    push = ExternalForce(0.1, 0.05, [1.0, 0.0, 0.0])
    active = [push.is_active(k * 0.002) for k in range(200)]
    assert sum(active) == 25 and active.index(True) == 50
    with pytest.raises(ConfigurationError, match="duration must be > 0"):
        ExternalForce(0.0, -1.0, [1.0, 0.0, 0.0])
    with pytest.raises(ConfigurationError, match="force must be 3 finite numbers"):
        ExternalForce(0.0, 1.0, [1.0, 0.0])
    with pytest.raises(ConfigurationError, match="'nose', which the robot does not have"):
        Simulation(get_robot("bioloid-like"), pushes=[ExternalForce(0, 1, [1, 0, 0], "nose")])


def test_step_targets_periods_and_settling():
    robot = get_robot("bioloid-like")
    sim = Simulation(robot, timestep=0.001, control_period=0.005)
    assert sim.nb_substeps == 5 and robot.mj_model.opt.timestep == 0.002
    targets = robot.q0[7:] + 0.1
    sim.step(targets)
    np.testing.assert_array_equal(sim.data.ctrl, robot.q_to_ctrl(np.r_[robot.q0[:7], targets]))
    assert sim.time == pytest.approx(0.005)
    with pytest.raises(ConfigurationError, match=f"{robot.model.nq - 7} joint angles"):
        sim.step(np.zeros(3))
    with pytest.raises(ConfigurationError, match="must be finite"):
        sim.step(np.full(robot.model.nq - 7, np.nan))
    with pytest.raises(ConfigurationError, match="not a multiple of the physics time step"):
        Simulation(robot, control_period=0.003)
    state = sim.reset(settle=0.2)
    assert state.time == 0.0 and state.base_position[2] < robot.q0[2]


def test_diverging_simulation_is_reported_not_silently_reset(monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)  # MuJoCo writes its warning to MUJOCO_LOG.TXT in the cwd
    sim = Simulation(get_robot("bioloid-like"))
    sim.step()
    sim.data.qvel[:] = 1e12
    with pytest.raises(SimulationUnstable, match="diverged at t = 0.020 s"):
        sim.step()


def test_oracle_imu_and_euler_angles_of_a_standing_robot():
    robot = get_robot("g1")
    sim = Simulation(robot, sensors=SensorModel.ideal())
    for _ in range(50):
        state = sim.step()
    truth = state.oracle
    assert np.linalg.norm(truth.imu.accelerometer) == pytest.approx(9.81, rel=0.01)
    assert abs(truth.roll) < 0.05 and abs(truth.pitch) < 0.05
    rpy = pin.rpy.matrixToRpy(state.base_rotation)
    np.testing.assert_allclose((truth.roll, truth.pitch, truth.yaw), rpy, atol=1e-12)
    np.testing.assert_array_equal(truth.com_state().position, truth.com[:2])
    omega = np.sqrt(9.81 / robot.com_height)
    np.testing.assert_allclose(truth.dcm, truth.com[:2] + truth.com_velocity[:2] / omega)


def test_the_oracle_is_the_controllers_state_type_and_the_sensors_are_raw_readings():
    """The oracle is an EstimatedState (source "oracle") of the ground truth; the sensor
    readings carry no state (no CoM, no pose): the estimator must build it."""
    robot = get_robot("bioloid-like")
    state = Simulation(robot).step()
    oracle = state.oracle
    assert isinstance(oracle, EstimatedState) and oracle.source == "oracle"
    assert oracle.time == state.time
    np.testing.assert_array_equal(oracle.sole_positions, state.sole_positions)
    np.testing.assert_array_equal(oracle.sole_yaws, state.sole_yaws)
    np.testing.assert_array_equal(oracle.q, state.q)
    np.testing.assert_array_equal(oracle.joint_velocities, state.v[6:])
    np.testing.assert_allclose(
        oracle.base_linear_velocity, state.base_rotation @ state.v[:3], rtol=0.0, atol=1e-15
    )
    assert oracle.sole_rotations.shape == (2, 3, 3) and not oracle.sole_positions.flags.writeable
    assert isinstance(state.sensors, SensorReadings)
    assert not {"com", "q", "sole_positions", "cop"} & set(vars(state.sensors))


def test_contact_wrenches_decoded_at_once_equal_mujocos_contact_force():
    robot = get_robot("g1")
    sim = Simulation(robot, pushes=[ExternalForce(0.0, 1.0, [30.0, 20.0, 0.0])])
    rng = np.random.default_rng(5)
    for _ in range(20):
        sim.step(robot.q0[7:] + rng.normal(0.0, 0.03, robot.model.nq - 7))
    index = np.arange(sim.data.ncon)
    assert len(index) >= 4  # measured: 5 contacts
    expected = np.zeros((len(index), 6))
    for row, i in enumerate(index):
        mujoco.mj_contactForce(sim.model, sim.data, int(i), expected[row])
    decoded = sim.contacts._contact_wrenches(sim.model, sim.data, index)
    np.testing.assert_allclose(decoded, expected, rtol=0.0, atol=1e-12)  # measured: 0.0


def test_quaternion_to_rpy_matches_pinocchio():
    rng = np.random.default_rng(3)
    for _ in range(20):
        rpy = rng.uniform([-3.0, -1.5, -3.0], [3.0, 1.5, 3.0])
        quaternion = pin.Quaternion(pin.rpy.rpyToMatrix(*rpy))
        wxyz = np.r_[quaternion.w, quaternion.x, quaternion.y, quaternion.z]
        np.testing.assert_allclose(quaternion_to_rpy(wxyz), rpy, atol=1e-9)


def test_video_of_a_few_frames(tmp_path):
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg", reason="imageio-ffmpeg not installed")
    robot = get_robot("bioloid-like")
    sim = Simulation(robot)
    path = tmp_path / "walk.mp4"
    try:
        recorder = VideoRecorder(path, sim.model, fps=50.0, width=160, height=120)
    except RenderingUnavailable as error:
        pytest.skip(f"no headless OpenGL backend (EGL/OSMesa) on this machine: {error}")
    with recorder:
        recorder.capture(sim.data, sim.time)
        for _ in range(10):  # 0.1 s at 50 fps: frames at 0, 0.02, ..., 0.1 s
            sim.step()
            recorder.capture(sim.data, sim.time)
        image = recorder.render(sim.data)
    assert recorder.nb_frames == 6
    assert image.shape == (120, 160, 3) and image.std() > 5.0  # not a blank frame
    reader = imageio_ffmpeg.read_frames(str(path))
    meta = next(reader)
    assert tuple(meta["size"]) == (160, 120) and meta["fps"] == pytest.approx(50.0)
    assert sum(1 for _ in reader) == 6
    with pytest.raises(ConfigurationError, match="even positive size"):
        VideoRecorder(tmp_path / "odd.mp4", sim.model, width=161)
    assert issubclass(VideoDependencyMissing, ImportError)


def test_missing_gl_backend_raises_a_named_error_saying_how_to_enable_one(monkeypatch, tmp_path):
    pytest.importorskip("imageio_ffmpeg", reason="imageio-ffmpeg not installed")
    monkeypatch.setenv("MUJOCO_GL", "osmesa")  # force a backend that cannot load here
    monkeypatch.setenv("PYOPENGL_PLATFORM", "egl")  # ... without touching PyOpenGL
    rendering._context_class.cache_clear()
    try:
        with pytest.raises(RenderingUnavailable, match="osmesa: ImportError") as error:
            VideoRecorder(tmp_path / "none.mp4", get_robot("bioloid-like").mj_model)
        assert "libosmesa6" in str(error.value) and "without --video" in str(error.value)
    finally:
        rendering._context_class.cache_clear()
