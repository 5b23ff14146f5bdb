"""The robot survey reads legs, axes, soles and a walking posture off a description."""

import math

import numpy as np
import pinocchio as pin
import pytest
from urdf_biped import biped_urdf

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.loading import example_robot_data_dir
from mpcwalk.robot.survey.draft import draft_preset
from mpcwalk.robot.survey.feet import soles_from_geometry
from mpcwalk.robot.survey.legs import AXES, find_legs
from mpcwalk.robot.survey.posture import HIP_HEIGHT_RATIO, solve_posture
from mpcwalk.robot.survey.writer import preset_toml
from mpcwalk.robot.urdf_repair import repair_inertias

ROOT = example_robot_data_dir()
needs_robots = pytest.mark.skipif(ROOT is None, reason="example-robot-data is not installed")


def _model(text: str) -> pin.Model:
    return pin.buildModelFromXML(repair_inertias(text)[0], pin.JointModelFreeFlyer())


@needs_robots
@pytest.mark.parametrize(
    ("description", "forward", "up", "left_leg"),
    [
        ("g1_description/urdf/g1_29dof_rev_1_0.urdf", "x", "z", "left_hip_pitch_joint"),
        ("talos_data/robots/talos_reduced.urdf", "x", "z", "leg_left_1_joint"),
        ("romeo_description/urdf/romeo.urdf", "x", "z", "LHipYaw"),
        ("icub_description/robots/icub.urdf", "-x", "z", "l_hip_pitch"),  # root x backward
        ("human_description/robots/human.urdf", "x", "y", "left_hip_Z"),  # drawn y up
    ],
)
def test_legs_and_axes_of_stock_humanoids(description, forward, up, left_leg):
    assert ROOT is not None
    survey = find_legs(_model((ROOT / description).read_text()))
    assert (survey.forward, survey.up) == (forward, up)
    assert survey.left.joints[0] == left_leg
    assert len(survey.left.joints) == len(survey.right.joints) == 6
    # the left foot is on the left of up x forward
    left_axis = np.cross(AXES[up], AXES[forward])
    assert (survey.left.foot_position - survey.right.foot_position) @ left_axis > 0.05


def test_a_biped_turned_backward_with_meaningless_names():
    for yaw, forward in ((0.0, "x"), (math.pi, "-x")):
        survey = find_legs(_model(biped_urdf(base_yaw=yaw)))
        assert survey.forward == forward
        assert survey.left.joints == ("jpa", "jpb", "jpc", "jpd", "jpe", "jpf")
        assert survey.left.knee == "jpd"
        assert survey.left.foot == "p5"
        assert survey.leg_length == pytest.approx(0.8, abs=1e-9)


def test_a_robot_without_two_legs_is_refused():
    text = biped_urdf().replace('name="jqa"', 'name="jqa"', 1)
    one_leg = "\n".join(
        line for line in text.splitlines() if not any(f'"q{i}"' in line for i in range(1, 6))
    )
    with pytest.raises(ConfigurationError, match="two legs|one branch"):
        find_legs(_model(one_leg))


@needs_robots
def test_g1_soles_are_its_contact_points():
    # the G1's URDF puts four contact spheres (5 mm) under each foot: the preset shipped by
    # hand reads "sole_offset = [0.035, 0.0, -0.035]" from them
    assert ROOT is not None
    path = ROOT / "g1_description/urdf/g1_29dof_rev_1_0.urdf"
    model = _model(path.read_text())
    left, right = soles_from_geometry(path, model, find_legs(model))
    assert left.offset == pytest.approx((0.035, 0.0, -0.035), abs=1e-3)
    assert left.size[1] == pytest.approx(0.07, abs=2e-3)
    assert right.offset == pytest.approx(left.offset, abs=1e-3)
    assert "collision" in left.source


@needs_robots
def test_romeo_soles_are_read_from_its_collada_feet():
    # MuJoCo reads no Collada mesh: Pinocchio measures Romeo's feet (the shipped preset uses
    # the URDF's own sole frames, 0.0675 m below the ankle, and a 0.20 x 0.10 m sole)
    assert ROOT is not None
    path = ROOT / "romeo_description/urdf/romeo.urdf"
    model = _model(path.read_text())
    left, right = soles_from_geometry(path, model, find_legs(model))
    assert left.offset[2] == pytest.approx(-0.0675, abs=1e-3)
    assert 0.15 < left.size[0] < 0.25 and 0.08 < left.size[1] < 0.14
    assert right.offset[1] == pytest.approx(-left.offset[1], abs=1e-3)  # mirrored


def test_posture_is_flat_bent_and_balanced():
    model = _model(biped_urdf(base_yaw=math.pi))
    survey = find_legs(model)
    centre = np.array([0.0, 0.0, -0.065])
    posture = solve_posture(model, survey, (centre, centre))
    data = model.createData()
    pin.framesForwardKinematics(model, data, posture.q)
    up = AXES[survey.up]
    for leg in (survey.left, survey.right):
        foot = data.oMf[model.getFrameId(leg.foot)]
        # flat: the foot keeps its orientation of the zero configuration
        assert foot.rotation @ np.array([0.0, 0.0, 1.0]) == pytest.approx(up, abs=1e-8)
    hip = data.oMi[model.getJointId(survey.left.joints[0])].translation
    assert hip @ up == pytest.approx(
        HIP_HEIGHT_RATIO * survey.left.hip_position @ up
        + (1 - HIP_HEIGHT_RATIO) * data.oMf[model.getFrameId("p5")].act(centre) @ up,
        abs=1e-6,
    )
    com = pin.centerOfMass(model, data, posture.q)
    soles = [data.oMf[model.getFrameId(f)].act(centre) for f in ("p5", "q5")]
    assert (com - 0.5 * (soles[0] + soles[1]))[:2] == pytest.approx([0.0, 0.0], abs=1e-8)
    assert posture.angles["jpd"] > 0.4  # the knee bends toward its larger range
    assert posture.outside_limits == ()


def test_draft_lists_repairs_and_writes_every_guess(tmp_path):
    path = tmp_path / "quirky.urdf"
    path.write_text(biped_urdf(base_yaw=math.pi, zero_inertia=3))
    draft = draft_preset(path, reference="quirky.urdf")
    assert draft.repaired_links == ("p0", "p1", "p4")
    assert draft.base == ("-x", "z")
    assert draft.legs.forward == "x"  # after the loader's re-expression of the root
    assert draft.torso[0] == "chest"
    text = preset_toml(draft)
    for expected in ('forward = "-x"', 'left = "p5"', "jpd = 0.", "[[actuators]]", "[gait]"):
        assert expected in text
    # servo stiffness of a leg: 3 m g l
    kp = next(s.kp for s in draft.servos if s.joint == "jpd")
    assert kp == pytest.approx(3 * draft.mass * 9.81 * draft.leg_length, rel=1e-2)
