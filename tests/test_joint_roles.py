"""Joint roles found from the kinematics: the shipped robots, and a robot whose joint names
say nothing."""

import math
import pickle

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.joint_role_detection import detect_joint_roles
from mpcwalk.robot.joint_roles import (
    ROLE_KEYS,
    JointRoles,
    with_preset_table,
)
from mpcwalk.robot.loading import robot_names

_LEG = ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle_pitch", "ankle_roll")


def _sides(left: dict, right: dict) -> dict:
    return {
        **{f"left_{k}": v for k, v in left.items()},
        **{f"right_{k}": v for k, v in right.items()},
    }


def _legs(pattern: str, names: tuple) -> dict:
    """Both legs' roles, the names ``pattern.format(side=..., name=...)``."""
    return {
        f"{side}_{role}": pattern.format(side=side, name=name)
        for side in ("left", "right")
        for role, name in zip(_LEG, names)
    }


#: The roles the joint names of each shipped robot imply (None: no joint of that role).
EXPECTED = {
    "bioloid-like": {
        **_legs("{side}_{name}", ("hip_yaw", "hip_roll", "hip_pitch", "knee", "foot_pitch", "foot_roll")),
        **_sides(*({"shoulder_pitch": f"{s}_shoulder_pitch", "shoulder_roll": None, "elbow": f"{s}_elbow"} for s in ("left", "right"))),
    },
    "atlas-like": {
        **_legs("{side}_{name}", _LEG),
        **_sides(*({"shoulder_pitch": f"{s}_shoulder_pitch", "shoulder_roll": f"{s}_shoulder_roll", "elbow": f"{s}_elbow"} for s in ("left", "right"))),
    },
    "g1": {
        **_legs("{side}_{name}_joint", _LEG),
        **_sides(*({"shoulder_pitch": f"{s}_shoulder_pitch_joint", "shoulder_roll": f"{s}_shoulder_roll_joint", "elbow": f"{s}_elbow_joint"} for s in ("left", "right"))),
    },
    # Talos's shoulder turns about yaw (arm_1), roll (arm_2) and yaw (arm_3): no pitch joint
    "talos": {
        **_legs("leg_{side}_{name}_joint", ("1", "2", "3", "4", "5", "6")),
        **_sides(*({"shoulder_pitch": None, "shoulder_roll": f"arm_{s}_2_joint", "elbow": f"arm_{s}_4_joint"} for s in ("left", "right"))),
    },
    # Romeo's arms point forward at q0: LShoulderYaw swings them sideways, LElbowYaw bends
    # the elbow, LElbowRoll twists the forearm
    "romeo": {
        **{f"{side}_{role}": side[0].upper() + name for side in ("left", "right") for role, name in zip(_LEG, ("HipYaw", "HipRoll", "HipPitch", "KneePitch", "AnklePitch", "AnkleRoll"))},
        **_sides(*({"shoulder_pitch": f"{s}ShoulderPitch", "shoulder_roll": None, "elbow": f"{s}ElbowYaw"} for s in "LR")),
    },
}  # fmt: skip


@pytest.mark.parametrize("name", [n for n in EXPECTED if n in robot_names()])
def test_detection_finds_the_roles_the_joint_names_imply_on_the_shipped_robots(name):
    robot = get_robot(name)
    roles = detect_joint_roles(robot.model, robot.q0, robot.foot_frames)
    assert dict(roles.names) == EXPECTED[name]
    assert roles.has_arms and roles.notes == ()
    assert robot.joint_roles == roles  # no shipped preset needs a [joints] table
    assert pickle.loads(pickle.dumps(robot)).joint_roles == roles  # sweeps send robots


def test_every_shipped_robot_is_checked():
    assert set(robot_names()) <= set(EXPECTED)


# A robot written here: joints named j0, j1... that say nothing; hips pitch-roll-yaw (as
# g1's), a waist, a head, and the right shoulder's roll joint turned 45 degrees about z.
def _body(model, joint, mass=1.0, com=(0.0, 0.0, -0.05)):
    inertia = pin.Inertia(mass, np.array(com, float), np.eye(3) * 1e-3)
    model.appendBodyToJoint(joint, inertia, pin.SE3.Identity())


def _meaningless_robot():
    model = pin.Model()
    base = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "j0")
    _body(model, base, 5.0, (0.0, 0.0, 0.1))
    axes = {"x": pin.JointModelRX, "y": pin.JointModelRY, "z": pin.JointModelRZ}

    def chain(parent, links):
        names = []
        for axis, offset, turn in links:
            name = f"j{model.njoints}"
            placement = pin.SE3(pin.utils.rotate("z", turn), np.array(offset, float))
            parent = model.addJoint(parent, axes[axis](), placement, name)
            _body(model, parent)
            names.append(name)
        return parent, names

    legs, arms = {}, {}
    for side, y in (("left", 0.1), ("right", -0.1)):
        leg = [("y", (0, y, 0), 0), ("x", (0, 0, -0.02), 0), ("z", (0, 0, -0.05), 0),
               ("y", (0, 0, -0.3), 0), ("y", (0, 0, -0.3), 0), ("x", (0, 0, 0), 0)]  # fmt: skip
        foot, legs[side] = chain(base, leg)
        sole = pin.SE3(np.eye(3), np.array([0.0, 0.0, -0.05]))
        model.addFrame(pin.Frame(f"f_{side}", foot, 0, sole, pin.FrameType.OP_FRAME))
    waist, _ = chain(base, [("z", (0, 0, 0.2), 0)])
    for side, y, turn in (("left", 0.2, 0), ("right", -0.2, math.pi / 4)):
        arm = [("y", (0, y, 0.3), 0), ("x", (0, 0, 0), turn), ("z", (0, 0, -0.1), -turn),
               ("y", (0, 0, -0.15), 0), ("z", (0, 0, -0.1), 0), ("y", (0, 0, -0.1), 0)]  # fmt: skip
        _, arms[side] = chain(waist, arm)
    chain(waist, [("z", (0, 0, 0.45), 0), ("y", (0, 0, 0.05), 0)])  # a head
    return model, legs, arms


def test_detection_reads_kinematics_not_names():
    model, legs, arms = _meaningless_robot()
    q = pin.neutral(model)
    q[2] = 0.77
    roles = detect_joint_roles(model, q, ("f_left", "f_right"))
    for side in ("left", "right"):
        pitch, roll, yaw, knee, ankle_pitch, ankle_roll = legs[side]
        assert roles.leg(side) == {
            "hip_yaw": yaw, "hip_roll": roll, "hip_pitch": pitch, "knee": knee,
            "ankle_pitch": ankle_pitch, "ankle_roll": ankle_roll,
        }  # fmt: skip
    shoulder_pitch, shoulder_roll, _, elbow, _, _ = arms["left"]
    assert roles.arm("left") == {
        "shoulder_pitch": shoulder_pitch, "shoulder_roll": shoulder_roll, "elbow": elbow
    }  # fmt: skip
    # the right shoulder's roll joint, turned 45 degrees, gets no role and a note
    shoulder_pitch, tilted, _, elbow, _, _ = arms["right"]
    assert roles.arm("right") == {
        "shoulder_pitch": shoulder_pitch,
        "shoulder_roll": None,
        "elbow": elbow,
    }
    assert any(tilted in note and "neither roll, pitch nor yaw" in note for note in roles.notes)
    assert roles.joint("left", "knee") == legs["left"][3] and roles.has_arms


def test_a_robot_without_arms_has_no_arm_roles():
    model = pin.buildModelFromXML(
        """<robot name="r"><link name="a"><inertial><mass value="1"/>
        <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>"""
        + "".join(
            f"""<joint name="{n}" type="revolute"><parent link="{p}"/><child link="{c}"/>
            <origin xyz="{xyz}"/><axis xyz="{axis}"/><limit effort="1" velocity="1" lower="-1" upper="1"/></joint>
            <link name="{c}"><inertial><mass value="1"/>
            <inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/></inertial></link>"""
            for n, p, c, xyz, axis in [
                ("q", "a", "l1", "0 0.1 0", "0 1 0"),
                ("w", "l1", "l2", "0 0 -0.3", "0 1 0"),
                ("e", "l2", "l3", "0 0 -0.3", "0 1 0"),
                ("r", "a", "r1", "0 -0.1 0", "0 1 0"),
                ("t", "r1", "r2", "0 0 -0.3", "0 1 0"),
                ("y", "r2", "r3", "0 0 -0.3", "0 1 0"),
            ]
        )
        + "</robot>",
        pin.JointModelFreeFlyer(),
    )
    q = pin.neutral(model)
    roles = detect_joint_roles(model, q, ("l3", "r3"))
    assert roles.leg("left") == {
        "hip_yaw": None, "hip_roll": None, "hip_pitch": "q", "knee": "w", "ankle_pitch": "e",
        "ankle_roll": None,
    }  # fmt: skip
    assert roles.leg("right")["knee"] == "t" and not roles.has_arms
    assert roles.arm("left") == {"shoulder_pitch": None, "shoulder_roll": None, "elbow": None}
    assert "no left arm found" in roles.notes
    with pytest.raises(ConfigurationError, match="left_shoulder_pitch.*\\[joints\\]"):
        roles.require(("shoulder_pitch",), user="The arm swing", robot="r")
    assert roles.require(("knee",), user="x", robot="r") == {"left_knee": "w", "right_knee": "t"}


def test_preset_table_overrides_detection_and_refuses_unknown_keys_and_joints():
    roles = JointRoles({"left_knee": "a", "left_shoulder_pitch": "s", "right_shoulder_pitch": "t"})
    names = ("a", "b", "s", "t")
    table = with_preset_table(roles, {"left_knee": "b"}, arms=True, joint_names=names, source="p")
    assert table.joint("left", "knee") == "b" and table.joint("left", "shoulder_pitch") == "s"
    no_arms = with_preset_table(roles, {}, arms=False, joint_names=names, source="p")
    assert no_arms.arm("left") == dict.fromkeys(("shoulder_pitch", "shoulder_roll", "elbow"))
    assert no_arms.joint("left", "knee") == "a" and not no_arms.has_arms
    with pytest.raises(ConfigurationError, match="left_kne.*left_hip_yaw"):
        with_preset_table(roles, {"left_kne": "a"}, arms=True, joint_names=names, source="p")
    with pytest.raises(ConfigurationError, match="'z' is no joint.*a, b, s, t"):
        with_preset_table(roles, {"left_knee": "z"}, arms=True, joint_names=names, source="p")
    with pytest.raises(ConfigurationError, match="arms = false"):
        with_preset_table(roles, {"left_elbow": "a"}, arms=False, joint_names=names, source="p")
    with pytest.raises(ConfigurationError, match="roles are"):
        JointRoles({"left_toe": "a"})
    assert len(ROLE_KEYS) == 18
