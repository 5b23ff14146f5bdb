"""Analytic leg IK of paper M against Pinocchio's forward kinematics and the whole-body IK."""

import numpy as np
import pinocchio as pin
import pytest

from mpcwalk.exceptions import ConfigurationError, LegUnreachable, MpcwalkError
from mpcwalk.footsteps.footstep import Side
from mpcwalk.ik import IKTargets, WholeBodyIK
from mpcwalk.ik.leg_ik import AnalyticLegIK
from mpcwalk.robot.loading import load_robot


@pytest.fixture(scope="module")
def robot():
    return load_robot("bioloid-like", visual=False)


@pytest.fixture(scope="module")
def leg_ik(robot):
    return AnalyticLegIK(robot)


def test_geometry_is_read_from_the_model(leg_ik):
    # numbers of robots/bioloid_like.xml: hips 0.04 m either side, hip axes 0.035 m below the
    # pelvis frame, 0.085 m thigh and shank, sole 0.032 m below the ankle axes
    for side, sign in ((Side.LEFT, 1.0), (Side.RIGHT, -1.0)):
        leg = leg_ik.geometry[side]
        assert np.allclose(leg.hip_center, [0.0, sign * 0.04, -0.035], atol=1e-15)
        assert leg.thigh_length == pytest.approx(0.085, abs=1e-15)
        assert leg.shank_length == pytest.approx(0.085, abs=1e-15)
        assert np.allclose(leg.ankle_to_sole.translation, [0.0, 0.0, -0.032], atol=1e-15)
        assert leg.joint_names[3] == f"{side.value}_knee" and leg.knee_sign == 1.0


def test_walking_posture_is_recovered(robot, leg_ik):
    """Torso upright, feet flat under the hips, CoM height of Table 1: the preset's angles."""
    left, right = robot.compute_sole_placements(robot.q0)
    base = pin.XYZQUATToSE3(robot.q0[:7])
    for side, sole in ((Side.LEFT, left), (Side.RIGHT, right)):
        angles = leg_ik.solve_leg(side, base.actInv(sole))
        assert np.allclose(angles, [0.0, 0.0, -0.38, 0.76, -0.38, 0.0], atol=1e-12)


def test_forward_kinematics_of_the_solution_reproduces_random_targets(robot, leg_ik):
    rng = np.random.default_rng(7)
    worst_pose, worst_angle = 0.0, 0.0
    for _ in range(200):
        q = robot.q0.copy()
        q[0:3] = rng.uniform(-0.5, 0.5, 3)
        quaternion = rng.normal(size=4)
        q[3:7] = quaternion / np.linalg.norm(quaternion)
        for leg in leg_ik.geometry.values():
            angles = rng.uniform(leg.lower, leg.upper)
            angles[3] = rng.uniform(0.05, leg.upper[3])  # a bent knee: one branch
            q[leg.q_indices] = angles
        left, right = robot.compute_sole_placements(q)
        solution = leg_ik.solve(pin.XYZQUATToSE3(q[:7]), left, right, q_reference=q)
        left_fk, right_fk = robot.compute_sole_placements(solution)
        worst_pose = max(
            worst_pose,
            np.abs(left_fk.homogeneous - left.homogeneous).max(),
            np.abs(right_fk.homogeneous - right.homogeneous).max(),
        )
        worst_angle = max(worst_angle, np.abs(solution[7:] - q[7:]).max())
    assert worst_pose < 1e-9
    assert worst_angle < 1e-9  # the solution is unique on the bent-knee branch


def test_agrees_with_the_whole_body_ik(robot, leg_ik):
    """WholeBodyIK.solve_pose on a swing-foot target; the analytic IK from the base pose it
    found gives the same leg angles."""
    start = IKTargets.from_configuration(robot, robot.q0)
    swing = pin.SE3(
        pin.exp3(np.array([0.0, 0.0, 0.2])), start.right_sole.translation + [0.03, -0.01, 0.025]
    )
    targets = IKTargets(
        start.com + [0.0, 0.025, -0.005],
        start.left_sole,
        swing,
        pin.exp3(np.array([0.0, 0.0, 0.1])),
    )
    result = WholeBodyIK(robot).solve_pose(robot.q0, targets)
    assert result.success
    base = pin.XYZQUATToSE3(result.q_next[:7])
    analytic = leg_ik.solve(base, targets.left_sole, targets.right_sole, result.q_next)
    for leg in leg_ik.geometry.values():
        assert np.abs(analytic[leg.q_indices] - result.q_next[leg.q_indices]).max() < 1e-6
    assert np.abs(analytic[7:] - result.q_next[7:]).max() < 1e-6


def test_unreachable_target_names_the_distance_and_the_leg_length(robot, leg_ik):
    base = pin.XYZQUATToSE3(robot.q0[:7])
    left, right = robot.compute_sole_placements(robot.q0)
    far = pin.SE3(left.rotation, left.translation - [0.0, 0.0, 0.1])
    with pytest.raises(LegUnreachable, match=r"beyond the leg length 0\.1700 m") as error:
        leg_ik.solve(base, far, right)
    assert isinstance(error.value, MpcwalkError)
    assert error.value.side == "left"
    assert error.value.leg_length == pytest.approx(0.17)
    hip_to_ankle = (base.translation + [0.0, 0.04, -0.035]) - (far.translation + [0, 0, 0.032])
    assert error.value.distance == pytest.approx(np.linalg.norm(hip_to_ankle), abs=1e-12)
    with pytest.raises(ConfigurationError, match="4x4"):
        leg_ik.solve_leg("left", np.eye(3))
    with pytest.raises(ConfigurationError, match="'left' or 'right'"):
        leg_ik.solve_leg("middle", pin.SE3.Identity())


@pytest.mark.parametrize(
    "name, reason",
    [
        ("g1", "expected z, x, y, y, y, x"),
        ("atlas-like", "do not cross at one hip centre"),
    ],
)
def test_other_leg_structures_are_refused(name, reason):
    with pytest.raises(ConfigurationError, match=reason):
        AnalyticLegIK(load_robot(name, visual=False))
