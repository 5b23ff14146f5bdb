"""The robot's kinematics relative to its base, and the world state built from them.

:meth:`BaseKinematics.compute` runs one Pinocchio pass with the floating base at the origin
(``centerOfMass`` with the joint velocities, which also computes the joint placements and
velocities, then ``updateFramePlacements``): the CoM, the soles and the IMU expressed in the
base frame, and their velocities due to the joints alone. Everything in the world follows by
one rigid motion of the base (position p, orientation R, angular velocity w in the base
frame, linear velocity v in the world):

    x_world = p + R x,    v_world = v + R (w x x + dx/dt).

:meth:`BaseKinematics.estimated_state` assembles the
:class:`~mpcwalk.estimation.estimated_state.EstimatedState` from them and the readings.
"""

import math
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from mpcwalk._checks import freeze, frozen_array
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.robot.robot import Robot
from mpcwalk.robot.sensors import FootContact, ForceTorqueReading, SensorReadings

_NAN3 = frozen_array([np.nan, np.nan, np.nan])

IMU_FRAME = "imu"
"""Pinocchio frame of the IMU, added by the robot loader to every robot."""


def rpy_of(rotation: np.ndarray) -> tuple[float, float, float]:
    """Roll, pitch, yaw [rad] (Z-Y-X Euler angles) of a rotation matrix."""
    roll = math.atan2(float(rotation[2, 1]), float(rotation[2, 2]))
    pitch = math.asin(max(-1.0, min(1.0, -float(rotation[2, 0]))))
    yaw = math.atan2(float(rotation[1, 0]), float(rotation[0, 0]))
    return roll, pitch, yaw


def cross_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a x b`` row by row, shapes (3,) or (n, 3) broadcast (np.cross is slow on small
    arrays)."""
    out = np.empty(a.shape if a.ndim >= b.ndim else b.shape)  # (3,) or (n, 3), broadcast
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


class KinematicsPass(NamedTuple):
    """The robot relative to its base, base frame, from one Pinocchio pass.

    Attributes:
        com: CoM position, shape (3,), in [m].
        com_velocity: CoM velocity due to the joints, shape (3,), in [m/s].
        foot_positions: Left and right sole origins, shape (2, 3), in [m].
        foot_rotations: Left and right sole orientations, shape (2, 3, 3).
        foot_velocities: Sole origin velocities due to the joints, shape (2, 3), in [m/s].
        foot_angular_velocities: Sole angular velocities due to the joints, shape (2, 3), in
            [rad/s].
        imu_position: Origin of the IMU frame, shape (3,), in [m].
        imu_rotation: Orientation of the IMU frame, shape (3, 3).
        imu_velocity: Velocity of the IMU frame's origin due to the joints, shape (3,), in
            [m/s].
        imu_angular_velocity: Angular velocity of the IMU frame due to the joints, shape
            (3,), in [rad/s].
        joint_velocities: The joint velocities of the pass [rad/s].
    """

    com: np.ndarray
    com_velocity: np.ndarray
    foot_positions: np.ndarray
    foot_rotations: np.ndarray
    foot_velocities: np.ndarray
    foot_angular_velocities: np.ndarray
    imu_position: np.ndarray
    imu_rotation: np.ndarray
    imu_velocity: np.ndarray
    imu_angular_velocity: np.ndarray
    joint_velocities: np.ndarray


class BaseKinematics:
    """Pinocchio kinematics of a robot relative to its floating base.

    Args:
        robot: The robot; its frame ``imu`` and sole frames are used. The estimator owns a
            Pinocchio data of its own (the robot's ``data`` is left to the others).
    """

    def __init__(self, robot: Robot) -> None:
        self.model = robot.model
        self.data = robot.model.createData()
        self.sole_ids = tuple(robot.frame_id(frame) for frame in robot.foot_frames)
        self.imu_id = robot.frame_id(IMU_FRAME)
        self.gravity = float(np.linalg.norm(robot.model.gravity.linear))
        self._q = pin.neutral(robot.model)
        self._q[0:7] = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)
        self._v = np.zeros(robot.model.nv)

    def compute(self, joint_positions: np.ndarray, joint_velocities: np.ndarray) -> KinematicsPass:
        """One kinematics pass at the given joint positions [rad] and velocities [rad/s]."""
        model, data = self.model, self.data
        self._q[7:] = joint_positions
        self._v[6:] = joint_velocities
        com = pin.centerOfMass(model, data, self._q, self._v, False).copy()
        pin.updateFramePlacements(model, data)
        world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED  # the base frame here
        soles = [data.oMf[i] for i in self.sole_ids]
        sole_velocities = [pin.getFrameVelocity(model, data, i, world) for i in self.sole_ids]
        imu = data.oMf[self.imu_id]
        imu_velocity = pin.getFrameVelocity(model, data, self.imu_id, world)
        return KinematicsPass(
            com=com,
            com_velocity=data.vcom[0].copy(),
            foot_positions=np.array([sole.translation for sole in soles]),
            foot_rotations=np.array([sole.rotation for sole in soles]),
            foot_velocities=np.array([velocity.linear for velocity in sole_velocities]),
            foot_angular_velocities=np.array([velocity.angular for velocity in sole_velocities]),
            imu_position=imu.translation.copy(),
            imu_rotation=imu.rotation.copy(),
            imu_velocity=np.array(imu_velocity.linear),
            imu_angular_velocity=np.array(imu_velocity.angular),
            joint_velocities=np.array(joint_velocities, dtype=float),
        )

    def estimated_state(
        self,
        readings: SensorReadings,
        relative: KinematicsPass,
        rotation: np.ndarray,
        angular_velocity: np.ndarray,
        position: np.ndarray,
        velocity: np.ndarray,
        in_contact: np.ndarray,
        omega: float,
        ground_tilt: np.ndarray | None = None,
    ) -> EstimatedState:
        """The world state of a base pose and twist and the robot's relative kinematics.

        Args:
            readings: The readings of this tick (kept in the state, wrenches used).
            relative: The kinematics pass of the same readings.
            rotation: Base orientation in the world, shape (3, 3).
            angular_velocity: Base angular velocity, base frame, shape (3,), in [rad/s].
            position: Base position, world frame, shape (3,), in [m].
            velocity: Base linear velocity, world frame, shape (3,), in [m/s].
            in_contact: Contact state of the left and right feet.
            omega: LIPM natural frequency sqrt(g / h) [1/s] of the DCM.
            ground_tilt: Gravity's tilt in the world (:class:`EstimatedState`), shape (2,);
                None: a level floor.
        """
        com = position + rotation @ relative.com
        com_velocity = velocity + rotation @ (
            cross_rows(angular_velocity, relative.com) + relative.com_velocity
        )
        sole_positions = position + relative.foot_positions @ rotation.T
        sole_rotations = rotation @ relative.foot_rotations
        feet = [
            self._foot_contact(wrench, sole_positions[i], sole_rotations[i], bool(in_contact[i]))
            for i, wrench in enumerate(readings.wrenches)
        ]
        total, weighted = 0.0, np.zeros(3)  # CoP of both feet, weighted by vertical force
        for foot in feet:
            if foot.in_contact and foot.force[2] > 0.0 and not math.isnan(foot.cop[0]):
                total += float(foot.force[2])
                weighted += float(foot.force[2]) * foot.cop
        has_cop = total > 0.0
        cop = freeze(weighted / total) if has_cop else _NAN3
        joints = readings.joint_positions
        if joints.flags.writeable:
            joints = frozen_array(joints)
        joint_velocities = frozen_array(relative.joint_velocities)
        quaternion = pin.Quaternion(rotation).normalized()
        q = np.concatenate([position, quaternion.coeffs(), joints])
        v = np.concatenate([velocity @ rotation, angular_velocity, joint_velocities])
        roll, pitch, yaw = rpy_of(rotation)
        return EstimatedState(
            time=float(readings.time),
            source="estimator",
            sensors=readings,
            q=freeze(q),
            v=freeze(v),
            base_position=frozen_array(position),
            base_rotation=frozen_array(rotation),
            base_linear_velocity=frozen_array(velocity),
            roll=roll,
            pitch=pitch,
            yaw=yaw,
            left_foot=feet[0],
            right_foot=feet[1],
            cop=cop,
            has_cop=has_cop,
            com=freeze(com),
            com_velocity=freeze(com_velocity),
            dcm=freeze(com[:2] + com_velocity[:2] / omega),
            joint_positions=joints,
            joint_velocities=joint_velocities,
            sole_positions=freeze(sole_positions),
            sole_rotations=freeze(sole_rotations),
            **({} if ground_tilt is None else {"ground_tilt": frozen_array(ground_tilt)}),
        )

    @staticmethod
    def _foot_contact(
        wrench: ForceTorqueReading,
        sole_position: np.ndarray,
        sole_rotation: np.ndarray,
        in_contact: bool,
    ) -> FootContact:
        """A foot's wrench and CoP in the world, from its sole-frame reading.

        The CoP of a wrench (force f, torque tau about the sole origin, sole frame) on the
        sole surface is ``(-tau_y / f_z, tau_x / f_z, 0)`` in the sole frame.
        """
        force = np.asarray(wrench.force, dtype=float)
        torque = np.asarray(wrench.torque, dtype=float)
        cop = _NAN3
        if in_contact and force[2] > 0.0:
            local = np.array((-torque[1] / force[2], torque[0] / force[2], 0.0))
            cop = freeze(sole_position + sole_rotation @ local)
        return FootContact(
            force=freeze(sole_rotation @ force),
            torque=freeze(sole_rotation @ torque),
            cop=cop,
            in_contact=in_contact,
        )


__all__ = ["IMU_FRAME", "BaseKinematics", "KinematicsPass", "cross_rows", "rpy_of"]
