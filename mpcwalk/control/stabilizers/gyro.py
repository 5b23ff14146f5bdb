"""Paper M's gyro stabilizer (eq. 26-30): leg joint offsets from the torso's angular rates.

The torso is kept upright, so its roll and pitch rates should be zero while walking; what the
gyroscope measures is model error and disturbance. The stabilizer adds to the servo targets
computed by the IK, for both legs::

    dq_hip_roll  = K_hr * w_roll     dq_hip_pitch = K_hp * w_pitch     dq_knee = K_k * w_pitch
    dq_foot_pitch = K_fp * w_pitch   dq_foot_roll = K_fr * w_roll

with the paper's gains (seconds, i.e. rad per rad/s) as defaults. The rates are those of the
torso about the horizontal axes of its heading frame (forward ``x``, left ``y``): the raw
gyroscope reading (IMU frame) is carried to the world by the IMU's orientation, which is the
estimated base orientation times the IMU's mounting in the robot description (the Pinocchio
frame ``imu`` at the estimated configuration), and turned by the estimated base yaw; an IMU
mounted in any orientation (Talos's is upside down) gives the same rates.

Signs. Paper M states the offsets as positive gains on its robot's joints. Here the sign of
each offset is taken from the joint's axis at the nominal posture, so that the offsets are
*correcting* on every robot: with the foot flat on the ground, the torso's roll relative to
the ground is minus the sum of the roll joint angles about ``+x`` along the leg, so a positive
roll rate (torso falling to the right) is answered by increasing the roll joints about ``+x``,
which rotates the torso back to the left; the same holds in pitch about ``+y``. A joint whose
axis points along ``-x`` (or ``-y``) gets the offset with the opposite sign.
"""

import math

import numpy as np
import pinocchio as pin

from mpcwalk._checks import checked_number
from mpcwalk.control.stabilizers.base import Stabilizer, StabilizerInput
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.robot.joint_roles import SIDES
from mpcwalk.robot.robot import Robot

#: Paper M's gains [s]: hip roll, hip pitch, knee, foot pitch, foot roll.
PAPER_M_GAINS = {
    "hip_roll": 0.01,
    "hip_pitch": 0.01,
    "knee": 0.01,
    "foot_pitch": 0.02,
    "foot_roll": 0.05,
}

#: Joint of each gain: the rate it answers (0 roll, 1 pitch), the world axis its sign is
#: taken from, and the leg role of its joint (``robot.joint_roles``).
_JOINTS = {
    "hip_roll": (0, "hip_roll"),
    "hip_pitch": (1, "hip_pitch"),
    "knee": (1, "knee"),
    "foot_pitch": (1, "ankle_pitch"),
    "foot_roll": (0, "ankle_roll"),
}


def heading_rates(gyro: np.ndarray, imu_rotation: np.ndarray, yaw: float) -> np.ndarray:
    """Roll and pitch rates [rad/s] about the forward and left axes of the heading frame (the
    world frame turned by ``yaw`` [rad]), shape (2,), of a gyroscope reading ``gyro`` [rad/s]
    in the IMU frame, whose orientation in the world is ``imu_rotation`` (3, 3)."""
    omega_world = np.asarray(imu_rotation, dtype=float) @ np.asarray(gyro, dtype=float)
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array(
        [c * omega_world[0] + s * omega_world[1], -s * omega_world[0] + c * omega_world[1]]
    )


class ImuMounting:
    """Where the IMU sits on the robot: its Pinocchio frame (``imu``) and that frame's parent.

    Args:
        robot: The robot; its description has a frame ``imu`` (every shipped robot does).

    Raises:
        FrameNotFound: The robot has no frame ``imu``.
    """

    frame = "imu"

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.frame_id = robot.frame_id(self.frame)
        frame = robot.model.frames[self.frame_id]
        self.on_base = int(frame.parentJoint) == 1  # the free-flyer joint
        """Whether the IMU is fixed to the floating base (no forward kinematics needed)."""
        self.base_to_imu = np.array(frame.placement.rotation)
        """Rotation of the IMU frame in its parent joint's frame, shape (3, 3)."""
        self._data = robot.model.createData()

    def world_rotation(self, state: EstimatedState) -> np.ndarray:
        """Orientation of the IMU frame in the world, shape (3, 3), from the estimated base
        orientation (and joint angles when the IMU is not on the base)."""
        if self.on_base:
            return np.asarray(state.base_rotation) @ self.base_to_imu
        model, data = self.robot.model, self._data
        pin.forwardKinematics(model, data, np.asarray(state.q))
        return np.array(pin.updateFramePlacement(model, data, self.frame_id).rotation)


class GyroStabilizer(Stabilizer):
    """Paper M's stabilizer: leg joint offsets proportional to the torso roll/pitch rates.

    Args:
        hip_roll: Gain K_hr [s].
        hip_pitch: Gain K_hp [s].
        knee: Gain K_k [s].
        foot_pitch: Gain K_fp [s].
        foot_roll: Gain K_fr [s].
        max_offset: Bound of each joint offset [rad].

    Raises:
        ConfigurationError: A negative or non-finite gain; on reset, a robot whose legs lack
            one of the joints.
    """

    name = "gyro"

    def __init__(
        self,
        *,
        hip_roll: float = PAPER_M_GAINS["hip_roll"],
        hip_pitch: float = PAPER_M_GAINS["hip_pitch"],
        knee: float = PAPER_M_GAINS["knee"],
        foot_pitch: float = PAPER_M_GAINS["foot_pitch"],
        foot_roll: float = PAPER_M_GAINS["foot_roll"],
        max_offset: float = 0.2,
    ) -> None:
        gains = dict(
            hip_roll=hip_roll,
            hip_pitch=hip_pitch,
            knee=knee,
            foot_pitch=foot_pitch,
            foot_roll=foot_roll,
            max_offset=max_offset,
        )
        for key, value in gains.items():
            checked_number(
                f"GyroStabilizer {key}",
                value,
                low=0.0,
                unit="rad" if key == "max_offset" else "s (rad per rad/s)",
                fix=f"paper M uses {PAPER_M_GAINS.get(key, 0.2)}",
            )
        self.gains = {key: float(gains[key]) for key in _JOINTS}
        self.max_offset = float(max_offset)
        self._indices = np.zeros(0, dtype=int)
        self._coefficients = np.zeros((0, 2))  # per joint: offset per (roll, pitch) rate
        self.last_rates = np.zeros(2)
        self.last_offsets = np.zeros(0)
        self.mounting: ImuMounting | None = None

    @staticmethod
    def _leg_joints(robot: Robot) -> list[tuple[str, int, str]]:
        """(gain name, joint index in robot.joint_names, joint name) of both legs."""
        joints = robot.joint_roles.require(
            [role for _, role in _JOINTS.values()], user="The gyro stabilizer", robot=robot.name
        )
        names = list(robot.joint_names)
        return [
            (key, names.index(joints[f"{side}_{role}"]), joints[f"{side}_{role}"])
            for side in SIDES
            for key, (_, role) in _JOINTS.items()
        ]

    def reset(self, inputs: StabilizerInput) -> None:
        """Find the leg joints of ``inputs.robot`` and the signs of their offsets."""
        self.calibrate(inputs.robot)

    def calibrate(self, robot: Robot) -> None:
        """Find the leg joints of ``robot`` and the signs of their offsets (from their axes at
        the nominal posture); forget the last rates."""
        self.last_rates = np.zeros(2)
        self.mounting = ImuMounting(robot)
        model, data = robot.model, robot.model.createData()
        q0 = robot.q0
        pin.computeJointJacobians(model, data, q0)
        indices, coefficients = [], []
        for key, index, name in self._leg_joints(robot):
            joint_id = model.getJointId(name)
            column = model.joints[joint_id].idx_v
            jacobian = pin.getJointJacobian(model, data, joint_id, pin.LOCAL_WORLD_ALIGNED)
            axis = jacobian[3:6, column]
            rate = _JOINTS[key][0]
            sign = 1.0 if axis[rate] >= 0.0 else -1.0
            row = np.zeros(2)
            row[rate] = sign * self.gains[key]
            indices.append(index)
            coefficients.append(row)
        self._indices = np.array(indices, dtype=int)
        self._coefficients = np.array(coefficients)
        self.last_offsets = np.zeros(len(indices))

    def offsets(self, rates: np.ndarray) -> dict[int, float]:
        """Joint offsets [rad] (joint index -> offset) for roll/pitch rates [rad/s]."""
        values = np.clip(
            self._coefficients @ np.asarray(rates, dtype=float), -self.max_offset, self.max_offset
        )
        return dict(zip(self._indices.tolist(), values.tolist()))

    def adjust_joint_targets(
        self, inputs: StabilizerInput, joint_targets: np.ndarray
    ) -> np.ndarray:
        """Servo targets plus the offsets of the torso's roll and pitch rates (gyroscope
        reading of the estimated state; unchanged without an estimated state)."""
        state = inputs.state
        if state is None or self.mounting is None or not len(self._indices):
            return joint_targets
        rotation = self.mounting.world_rotation(state)
        self.last_rates = heading_rates(state.sensors.imu.gyro, rotation, state.yaw)
        values = np.clip(self._coefficients @ self.last_rates, -self.max_offset, self.max_offset)
        self.last_offsets = values
        out = np.array(joint_targets, dtype=float, copy=True)
        np.add.at(out, self._indices, values)
        return out
