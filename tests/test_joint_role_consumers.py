"""The controllers find their joints by role: paper A's ankle strategy on every robot, paper
M's arm swing left out (and said so) on a robot without shoulder pitch joints, and
``--arm-swing 0`` beside a controller that swings its arms."""

import argparse
import dataclasses

import pytest
from conftest import get_robot

from mpcwalk.cli.walk_options import add_walk_options, spec_from_args
from mpcwalk.control.arm_swing import ArmSwing, arm_swing_for
from mpcwalk.control.stabilizers.ankle_imu import AnkleImuStabilizer
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.joint_roles import with_preset_table
from mpcwalk.robot.loading import robot_names
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import WalkSpec, write_spec

ANKLES = {
    "bioloid-like": ("left_foot_pitch", "left_foot_roll", "right_foot_pitch", "right_foot_roll"),
    "atlas-like": ("left_ankle_pitch", "left_ankle_roll", "right_ankle_pitch", "right_ankle_roll"),
    "g1": tuple(f"{s}_ankle_{a}_joint" for s in ("left", "right") for a in ("pitch", "roll")),
    "talos": ("leg_left_5_joint", "leg_left_6_joint", "leg_right_5_joint", "leg_right_6_joint"),
    "romeo": ("LAnklePitch", "LAnkleRoll", "RAnklePitch", "RAnkleRoll"),
}


@pytest.mark.parametrize("name", [n for n in ANKLES if n in robot_names()])
def test_the_ankle_imu_stabilizer_finds_the_ankles_of_every_shipped_robot(name):
    robot = get_robot(name)
    joints = AnkleImuStabilizer._ankle_joints(robot)
    found = [robot.joint_names[i] for side in joints.values() for i in side]
    assert tuple(found) == ANKLES[name]


def _armless(robot):
    roles = with_preset_table(
        robot.joint_roles, {}, arms=False, joint_names=robot.joint_names, source="test"
    )
    return dataclasses.replace(robot, joint_roles=roles)


def test_arm_swing_is_left_out_and_said_so_on_a_robot_without_shoulder_pitch_joints():
    robot = get_robot("bioloid-like")
    swing, notes = arm_swing_for(robot, 0.8)
    assert isinstance(swing, ArmSwing) and notes == ()
    assert arm_swing_for(robot, 0.0) == (None, ())
    armless = _armless(robot)
    swing, notes = arm_swing_for(armless, 0.8)
    assert swing is None and len(notes) == 1 and "walks without arm swing" in notes[0]
    with pytest.raises(ConfigurationError, match="left_shoulder_pitch.*\\[joints\\]"):
        ArmSwing(armless, 0.8)
    spec = WalkSpec.build("bioloid-like", controller="paper-m", nb_steps=2, progress=False)
    result = run_walk(spec, robot=armless)
    assert result.metrics.warnings[:1] == notes
    assert run_walk(spec, robot=robot).metrics.warnings == ()


def _walk_spec(argv):
    parser = argparse.ArgumentParser()
    add_walk_options(parser)
    return spec_from_args(parser.parse_args(argv), out=None)


def test_arm_swing_zero_beside_a_swinging_controller_keeps_the_arms_still(tmp_path):
    spec = _walk_spec(["--controller", "paper-m", "--arm-swing", "0", "--steps", "2"])
    assert spec.controller.arm_swing == 0.0 and spec.controller.stabilizers == ("gyro",)
    file = write_spec(
        WalkSpec.build("bioloid-like", controller="paper-m", nb_steps=2), tmp_path / "s.toml"
    )
    assert _walk_spec(["--spec", str(file), "--arm-swing", "0"]).controller.arm_swing == 0.0
    assert _walk_spec(["--spec", str(file)]).controller.arm_swing == 0.8
