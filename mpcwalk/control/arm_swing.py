"""Paper M's arm swing (eq. 24-25): each hand follows the opposite foot.

To compensate the yaw moment the legs induce (and the slipping it causes), each arm gets a
forward displacement proportional to the forward displacement of the opposite leg::

    x_larm = s * x_r        x_rarm = s * x_l

where ``x_l``, ``x_r`` are the feet's forward positions relative to the CoM, in the torso's
heading frame, and ``s`` is the arm movement factor (0.8 in paper M). The displacement of a
hand hanging at distance ``l`` below its shoulder is realised by the shoulder pitch joint,
``sin(-theta) * l = x`` for an axis along ``+y`` (the sign follows the joint's axis, so the
hand moves forward on any robot).

In the control tick the arm swing is a joint stage of its own, after the whole-body IK:
:meth:`ArmSwing.apply` sets the two shoulder pitch angles of the IK's next configuration.
The configuration it returns is the controller's reference ``q_ref``, from which the servo
targets and the next IK step start: the IK's CoM task then sees the moved arms and corrects
the CoM at the next tick, and its posture task pulls the arms towards the nominal posture
with a small weight that the next arm-swing stage overrides.
"""

import math

import numpy as np
import pinocchio as pin

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.swing_foot import FeetState
from mpcwalk.robot.joint_roles import SIDES
from mpcwalk.robot.robot import Robot


def arm_swing_for(robot: Robot, factor: float) -> tuple["ArmSwing | None", tuple[str, ...]]:
    """The arm swing of ``factor`` on ``robot`` (None for 0), and what it left out: on a robot
    whose joint roles have no shoulder pitch joints (no arms, or shoulders turning about other
    axes), None and a note saying the robot walks without arm swing.

    Raises:
        ConfigurationError: A negative or non-finite factor.
    """
    factor = checked_number(
        "The arm swing factor s", factor, low=0.0, fix="paper M uses 0.8, 0 keeps the arms still"
    )
    if not factor:
        return None, ()
    roles = robot.joint_roles
    missing = [side for side in SIDES if roles.joint(side, "shoulder_pitch") is None]
    if missing:
        return None, (
            f"robot '{robot.name}' has no shoulder pitch joint ({', '.join(missing)}) among its "
            "joint roles (a preset's [joints] table names them): it walks without arm swing",
        )
    return ArmSwing(robot, factor), ()


class ArmSwing:
    """Shoulder-pitch angles that swing each hand with the opposite foot.

    Args:
        robot: The robot; its arms are found by their shoulder pitch joints
            (``robot.joint_roles``).
        factor: Arm movement factor s (>= 0; paper M: 0.8).

    Raises:
        ConfigurationError: A negative or non-finite factor, or a robot without shoulder
            pitch joints.
    """

    def __init__(self, robot: Robot, factor: float) -> None:
        self.factor = checked_number(
            "The arm swing factor s",
            factor,
            low=0.0,
            fix="paper M uses 0.8, 0 keeps the arms still",
        )
        model = robot.model
        data = model.createData()
        pin.forwardKinematics(model, data, robot.q0)
        pin.updateFramePlacements(model, data)
        pin.computeJointJacobians(model, data, robot.q0)
        indices, nominal, lengths, signs = [], [], [], []
        shoulders = robot.joint_roles.require(
            ("shoulder_pitch",), user="Arm swing (use arm_swing=0 for this robot)", robot=robot.name
        )
        for side in SIDES:
            name = shoulders[f"{side}_shoulder_pitch"]
            joint_id = model.getJointId(name)
            shoulder = data.oMi[joint_id].translation
            subtree = set(model.subtrees[joint_id])
            ends = [
                data.oMf[i].translation
                for i, frame in enumerate(model.frames)
                if frame.parentJoint in subtree
            ]
            ends += [data.oMi[j].translation for j in subtree]
            lengths.append(max(float(np.linalg.norm(p - shoulder)) for p in ends))
            axis = pin.getJointJacobian(model, data, joint_id, pin.LOCAL_WORLD_ALIGNED)[
                3:6, model.joints[joint_id].idx_v
            ]
            signs.append(1.0 if axis[1] >= 0.0 else -1.0)
            index = robot.joint_names.index(name)
            indices.append(index)
            nominal.append(float(robot.q0[7 + index]))
        if min(lengths) <= 1e-6:
            raise ConfigurationError(
                f"Robot '{robot.name}' has no arm below its shoulder pitch joints; use arm_swing=0."
            )
        self.joint_indices = np.array(indices, dtype=int)
        """Indices of the left and right shoulder pitch joints in ``robot.joint_names``."""
        self.nominal = np.array(nominal)
        self.arm_lengths = np.array(lengths)
        self._signs = np.array(signs)

    def hand_displacements(
        self, com_xy: np.ndarray, left_xy: np.ndarray, right_xy: np.ndarray, yaw: float
    ) -> tuple[float, float]:
        """Forward displacements [m] of the left and right hands (eq. 24-25)."""
        forward = np.array([math.cos(yaw), math.sin(yaw)])
        x_left = float(forward @ (np.asarray(left_xy[:2]) - com_xy))
        x_right = float(forward @ (np.asarray(right_xy[:2]) - com_xy))
        return self.factor * x_right, self.factor * x_left

    def joint_angles(
        self, com_xy: np.ndarray, left_xy: np.ndarray, right_xy: np.ndarray, yaw: float
    ) -> np.ndarray:
        """Left and right shoulder pitch angles [rad], shape (2,)."""
        x = np.array(self.hand_displacements(com_xy, left_xy, right_xy, yaw))
        ratio = np.clip(x / self.arm_lengths, -0.9, 0.9)
        return self.nominal - self._signs * np.arcsin(ratio)

    def apply(self, q: np.ndarray, com_xy: np.ndarray, feet: FeetState, yaw: float) -> np.ndarray:
        """Configuration ``q`` (nq,) with the shoulder pitch angles of the arm swing for the
        CoM ``com_xy`` [m], the feet targets and the torso yaw [rad] (a new array)."""
        swung = np.array(q, dtype=float)
        swung[7 + self.joint_indices] = self.joint_angles(
            com_xy, feet.left.position, feet.right.position, yaw
        )
        return swung
