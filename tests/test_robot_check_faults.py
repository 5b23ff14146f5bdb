"""`mpcwalk robots check` on a small URDF biped written here, with one fault at a time: each
failure is found with its number and its fix; the exit codes through the CLI's `main()`."""

import re

import pytest

from mpcwalk.cli import main as cli_main
from mpcwalk.robot import load_robot
from mpcwalk.robot.footprint import sole_from_geometry
from mpcwalk.robot.loading import example_robot_data_dir
from mpcwalk.walking.body_checks import standing_torques
from mpcwalk.walking.robot_check import check_robot

pytestmark = pytest.mark.skipif(
    example_robot_data_dir() is None,
    reason="the loader needs example-robot-data for any URDF robot",
)


def _inertial(mass, ixx, iyy, izz, z=0.0):
    return (
        f'<inertial><origin xyz="0 0 {z}"/><mass value="{mass}"/><inertia ixx="{ixx}" '
        f'iyy="{iyy}" izz="{izz}" ixy="0" ixz="0" iyz="0"/></inertial>'
    )


def _leg(side: str, y: float, thigh: str, shank: str) -> str:
    links = {
        "thigh": thigh,
        "shank": shank,
        "ankle": _inertial(0.2, 1e-4, 1e-4, 1e-4),
        "foot": _inertial(0.5, 5e-4, 1e-3, 1e-3, -0.03)
        + '<collision><origin xyz="0.02 0 -0.04"/><geometry><box size="0.16 0.08 0.02"/>'
        "</geometry></collision>",
    }
    text = "".join(f'<link name="{side}_{name}">{body}</link>' for name, body in links.items())
    joints = [
        ("hip_pitch", "pelvis", "thigh", f"0 {y} -0.05", "0 1 0", -2.0, 1.0),
        ("knee", "thigh", "shank", "0 0 -0.3", "0 1 0", 0.0, 2.5),
        ("ankle_pitch", "shank", "ankle", "0 0 -0.3", "0 1 0", -1.0, 1.0),
        ("ankle_roll", "ankle", "foot", "0 0 0", "1 0 0", -0.5, 0.5),
    ]
    for name, parent, child, xyz, axis, lower, upper in joints:
        parent = parent if parent == "pelvis" else f"{side}_{parent}"
        text += (
            f'<joint name="{side}_{name}" type="revolute"><parent link="{parent}"/>'
            f'<child link="{side}_{child}"/><origin xyz="{xyz}"/><axis xyz="{axis}"/>'
            f'<limit lower="{lower}" upper="{upper}" effort="100" velocity="10"/></joint>'
        )
    return text


def _urdf(torso_rpy="0 0 0", left_shank=None, right_thigh=None) -> str:
    limb = _inertial(1.0, 0.008, 0.008, 0.001, -0.15)
    return (
        '<robot name="biped">'
        f'<link name="pelvis">{_inertial(5.0, 0.05, 0.05, 0.05)}</link>'
        f'<link name="torso">{_inertial(5.0, 0.08, 0.06, 0.04, 0.2)}</link>'
        '<joint name="torso_fixed" type="fixed"><parent link="pelvis"/><child link="torso"/>'
        f'<origin xyz="0 0 0.1" rpy="{torso_rpy}"/></joint>'
        + _leg("left", 0.1, limb, left_shank or limb)
        + _leg("right", -0.1, right_thigh or limb, limb)
        + "</robot>"
    )


POSTURE = {"hip_pitch": -0.3, "knee": 0.6, "ankle_pitch": -0.3}


def _preset(com_height=0.5, sole_offset="[0.02, 0.0, -0.05]", force_limit="", **posture) -> str:
    angles = {
        f"{side}_{joint}": angle for joint, angle in POSTURE.items() for side in ("left", "right")
    }
    angles.update(posture)
    return (
        'name = "biped"\nformat = "urdf"\ndescription = "biped.urdf"\n'
        f'torso_frame = "torso"\ncom_height = {com_height}\n'
        '[feet]\nleft = "left_foot"\nright = "right_foot"\n'
        f"sole_offset = {sole_offset}\nsole_size = [0.16, 0.08]\n"
        '[imu]\nframe = "pelvis"\n[nominal_posture]\n'
        + "".join(f"{name} = {angle}\n" for name, angle in angles.items())
        + f'[[actuators]]\njoints = "*"\nkp = 400.0\nkv = 8.0\narmature = 0.01\n{force_limit}'
    )


@pytest.fixture
def write(tmp_path):
    """Write the biped (URDF, preset) in a folder; the preset's path. The CoM height is the
    nominal posture's."""
    com_height = []

    def write(urdf: str | None = None, **preset):
        (tmp_path / "biped.urdf").write_text(urdf or _urdf())
        path = tmp_path / "biped.toml"
        if not com_height:
            path.write_text(_preset())
            robot = load_robot(path, visual=False)
            com_height.append(round(float(robot.compute_com(robot.q0)[2]), 4))
        path.write_text(_preset(com_height=com_height[0], **preset))
        return path

    return write


def _by_name(results):
    return {r.name: r for r in results}


STATIC = [
    "it loads",
    "the inertias",
    "the engines agree",
    "the nominal posture is within the joint limits",
    "the nominal posture is flat",
    "the torso frame is upright",
    "the soles lie on the feet",
    "the servos hold the posture",
]


def test_the_sound_biped_passes_every_check_it_stands_and_its_sole_is_measured(write):
    results = check_robot(write(), walk=False)
    assert [r.name for r in results] == [*STATIC, "it stands under its servos"]
    assert all(r.passed for r in results), [r for r in results if not r.passed]
    footprint = sole_from_geometry(write().parent / "biped.urdf", "left_foot")
    assert footprint.source == "collision"
    assert footprint.offset == pytest.approx((0.02, 0.0, -0.05), abs=1e-9)
    assert footprint.size == pytest.approx((0.16, 0.08), abs=1e-9)


def test_a_link_with_mass_and_no_inertia_and_a_triangle_violation_are_listed(write):
    """MuJoCo refuses both; the loader repairs both in one pass, the check names both."""
    urdf = _urdf(
        left_shank=_inertial(1.0, 0, 0, 0, -0.15),
        right_thigh=_inertial(1.0, 0.01, 0.01, 0.03, -0.15),
    )
    result = _by_name(check_robot(write(urdf), walk=False))["the inertias"]
    assert result.passed and result.detail.startswith("2 links repaired")
    assert "zero inertia with 1 kg: left_shank" in result.detail
    assert "inertia breaks A + B >= C (0.01 + 0.01 < 0.03): right_thigh" in result.detail


def test_a_posture_outside_the_limits_is_found_with_its_value_and_limits(write):
    results = _by_name(check_robot(write(left_knee=2.8, right_ankle_roll=-0.7), walk=False))
    result = results["the nominal posture is within the joint limits"]
    assert not result.passed
    assert "left_knee = 2.8000 rad outside [0.0000, 2.5000] (set it to 2.5000" in result.detail
    assert "right_ankle_roll = -0.7000 rad outside [-0.5000, 0.5000]" in result.detail
    assert "it stands under its servos" not in results  # no simulation after a failure


def test_a_tilted_sole_is_measured_and_the_ankle_change_that_flattens_it_given(write):
    result = _by_name(check_robot(write(left_ankle_pitch=-0.2), walk=False))[
        "the nominal posture is flat"
    ]
    assert not result.passed
    assert "L sole not flat: tilted 5.73 deg" in result.detail  # 0.1 rad
    assert "pitch 5.73 deg; tolerance 0.5 deg" in result.detail
    assert "change left_ankle_pitch by -0.1000 rad (to -0.3000)" in result.detail
    assert "R sole not flat" not in result.detail


def test_the_sole_tilt_tolerance_takes_rounded_angles(write):
    """0.005 rad (0.29 deg, angles rounded to 2 decimals) passes; 0.01 rad (0.57 deg) not."""
    flat = _by_name(check_robot(write(left_ankle_pitch=-0.295), walk=False))
    assert flat["the nominal posture is flat"].passed
    assert "tilts 0.29 and 0.00 deg" in flat["the nominal posture is flat"].detail
    tilted = _by_name(check_robot(write(left_ankle_pitch=-0.29), walk=False))
    assert "tilted 0.57 deg" in tilted["the nominal posture is flat"].detail


def test_a_rotated_torso_frame_is_found_and_an_upright_frame_named(write):
    result = _by_name(check_robot(write(_urdf(torso_rpy="0 0 1.5708")), walk=False))[
        "the torso frame is upright"
    ]
    assert not result.passed
    assert "z axis 0.0 deg from up, x axis 90.0 deg from the soles' forward" in result.detail
    assert "its x axis (0.00, 1.00, 0.00)" in result.detail
    assert "set torso_frame to an upright frame of the trunk: pelvis" in result.detail
    tilted = _by_name(check_robot(write(_urdf(torso_rpy="0 0.2 0")), walk=False))
    assert "z axis 11.5 deg from up" in tilted["the torso frame is upright"].detail


def test_a_sole_offset_outside_the_foot_is_found_with_the_measured_footprint(write):
    result = _by_name(check_robot(write(sole_offset="[0.08, 0.0, -0.05]"), walk=False))[
        "the soles lie on the feet"
    ]
    assert not result.passed
    assert "L sole 0.160 x 0.080 m at (0.080, 0.000) m reaches 60.0 mm outside" in result.detail
    assert "0.160 x 0.080 m centred at (0.020, 0.000, -0.050) m (collision" in result.detail
    assert "sole_offset = [0.020, 0.000, -0.050], sole_size = [0.160, 0.080]" in result.detail


def test_servos_too_weak_for_the_posture_are_found(write):
    results = _by_name(check_robot(write(force_limit="force_limit = 5.0\n"), walk=False))
    result = results["the servos hold the posture"]
    assert not result.passed
    torques = re.findall(r"(\w+) ([\d.]+) N m, (\d+) % of its 5.0 N m limit", result.detail)
    assert {name for name, *_ in torques} >= {"left_knee", "right_knee"}
    assert "raise the force_limit of the preset's [[actuators]]" in result.detail


def test_the_standing_torques_are_those_mujoco_measures(write):
    """Pinocchio's static torques of the standing posture against the servo torques MuJoCo
    needs to hold it after a second (measured: knee -4.78 against -4.94 N m)."""
    import mujoco
    import numpy as np

    from mpcwalk.sim import make_mj_data

    robot = load_robot(write(), visual=False)
    torques = standing_torques(robot)
    data = make_mj_data(robot)
    while data.time < 1.0:
        mujoco.mj_step(robot.mj_model, data)
    knee = robot.joint_names.index("left_knee")
    actuator = robot.mj_model.actuator("left_knee").id
    assert abs(torques[knee]) > 1.0
    assert data.actuator_force[actuator] == pytest.approx(torques[knee], rel=0.1)
    assert np.abs(torques[[robot.joint_names.index("left_ankle_roll")]]).max() < 0.1


def test_exit_codes_nothing_to_check_is_2_a_failed_check_is_1(write, tmp_path, capsys):
    assert cli_main(["robots", "check", str(tmp_path / "missing.toml")]) == 2
    assert "not found" in capsys.readouterr().err
    assert cli_main(["robots", "check", "no-such-robot"]) == 2
    assert cli_main(["robots", "check", str(write(left_knee=2.8)), "--no-walk"]) == 1
    out = capsys.readouterr().out
    assert "FAIL the nominal posture is within the joint limits: left_knee = 2.8000" in out
    assert cli_main(["robots", "check", str(write()), "--no-walk"]) == 0
