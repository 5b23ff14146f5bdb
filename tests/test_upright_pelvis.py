"""Paper M's engine keeps the trunk rigid: on a robot with a waist its IK holds the pelvis
upright with the torso frame (``WholeBodyIK(upright_pelvis=True)``), and paper M's engine
then walks atlas-like."""

import numpy as np
import pinocchio as pin
from conftest import get_robot, walk

from mpcwalk.ik import IKTargets, WholeBodyIK
from mpcwalk.walking.specification import ControllerSpec


def _single_support_pose(robot, upright: bool) -> tuple[np.ndarray, WholeBodyIK]:
    """The IK's pose with the CoM above the left sole and the right foot lifted 8 cm and
    put 15 cm forward (the middle of a step)."""
    q0 = robot.q0
    start = IKTargets.from_configuration(robot, q0)
    left, right = start.left_sole, start.right_sole.copy()
    right.translation = right.translation + np.array([0.15, 0.0, 0.08])
    com = np.array([left.translation[0] + 0.02, left.translation[1], start.com[2]])
    ik = WholeBodyIK(robot, upright_pelvis=upright)
    result = ik.solve_pose(q0, IKTargets(com, left, right, start.torso_rotation))
    assert result.success
    return result.q_next, ik


def _tilt(rotation: np.ndarray) -> float:
    """Angle of the frame's z axis from the vertical [rad]."""
    return float(np.arccos(np.clip(rotation[2, 2], -1.0, 1.0)))


def test_upright_pelvis_holds_the_pelvis_of_a_robot_with_a_waist():
    robot = get_robot("atlas-like")  # torso_yaw, torso_pitch, torso_roll below its torso frame
    tilts = {}
    for upright in (False, True):
        q, ik = _single_support_pose(robot, upright)
        base = pin.Quaternion(q[6], q[3], q[4], q[5]).toRotationMatrix()
        torso = robot.compute_frame_placement(q, robot.torso_frame).rotation
        tilts[upright] = _tilt(base)
        assert _tilt(torso) < 1e-4  # the torso frame upright either way
    assert tilts[False] > np.radians(1.0)  # the waist lets the pelvis lean
    assert tilts[True] < 1e-4
    assert ik.pelvis_task is not None


def test_no_task_is_added_without_a_waist():
    """bioloid-like (paper M's robot): its torso frame is the floating base's body, so the IK
    is the same and its walks stay bit-identical."""
    robot = get_robot("bioloid-like")
    ik = WholeBodyIK(robot, upright_pelvis=True)
    assert ik.pelvis_task is None
    assert len(ik.tasks) == len(WholeBodyIK(robot).tasks) == 4


def test_paper_m_keeps_the_trunk_rigid():
    assert ControllerSpec.named("paper-m").controller_options["upright_pelvis"] is True
    assert ControllerSpec.named("paper-m-open").controller_options["upright_pelvis"] is True


def test_paper_m_walks_atlas_like():
    """With the pelvis free to lean (the torso frame alone upright) atlas-like fell at 3.54 s,
    in its third step: the pelvis pitched back 5-6 deg at each single support."""
    result = walk("atlas-like", "paper-m", command=(0.1, 0.0, 0.0), nb_steps=3)
    m = result.metrics
    assert not m.fell, m.fall_reason
    assert m.steps_completed == m.steps_planned == 4
