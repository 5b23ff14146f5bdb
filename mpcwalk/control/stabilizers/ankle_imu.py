"""Paper A's ankle strategy and IMU correction as a stabilizer.

Ankle strategy (paper A, static stability controller): in contact, the support foot's normal
should point at the CoM as the reference motion has it. The rotation that takes the measured
sole-to-CoM vector onto the reference one, ``omega = (v_meas x v_ref) / |v|^2`` [rad], is the
error of a PID whose output turns the ankle pitch and roll joints of the feet in contact. A
joint angle ``q`` turns the foot relative to the shank, so with the foot on the ground it turns
the body above by ``-q`` about the joint axis: the correction is ``dq_j = -u . a_j`` with
``a_j`` the axis (the sole's y axis for the pitch, its x axis for the roll).

IMU correction: the body inclination (the estimated base roll and pitch, from the IMU;
first-order low-pass filtered) is fed back the same way, turning the feet in contact so that the body comes back upright and
the CoM back over the support.
"""

import math

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.control.stabilizers.base import Stabilizer, StabilizerInput
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Side
from mpcwalk.robot.robot import Robot


class AnkleImuStabilizer(Stabilizer):
    """PID on the ankle joints keeping the support normal at the CoM, plus IMU correction.

    Args:
        kp: Proportional gain [rad/rad].
        ki: Integral gain [1/s].
        kd: Derivative gain [s].
        imu_gain: Ankle correction per radian of filtered body inclination [rad/rad].
        imu_cutoff: Cut-off frequency of the IMU low-pass filter [Hz].
        max_correction: Bound of the correction of each ankle joint [rad].
        integral_limit: Bound of the integrated error [rad s].
    """

    name = "ankle-imu"

    def __init__(
        self,
        *,
        kp: float = 0.5,
        ki: float = 0.2,
        kd: float = 0.02,
        imu_gain: float = 0.2,
        imu_cutoff: float = 2.0,
        max_correction: float = 0.05,
        integral_limit: float = 0.1,
    ) -> None:
        values = dict(
            kp=kp,
            ki=ki,
            kd=kd,
            imu_gain=imu_gain,
            imu_cutoff=imu_cutoff,
            max_correction=max_correction,
            integral_limit=integral_limit,
        )
        for key, value in values.items():
            checked_number(f"AnkleImuStabilizer {key}", value, low=0.0)
        if imu_cutoff <= 0.0:
            raise ConfigurationError("AnkleImuStabilizer imu_cutoff must be positive [Hz].")
        self.kp, self.ki, self.kd = float(kp), float(ki), float(kd)
        self.imu_gain, self.imu_cutoff = float(imu_gain), float(imu_cutoff)
        self.max_correction, self.integral_limit = float(max_correction), float(integral_limit)
        self._joints: dict[Side, tuple[int, int]] | None = None
        self._clear()

    def _clear(self) -> None:
        self.integral = np.zeros(3)
        self.previous_error: np.ndarray | None = None
        self.inclination = np.zeros(2)  # filtered (roll, pitch) [rad]
        self.last_correction = np.zeros(4)  # left pitch, left roll, right pitch, right roll

    def reset(self, inputs: StabilizerInput) -> None:
        """Forget the filter and PID states; find the ankle joints of ``inputs.robot``."""
        self._clear()
        self._joints = self._ankle_joints(inputs.robot)

    @staticmethod
    def _ankle_joints(robot: Robot) -> dict[Side, tuple[int, int]]:
        """Indices of each side's ankle pitch and roll joints in ``robot.joint_names`` (its
        joint roles)."""
        joints = robot.joint_roles.require(
            ("ankle_pitch", "ankle_roll"), user="The ankle-imu stabilizer", robot=robot.name
        )
        names = list(robot.joint_names)
        return {
            side: (
                names.index(joints[f"{side.value}_ankle_pitch"]),
                names.index(joints[f"{side.value}_ankle_roll"]),
            )
            for side in Side
        }

    def _filter(
        self, roll: float, pitch: float, reference_base_quaternion: np.ndarray, dt: float
    ) -> np.ndarray:
        """Low-pass filtered body inclination (roll, pitch) [rad] of the estimated base
        relative to the reference base orientation (the IK's, pinocchio quaternion x, y, z,
        w)."""
        x, y, z, w = (float(c) for c in reference_base_quaternion)
        roll_ref = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
        pitch_ref = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
        alpha = dt / (dt + 1.0 / (2.0 * math.pi * self.imu_cutoff))
        error = np.array([roll - roll_ref, pitch - pitch_ref])
        self.inclination += alpha * (error - self.inclination)
        return self.inclination

    def adjust_joint_targets(
        self, inputs: StabilizerInput, joint_targets: np.ndarray
    ) -> np.ndarray:
        """Servo targets plus the ankle corrections of the feet in contact (unchanged
        without an estimated state)."""
        state = inputs.state
        if state is None or self._joints is None:
            return joint_targets
        positions, feet = state.sole_positions, inputs.targets.feet
        dt = inputs.control_period
        roll, pitch = self._filter(state.roll, state.pitch, inputs.q_ref[3:7], dt)
        contacts = feet.contact_sides
        if not contacts:
            return joint_targets
        # error: rotation taking the measured sole->CoM vector onto the reference one
        weights = dict(zip(Side, inputs.support_weights))
        error = np.zeros(3)
        com_ref = inputs.com_reference
        for side in contacts:
            index = 0 if side is Side.LEFT else 1
            v_meas = state.com - positions[index]
            v_ref = com_ref - feet[side].position
            error += weights[side] * np.cross(v_meas, v_ref) / float(np.dot(v_ref, v_ref))
        error[2] = 0.0
        derivative = (
            np.zeros(3) if self.previous_error is None else (error - self.previous_error) / dt
        )
        self.previous_error = error
        self.integral = np.clip(
            self.integral + error * dt, -self.integral_limit, self.integral_limit
        )
        command = self.kp * error + self.ki * self.integral + self.kd * derivative
        # body inclination back to upright: world rotation -(roll, pitch)
        command += self.imu_gain * np.array([-roll, -pitch, 0.0])
        out = np.array(joint_targets, dtype=float, copy=True)
        self.last_correction = np.zeros(4)
        rotations = state.sole_rotations
        for side in contacts:
            index = 0 if side is Side.LEFT else 1
            pitch_joint, roll_joint = self._joints[side]
            axes = rotations[index]
            dq = np.clip(
                [-command @ axes[:, 1], -command @ axes[:, 0]],
                -self.max_correction,
                self.max_correction,
            )
            out[pitch_joint] += dq[0]
            out[roll_joint] += dq[1]
            self.last_correction[2 * index : 2 * index + 2] = dq
        return out
