"""Analytic leg IK of paper M (sec. 3.4) for the small humanoid.

Each leg is a chain hip-yaw (z), hip-roll (x), hip-pitch (y), knee (y), foot-pitch (y),
foot-roll (x) hanging from the root body (the torso), all joint frames parallel to the torso
in the zero posture, the hip roll and pitch axes crossing at the hip centre, the ankle pitch
and roll axes crossing at the ankle, the yaw axis through the hip centre, the thigh and
shank straight down. The geometry (hip centre, thigh and shank lengths, ankle-to-sole
transform) is read from the Pinocchio model's joint placements.

With ``R_a, p_a`` the ankle frame in the torso frame and ``H`` the hip centre, the vector
``r = R_a^T (H - p_a)`` (hip seen from the ankle, in the foot frame) has the length ``D`` that
fixes the knee (law of cosines: ``D^2 = L1^2 + L2^2 + 2 L1 L2 cos(q_knee)``); its direction
gives the foot roll ``atan2(r_y, r_z)`` and then the foot pitch; the hip rotation
``Rz(q_yaw) Rx(q_roll) Ry(q_pitch) = R_a Rx(-q_foot_roll) Ry(-q_knee - q_foot_pitch)`` gives
the three hip angles. The solution is exact (no iteration); the knee bends the way its joint
range allows and the foot roll and hip roll are taken in (-pi/2, pi/2).
"""

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError, LegUnreachable
from mpcwalk.footsteps.footstep import Side

_AXES = (
    "JointModelRZ",
    "JointModelRX",
    "JointModelRY",
    "JointModelRY",
    "JointModelRY",
    "JointModelRX",
)
_TOLERANCE = 1e-12


@dataclass(frozen=True)
class LegGeometry:
    """Geometry of one leg, read from the model.

    Attributes:
        side: ``"left"`` or ``"right"``.
        joint_names: The six joints, hip yaw to foot roll.
        q_indices: Their indices in the configuration vector, shape (6,).
        hip_center: Hip centre in the root (torso) frame, shape (3,), in [m].
        thigh_length: Hip centre to knee, in [m].
        shank_length: Knee to ankle, in [m].
        ankle_to_sole: Sole frame in the foot-roll joint frame.
        knee_sign: +1 when the knee bends with positive angles.
        lower: Lower joint limits, shape (6,), in [rad].
        upper: Upper joint limits, shape (6,), in [rad].
    """

    side: str
    joint_names: tuple[str, ...]
    q_indices: np.ndarray
    hip_center: np.ndarray
    thigh_length: float
    shank_length: float
    ankle_to_sole: pin.SE3
    knee_sign: float
    lower: np.ndarray
    upper: np.ndarray

    @staticmethod
    def from_model(model: pin.Model, sole_frame: str, side: str) -> "LegGeometry":
        """Read the leg ending at ``sole_frame``; raise ConfigurationError if its structure
        is not the one of paper M's robot (see the module docstring)."""

        def fail(reason: str) -> ConfigurationError:
            return ConfigurationError(
                f"The analytic leg IK of paper M does not apply to the {side} leg of robot "
                f"'{model.name}': {reason}. Use WholeBodyIK for this robot."
            )

        frame = model.frames[model.getFrameId(sole_frame)]
        chain, joint = [], frame.parentJoint
        while joint > 1:
            chain.append(joint)
            joint = model.parents[joint]
        chain.reverse()
        names = tuple(model.names[j] for j in chain)
        if len(chain) != 6:
            raise fail(f"it has {len(chain)} joints from the torso to the sole ({names}), not 6")
        kinds = tuple(model.joints[j].shortname() for j in chain)
        if kinds != _AXES:
            raise fail(f"its joint axes are {kinds}, expected z, x, y, y, y, x")
        placements = [model.jointPlacements[j] for j in chain]
        if any(np.abs(p.rotation - np.eye(3)).max() > _TOLERANCE for p in placements):
            raise fail("its joint frames are not parallel to the torso in the zero posture")
        offsets = [p.translation for p in placements]
        if np.abs(offsets[1][:2]).max() > _TOLERANCE or np.abs(offsets[2]).max() > _TOLERANCE:
            raise fail("the hip yaw, roll and pitch axes do not cross at one hip centre")
        if np.abs(offsets[5]).max() > _TOLERANCE:
            raise fail("the foot pitch and roll axes do not cross")
        if np.abs(offsets[3][:2]).max() > _TOLERANCE or np.abs(offsets[4][:2]).max() > _TOLERANCE:
            raise fail("the thigh or the shank is not straight down")
        q_indices = np.array([model.idx_qs[j] for j in chain])
        knee = model.idx_qs[chain[3]]
        knee_middle = 0.5 * (model.lowerPositionLimit[knee] + model.upperPositionLimit[knee])
        return LegGeometry(
            side=side,
            joint_names=names,
            q_indices=q_indices,
            hip_center=offsets[0] + offsets[1],
            thigh_length=float(-offsets[3][2]),
            shank_length=float(-offsets[4][2]),
            ankle_to_sole=frame.placement.copy(),
            knee_sign=1.0 if not knee_middle < 0.0 else -1.0,
            lower=model.lowerPositionLimit[q_indices].copy(),
            upper=model.upperPositionLimit[q_indices].copy(),
        )


def _as_se3(pose, name: str) -> pin.SE3:
    if isinstance(pose, pin.SE3):
        return pose
    matrix = np.asarray(pose, dtype=float)
    if matrix.shape != (4, 4) or not np.all(np.isfinite(matrix)):
        raise ConfigurationError(
            f"{name} must be a pinocchio.SE3 or a 4x4 homogeneous transform, got shape "
            f"{matrix.shape}."
        )
    return pin.SE3(matrix)


class AnalyticLegIK:
    """Closed-form joint angles of both legs from the sole poses (paper M, sec. 3.4).

    Args:
        robot: A robot whose legs have paper M's structure (``bioloid-like``).

    Raises:
        ConfigurationError: A leg does not have that structure.
    """

    def __init__(self, robot) -> None:
        self.robot = robot
        self.geometry: dict[Side, LegGeometry] = {
            side: LegGeometry.from_model(robot.model, frame, side.value)
            for side, frame in zip((Side.LEFT, Side.RIGHT), robot.foot_frames)
        }

    def solve_leg(self, side, sole_in_torso) -> np.ndarray:
        """Joint angles of one leg (hip yaw, hip roll, hip pitch, knee, foot pitch, foot
        roll), in [rad], shape (6,), that put its sole at ``sole_in_torso`` (pose in the root
        body frame). Angles are not clipped to the joint limits.

        Raises:
            LegUnreachable: The ankle target is out of the leg's reach.
        """
        leg = self.geometry[Side.parse(side)]
        ankle = _as_se3(sole_in_torso, "sole_in_torso") * leg.ankle_to_sole.inverse()
        rotation = ankle.rotation
        r = rotation.T @ (leg.hip_center - ankle.translation)  # hip seen from the ankle
        distance = float(np.linalg.norm(r))
        l1, l2 = leg.thigh_length, leg.shank_length
        if distance > l1 + l2 + 1e-12 or distance < abs(l1 - l2) - 1e-12:
            raise LegUnreachable(leg.side, distance, l1 + l2, abs(l1 - l2))
        cos_knee = np.clip((distance**2 - l1**2 - l2**2) / (2.0 * l1 * l2), -1.0, 1.0)
        knee = leg.knee_sign * float(np.arccos(cos_knee))
        foot_roll = float(np.arctan(r[1] / r[2])) if r[2] != 0.0 else np.copysign(np.pi / 2, r[1])
        c, s = np.cos(foot_roll), np.sin(foot_roll)
        w = np.array([r[0], s * r[1] + c * r[2]])  # Rx(foot_roll) r, in the x-z plane
        u = np.array([-l1 * np.sin(knee), l1 * np.cos(knee) + l2])  # same vector, shank frame
        foot_pitch = float(np.arctan2(u[0], u[1]) - np.arctan2(w[0], w[1]))
        hip = rotation @ _rot_x(-foot_roll) @ _rot_y(-knee - foot_pitch)
        hip_roll = float(np.arcsin(np.clip(hip[2, 1], -1.0, 1.0)))
        hip_pitch = float(np.arctan2(-hip[2, 0], hip[2, 2]))
        hip_yaw = float(np.arctan2(-hip[0, 1], hip[1, 1]))
        angles = np.array([hip_yaw, hip_roll, hip_pitch, knee, foot_pitch, foot_roll])
        return (angles + np.pi) % (2.0 * np.pi) - np.pi

    def solve(
        self, base_pose, left_sole, right_sole, q_reference: np.ndarray | None = None
    ) -> np.ndarray:
        """Configuration with the base at ``base_pose`` (world pose of the root body) and both
        soles at their world poses; other joints from ``q_reference`` (default ``robot.q0``).

        Raises:
            LegUnreachable: A sole target is out of reach.
        """
        base = _as_se3(base_pose, "base_pose")
        q = np.array(self.robot.q0 if q_reference is None else q_reference, dtype=float)
        q[0:3] = base.translation
        q[3:7] = pin.Quaternion(base.rotation).coeffs()
        for side, sole in ((Side.LEFT, left_sole), (Side.RIGHT, right_sole)):
            sole_in_torso = base.actInv(_as_se3(sole, f"{side.value}_sole"))
            q[self.geometry[side].q_indices] = self.solve_leg(side, sole_in_torso)
        return q


def _rot_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rot_y(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
