"""Robots: Pinocchio and MuJoCo built from one description agree; presets are right."""

import json
import re
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError, FrameNotFound, MpcwalkError, RobotNotFound
from mpcwalk.footsteps import LegLimits
from mpcwalk.robot import Robot, load_robot, robot_names
from mpcwalk.robot import loading as robots
from mpcwalk.robot.ground import FIELD_NAME
from mpcwalk.sim import make_mj_data

NAMES = robot_names()
TOLERANCE = 1e-9


def random_configuration(robot: Robot, rng: np.random.Generator) -> np.ndarray:
    """Random base pose and joint angles uniform within the joint limits."""
    q = np.empty(robot.model.nq)
    q[0:3] = rng.uniform(-1.0, 1.0, 3)
    quaternion = rng.normal(size=4)
    q[3:7] = quaternion / np.linalg.norm(quaternion)
    lower = np.clip(robot.model.lowerPositionLimit[7:], -np.pi, np.pi)
    upper = np.clip(robot.model.upperPositionLimit[7:], -np.pi, np.pi)
    q[7:] = rng.uniform(lower, upper)
    return q


def mujoco_at(robot: Robot, q: np.ndarray) -> mujoco.MjData:
    data = mujoco.MjData(robot.mj_model)
    data.qpos[:] = robot.q_to_qpos(q)
    mujoco.mj_forward(robot.mj_model, data)
    return data


def test_required_robots_are_available():
    assert {"bioloid-like", "atlas-like", "g1"} <= set(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_soles_frames_and_com_agree_for_random_configurations(name):
    robot = get_robot(name)
    rng = np.random.default_rng(42)
    body_frames = [
        f.name
        for f in robot.model.frames
        if f.type == pin.FrameType.BODY
        and mujoco.mj_name2id(robot.mj_model, mujoco.mjtObj.mjOBJ_BODY, f.name) >= 0
    ]
    assert len(body_frames) >= len(robot.joint_names)
    for _ in range(10):
        q = random_configuration(robot, rng)
        data = mujoco_at(robot, q)
        for frame in (*robot.foot_frames, robots.IMU_SITE):
            placement = robot.compute_frame_placement(q, frame)
            site = robot.mj_model.site(frame).id
            np.testing.assert_allclose(placement.translation, data.site_xpos[site], atol=TOLERANCE)
            np.testing.assert_allclose(
                placement.rotation, data.site_xmat[site].reshape(3, 3), atol=TOLERANCE
            )
        for frame in body_frames:
            body = robot.mj_model.body(frame).id
            placement = robot.compute_frame_placement(q, frame)
            np.testing.assert_allclose(placement.translation, data.xpos[body], atol=TOLERANCE)
        np.testing.assert_allclose(robot.compute_com(q), data.subtree_com[0], atol=TOLERANCE)


@pytest.mark.parametrize("name", NAMES)
def test_mass_matrix_and_gravity_agree(name):
    """Same inertias and armatures in both engines: M_pin = C^T M_mj C, g_pin = C^T g_mj."""
    robot = get_robot(name)
    model = robot.model
    q = random_configuration(robot, np.random.default_rng(7))
    data = mujoco_at(robot, q)
    mass_matrix = np.zeros((model.nv, model.nv))
    if hasattr(data, "qM"):  # MuJoCo 3
        mujoco.mj_fullM(robot.mj_model, mass_matrix, data.qM)
    else:  # MuJoCo 4
        mujoco.mj_fullM(robot.mj_model, data, mass_matrix)
    jacobian = np.array([robot.v_to_qvel(q, e) for e in np.eye(model.nv)]).T  # dqvel / dv
    pin_mass_matrix = pin.crba(model, robot.data, q)
    pin_mass_matrix = np.triu(pin_mass_matrix) + np.triu(pin_mass_matrix, 1).T
    np.testing.assert_allclose(jacobian.T @ mass_matrix @ jacobian, pin_mass_matrix, atol=1e-9)
    gravity = pin.computeGeneralizedGravity(model, robot.data, q)
    np.testing.assert_allclose(jacobian.T @ data.qfrc_bias, gravity, atol=1e-9)


@pytest.mark.parametrize("name", NAMES)
def test_total_mass_matches(name):
    robot = get_robot(name)
    assert robot.total_mass == pytest.approx(robot.mj_model.body_mass.sum(), abs=1e-9)


@pytest.mark.parametrize("name", NAMES)
def test_state_conversions_round_trip_and_match_site_velocities(name):
    robot = get_robot(name)
    rng = np.random.default_rng(3)
    q = random_configuration(robot, rng)
    v = rng.normal(size=robot.model.nv)
    np.testing.assert_allclose(robot.qpos_to_q(robot.q_to_qpos(q)), q, atol=1e-12)
    qvel = robot.v_to_qvel(q, v)
    np.testing.assert_allclose(robot.qvel_to_v(robot.q_to_qpos(q), qvel), v, atol=1e-12)
    data = mujoco_at(robot, q)
    data.qvel[:] = qvel
    mujoco.mj_forward(robot.mj_model, data)
    frame = robot.foot_frames[0]
    velocity = np.zeros(6)  # MuJoCo: (angular, linear) in the world frame, at the site
    mujoco.mj_objectVelocity(
        robot.mj_model, data, mujoco.mjtObj.mjOBJ_SITE, robot.mj_model.site(frame).id, velocity, 0
    )
    pin.forwardKinematics(robot.model, robot.data, q, v)
    expected = pin.getFrameVelocity(
        robot.model, robot.data, robot.frame_id(frame), pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    )
    np.testing.assert_allclose(velocity[3:], expected.linear, atol=1e-9)
    np.testing.assert_allclose(velocity[:3], expected.angular, atol=1e-9)


@pytest.mark.parametrize("name", NAMES)
def test_nominal_posture_stands_flat_on_the_soles(name):
    robot = get_robot(name)
    for placement, y_sign in zip(robot.compute_sole_placements(robot.q0), (1.0, -1.0)):
        assert placement.translation[2] == pytest.approx(0.0, abs=1e-9)
        np.testing.assert_allclose(placement.rotation, np.eye(3), atol=1e-9)
        assert np.sign(placement.translation[1]) == y_sign
    com = robot.compute_com(robot.q0)
    assert com[2] == pytest.approx(robot.com_height, abs=0.001)
    assert abs(com[0]) < 0.25 * robot.sole_size[0]  # CoM above the feet
    np.testing.assert_array_equal(robot.q_to_ctrl(robot.q0).shape, (robot.mj_model.nu,))


def test_look_alikes_match_their_published_figures():
    bioloid, atlas = get_robot("bioloid-like"), get_robot("atlas-like")
    assert len(bioloid.joint_names) == bioloid.mj_model.nu == 18
    assert len(atlas.joint_names) == atlas.mj_model.nu == 28
    assert bioloid.total_mass == pytest.approx(2.0, abs=0.1)
    assert atlas.total_mass == pytest.approx(150.0, abs=1.0)
    assert bioloid.compute_com(bioloid.q0)[2] == pytest.approx(0.23, abs=0.01)  # paper M
    assert bioloid.sole_size == (0.10, 0.06) and atlas.sole_size == (0.26, 0.13)
    np.testing.assert_allclose(bioloid.mj_model.actuator_forcerange[:, 1], 1.5)  # AX-12A
    for robot, height in ((bioloid, 0.41), (atlas, 1.88)):  # standing straight
        q = robot.q0.copy()
        q[7:] = 0.0
        data = mujoco_at(robot, q)
        boxes = np.flatnonzero(robot.mj_model.geom_type == mujoco.mjtGeom.mjGEOM_BOX)
        top = max(data.geom_xpos[g][2] + robot.mj_model.geom_size[g][2] for g in boxes)
        sole = data.site_xpos[robot.mj_model.site(robot.foot_frames[0]).id][2]
        assert top - sole == pytest.approx(height, abs=0.01)


@pytest.mark.parametrize("name", NAMES)
def test_only_the_feet_touch_the_floor(name):
    model = get_robot(name).mj_model
    colliding = {
        model.geom(g).name
        for g in range(model.ngeom)
        if model.geom_contype[g] or model.geom_conaffinity[g]
    }
    # the ground's height field lies on the floor, dormant: no geom's type matches its affinity
    assert colliding == {"floor", "left_sole_box", "right_sole_box", FIELD_NAME}
    field = model.geom(FIELD_NAME).id
    assert model.geom_contype[field] == 0
    assert not np.any(model.geom_contype & model.geom_conaffinity[field])
    for sensor in (
        "imu_gyro",
        "imu_accelerometer",
        "imu_orientation",
        "left_foot_force",
        "right_foot_torque",
        "left_foot_touch",
        "right_foot_touch",
    ):
        assert model.sensor(sensor).id >= 0


@pytest.mark.parametrize("name", NAMES)
def test_stands_one_second_under_position_control(name):
    robot = get_robot(name)
    data = make_mj_data(robot)
    height = data.qpos[2]
    while data.time < 1.0:
        mujoco.mj_step(robot.mj_model, data)
    assert data.qpos[2] == pytest.approx(height, rel=0.05)
    tilt = 2.0 * np.arccos(min(1.0, abs(data.qpos[3])))
    assert tilt < np.radians(5.0)
    support = data.sensor("left_foot_touch").data[0] + data.sensor("right_foot_touch").data[0]
    assert support == pytest.approx(robot.total_mass * 9.81, rel=0.05)


def test_g1_with_meshes_has_the_same_kinematics():
    with_meshes, without = load_robot("g1"), get_robot("g1")
    assert with_meshes.mj_model.nmesh > 0 and without.mj_model.nmesh == 0
    q = random_configuration(without, np.random.default_rng(1))
    np.testing.assert_allclose(
        mujoco_at(with_meshes, q).site_xpos, mujoco_at(without, q).site_xpos, atol=1e-12
    )


def test_unknown_robot_lists_the_available_ones():
    with pytest.raises(RobotNotFound, match=r"Unknown robot 'nao'.*bioloid-like") as error:
        load_robot("nao")
    assert isinstance(error.value, MpcwalkError) and "g1" in error.value.available


def test_missing_frame_lists_the_existing_ones():
    robot = get_robot("bioloid-like")
    with pytest.raises(FrameNotFound, match=r"Frame 'nose' not found.*left_sole") as error:
        robot.compute_frame_placement(robot.q0, "nose")
    assert "right_sole" in error.value.available


def _patched_preset(monkeypatch, tmp_path, source: str, old: str, new: str) -> str:
    text = (robots.PRESETS_DIR / source).read_text()
    assert old in text
    (tmp_path / source).write_text(text.replace(old, new))
    monkeypatch.setattr(robots, "PRESETS_DIR", tmp_path)
    return re.search(r'^name = "([^"]+)"', text, re.MULTILINE).group(1)


def test_preset_with_a_missing_sole_site_raises_frame_not_found(monkeypatch, tmp_path):
    name = _patched_preset(
        monkeypatch, tmp_path, "bioloid_like.toml", 'left = "left_sole"', 'left = "left_toe"'
    )
    with pytest.raises(FrameNotFound, match=r"'left_toe'.*right_sole"):
        load_robot(name)


def test_preset_with_a_missing_foot_link_raises_frame_not_found(monkeypatch, tmp_path):
    name = _patched_preset(
        monkeypatch, tmp_path, "g1.toml", 'left = "left_ankle_roll_link"', 'left = "left_toe_link"'
    )
    with pytest.raises(FrameNotFound, match=r"'left_toe_link'.*right_ankle_roll_link"):
        load_robot(name, visual=False)


def test_preset_errors_are_configuration_errors(monkeypatch, tmp_path):
    name = _patched_preset(
        monkeypatch, tmp_path, "bioloid_like.toml", "left_knee = 0.76", "left_kneee = 0.76"
    )
    with pytest.raises(ConfigurationError, match=r"joint 'left_kneee'.*left_knee"):
        load_robot(name)
    (tmp_path / "broken.toml").write_text('name = "broken"\nformat = "mjcf"\n')
    with pytest.raises(ConfigurationError, match=r"broken.toml is malformed"):
        load_robot("broken")


def test_unknown_gait_key_is_refused_with_the_valid_names(monkeypatch, tmp_path):
    name = _patched_preset(
        monkeypatch, tmp_path, "bioloid_like.toml", "step_height = 0.04", "step_heigth = 0.04"
    )
    with pytest.raises(ConfigurationError, match=r"unknown \[gait\] key\(s\) step_heigth") as error:
        load_robot(name)
    assert "bioloid_like.toml" in str(error.value)
    assert "valid keys: step_duration, double_support_ratio, step_height" in str(error.value)


@pytest.mark.parametrize("name", NAMES)
def test_leg_limits_and_initial_feet_come_from_the_preset_and_the_nominal_posture(name):
    """The values the walk runner computed before they were the robot's: the ``[gait]``
    limits, the half stance width of ``q0`` where the preset has none, and y_sep at most it."""
    robot = get_robot(name)
    left, right = robot.compute_sole_placements(robot.q0)
    half_width = 0.5 * float(np.linalg.norm(left.translation[:2] - right.translation[:2]))
    keys = [f for f in LegLimits.__dataclass_fields__ if getattr(robot.gait, f) is not None]
    values = {"half_stance_width": half_width, **{k: getattr(robot.gait, k) for k in keys}}
    values.setdefault("y_sep", min(LegLimits().y_sep, values["half_stance_width"]))
    assert robot.leg_limits == LegLimits(**values)
    feet = robot.initial_feet()
    for foot, sole in zip(feet, (left, right)):
        np.testing.assert_array_equal(foot.position, sole.translation)
        assert foot.yaw == np.arctan2(sole.rotation[1, 0], sole.rotation[0, 0])
    assert robot.gait is robot.preset.gait


def test_importing_robots_loads_no_mujoco():
    import subprocess
    import sys

    code = "import sys, mpcwalk.robot; print('mujoco' in sys.modules)"
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    assert result.stdout.strip() == "False"


def _user_preset(folder, name: str = "my-biped") -> Path:
    """A user's robot outside the repository: a shipped MJCF copied under a new name, and a
    preset file beside it naming it."""
    description = folder / "my_biped.xml"
    description.write_text((robots.ROBOTS_DIR / "bioloid_like.xml").read_text())
    text = (robots.PRESETS_DIR / "bioloid_like.toml").read_text()
    text = text.replace('name = "bioloid-like"', f'name = "{name}"')
    text = text.replace('description = "bioloid_like.xml"', 'description = "my_biped.xml"')
    preset = folder / "my_biped.toml"
    preset.write_text(text)
    return preset


def test_a_user_preset_outside_the_repository_loads_and_walks(tmp_path):
    from mpcwalk.cli import main as cli_main

    preset = _user_preset(tmp_path)
    robot = load_robot(preset)
    assert robot.name == "my-biped" and robot.description_path == tmp_path / "my_biped.xml"
    assert load_robot(str(preset)).total_mass == pytest.approx(robot.total_mass)
    out = tmp_path / "out"
    code = cli_main(["walk", "--robot", str(preset), "--duration", "1", "--out", str(out)])
    assert code == 0
    metrics = json.loads((out / "metrics.json").read_text())
    assert not metrics["fell"] and metrics["steps_completed"] == metrics["steps_planned"]


def test_a_user_preset_whose_description_is_missing_is_refused(tmp_path):
    preset = _user_preset(tmp_path)
    (tmp_path / "my_biped.xml").unlink()
    with pytest.raises(RobotNotFound, match=r"my_biped.xml"):
        load_robot(preset)
    with pytest.raises(RobotNotFound, match=r"is not found"):
        load_robot(tmp_path / "nowhere.toml")
