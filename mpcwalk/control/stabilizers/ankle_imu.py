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

Gains on other robots (the servo stiffness rule). Paper A's gains are Atlas's. A correction
``dq`` of an ankle joint asks its position servo for ``kp dq`` [N m]; what that torque does to
the body is measured by the gravity torque of the body leaning on its ankle, ``m g z_c`` [N m
per rad of lean] (m: total mass, z_c: CoM height). The ratio ``rho = kp / (m g z_c)`` of each
ankle joint is 2.49 on ``atlas-like`` (:data:`PAPER_A_STIFFNESS_RATIO`: kp 4000 N m/rad, 150 kg,
1.093 m). On a robot whose ankle servos are stiffer than that relative to its weight, the
correction of each ankle joint is scaled by ``PAPER_A_STIFFNESS_RATIO / rho`` (its bound
``max_correction`` with it), so that it asks for the same torque, relative to the body's
gravity torque, as paper A's gains on Atlas; a robot with softer ankle servos keeps paper A's
gains (scaling them up would drive the servos into their torque limits, and these robots walk
with paper A's gains). ``atlas-like`` keeps paper A's gains exactly; ``talos`` (rho 2.58) gets
0.97 of them, ``g1`` (1.35) and ``romeo`` (1.10) all of them, ``bioloid-like`` (hobby servos of
50 N m/rad on a 2 kg robot, rho 11.0) 0.23 of them: with paper A's gains its noisy ankle
targets (0.5 deg of jitter at every tick from the derivative term) made its stance foot creep
and the robot yaw 15 deg during a 12 s step.
"""

import math

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.control.stabilizers.base import Stabilizer, StabilizerInput
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Side
from mpcwalk.robot.robot import Robot

#: Ankle servo stiffness over the body's gravity stiffness, ``kp / (m g z_c)``, of paper A's
#: robot (``atlas-like``: kp 4000 N m/rad, 150 kg, CoM 1.093 m above the soles).
PAPER_A_STIFFNESS_RATIO = 4000.0 / (150.0 * 9.81 * 1.093)
#: Ratios within this relative tolerance of paper A's count as paper A's (exact gains).
_RATIO_TOLERANCE = 1e-3


def stiffness_scale(
    stiffness: float, mass: float, com_height: float, gravity: float = 9.81
) -> float:
    """Share of paper A's ankle correction an ankle joint gets (the servo stiffness rule of
    the module docstring): ``min(1, PAPER_A_STIFFNESS_RATIO / rho)`` with ``rho = stiffness /
    (mass gravity com_height)``, 1 within 0.1 % of paper A's ratio.

    Args:
        stiffness: The ankle joint's servo stiffness kp [N m/rad] (inf: no position servo, which gets no correction).
        mass: The robot's total mass [kg].
        com_height: Its CoM height above the soles [m].
        gravity: Gravity [m/s^2].

    Raises:
        ConfigurationError: A mass, CoM height, gravity or stiffness that is not positive.
    """
    for name, value in (("stiffness", stiffness), ("mass", mass), ("com_height", com_height)):
        if not value > 0.0:
            raise ConfigurationError(
                f"The ankle-imu stiffness rule needs a positive {name}, got {value!r}."
            )
    checked_number("gravity", gravity, low=0.0)
    ratio = float(stiffness) / (float(mass) * float(gravity) * float(com_height))
    if ratio <= PAPER_A_STIFFNESS_RATIO * (1.0 + _RATIO_TOLERANCE):
        return 1.0
    return PAPER_A_STIFFNESS_RATIO / ratio


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
        stiffness_rule: Scale each ankle joint's correction by :func:`stiffness_scale` of the
            robot's servo stiffness, mass and CoM height (False: paper A's gains on every
            robot).
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
        stiffness_rule: bool = True,
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
        self.stiffness_rule = bool(stiffness_rule)
        self._joints: dict[Side, tuple[int, int]] | None = None
        self.scales: dict[Side, np.ndarray] = {side: np.ones(2) for side in Side}
        """Per side, the share (pitch, roll) of paper A's correction each ankle joint gets."""
        self._clear()

    def _clear(self) -> None:
        self.integral = np.zeros(3)
        self.previous_error: np.ndarray | None = None
        self.inclination = np.zeros(2)  # filtered (roll, pitch) [rad]
        self.last_correction = np.zeros(4)  # left pitch, left roll, right pitch, right roll

    def reset(self, inputs: StabilizerInput) -> None:
        """Forget the filter and PID states; find the ankle joints of ``inputs.robot`` and
        their share of the correction (the servo stiffness rule)."""
        self._clear()
        robot = inputs.robot
        self._joints = self._ankle_joints(robot)
        self.scales = {side: np.ones(2) for side in Side}
        if self.stiffness_rule:
            stiffness = robot.servo_gains.stiffness
            mass, height = robot.total_mass, robot.com_height
            self.scales = {
                side: np.array([stiffness_scale(float(stiffness[j]), mass, height) for j in joints])
                for side, joints in self._joints.items()
            }

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
            dq = self.scales[side] * np.clip(
                [-command @ axes[:, 1], -command @ axes[:, 0]],
                -self.max_correction,
                self.max_correction,
            )
            out[pitch_joint] += dq[0]
            out[roll_joint] += dq[1]
            self.last_correction[2 * index : 2 * index + 2] = dq
        return out
