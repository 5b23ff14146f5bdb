"""A preset's [base] and [joints] tables on a description written into a folder of its own:
g1 turned backwards (or sideways) in its URDF loads as g1 with forward = "-x" (or "y")."""

import math
import re

import numpy as np
import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.base_orientation import base_rotation, reorient_urdf_root
from mpcwalk.robot.loading import PRESETS_DIR, load_robot, robot_names
from mpcwalk.walking.robot_check import check_engines, check_posture

pytestmark = pytest.mark.skipif("g1" not in robot_names(), reason="example-robot-data missing")


def _turned_g1(folder, turn: float, base: str = "", joints: str = "") -> str:
    """Preset file of g1 whose URDF has a new root link ``turned``, the pelvis fixed to it
    turned by ``turn`` [rad] about z: the pelvis' x axis (forward) is ``Rz(turn) x`` in the
    description's root frame."""
    robot = get_robot("g1")
    text = robot.description_path.read_text()
    turned = (
        '<link name="turned"/>\n<joint name="turned_to_pelvis" type="fixed">'
        '<parent link="turned"/><child link="pelvis"/>'
        f'<origin xyz="0 0 0" rpy="0 0 {turn!r}"/></joint>\n'
    )
    text = re.sub(r"(<robot\b[^>]*>)", lambda m: m.group(1) + "\n" + turned, text, count=1)
    (folder / "g1_turned.urdf").write_text(text)
    preset = (PRESETS_DIR / "g1.toml").read_text()
    preset = re.sub(r"^description = .*$", 'description = "g1_turned.urdf"', preset, flags=re.M)
    preset = preset.replace('name = "g1"', 'name = "g1-turned"') + base + joints
    (folder / "g1_turned.toml").write_text(preset)
    return str(folder / "g1_turned.toml")


def _hips_soles_com(robot) -> np.ndarray:
    soles = [placement.homogeneous for placement in robot.compute_sole_placements(robot.q0)]
    hips = [robot.compute_frame_placement(robot.q0, hip).translation for hip in robot.hip_joints]
    return np.concatenate([np.ravel(soles), np.ravel(hips), robot.compute_com(robot.q0)])


@pytest.mark.parametrize(("turn", "forward"), [(math.pi, "-x"), (math.pi / 2, "y")])
def test_a_turned_description_loads_as_the_robot_with_its_base_table(tmp_path, turn, forward):
    g1 = get_robot("g1")
    preset = _turned_g1(tmp_path, turn, f'\n[base]\nforward = "{forward}"\nup = "z"\n')
    robot = load_robot(preset, visual=False)
    assert robot.total_mass == pytest.approx(g1.total_mass, rel=1e-12)
    np.testing.assert_allclose(_hips_soles_com(robot), _hips_soles_com(g1), atol=1e-9)
    assert robot.joint_roles == g1.joint_roles
    assert check_posture(robot).passed and check_engines(robot).passed


def test_a_turned_description_without_its_base_table_fails_the_posture_check(tmp_path):
    robot = load_robot(_turned_g1(tmp_path, math.pi), visual=False)
    result = check_posture(robot)
    assert not result.passed and "wrong side" in result.detail


def test_the_joints_table_overrides_the_detection_and_is_checked(tmp_path):
    joints = '\n[joints]\nleft_elbow = "left_wrist_pitch_joint"\narms = true\n'
    robot = load_robot(_turned_g1(tmp_path, 0.0, joints=joints), visual=False)
    assert robot.joint_roles.joint("left", "elbow") == "left_wrist_pitch_joint"
    assert robot.joint_roles.joint("right", "elbow") == "right_elbow_joint"
    robot = load_robot(_turned_g1(tmp_path, 0.0, joints="\n[joints]\narms = false\n"))
    assert not robot.joint_roles.has_arms and robot.joint_roles.joint("left", "knee")
    for table, message in (
        ('left_elbo = "left_elbow_joint"', "unknown key.*left_elbo.*left_hip_yaw"),
        ('left_elbow = "elbow"', "'elbow' is no joint of the robot.*left_hip_pitch_joint"),
        ("arms = 1", "arms to true or false"),
    ):
        with pytest.raises(ConfigurationError, match=message):
            load_robot(_turned_g1(tmp_path, 0.0, joints=f"\n[joints]\n{table}\n"), visual=False)


@pytest.mark.parametrize(("forward", "up"), [("x", "x"), ("w", "z"), ("-z", "z")])
def test_bad_base_axes_are_refused(tmp_path, forward, up):
    with pytest.raises(ConfigurationError, match="forward"):
        base_rotation(forward, up)
    preset = _turned_g1(tmp_path, 0.0, f'\n[base]\nforward = "{forward}"\nup = "{up}"\n')
    with pytest.raises(ConfigurationError, match=r"\[base\] forward"):
        load_robot(preset, visual=False)


def test_base_rotation_columns_and_the_untouched_default():
    np.testing.assert_array_equal(base_rotation("y", "z"), [[0, -1, 0], [1, 0, 0], [0, 0, 1]])
    np.testing.assert_array_equal(base_rotation("x", "-y"), [[1, 0, 0], [0, 0, -1], [0, 1, 0]])
    text = '<robot name="r"><link name="a"/></robot>'
    assert reorient_urdf_root(text, "x", "z") is text


def test_an_mjcf_robot_refuses_a_base_table(tmp_path):
    preset = (PRESETS_DIR / "bioloid_like.toml").read_text() + '\n[base]\nforward = "-x"\n'
    (tmp_path / "b.toml").write_text(preset.replace('"bioloid-like"', '"b"'))
    with pytest.raises(ConfigurationError, match="URDF descriptions only"):
        load_robot(tmp_path / "b.toml", visual=False)
