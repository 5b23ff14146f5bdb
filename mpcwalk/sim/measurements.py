"""What the simulation reports each tick: sensor readings and ground-truth state.

All arrays are read-only copies: a :class:`SimState` is a snapshot that later steps of the
simulation never change.
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.generators.pattern_generator import ComState


def quaternion_to_rpy(quaternion_wxyz: np.ndarray) -> tuple[float, float, float]:
    """Roll, pitch, yaw [rad] (Z-Y-X Euler angles) of a unit quaternion (w, x, y, z)."""
    w, x, y, z = (float(c) for c in quaternion_wxyz)
    norm2 = w * w + x * x + y * y + z * z
    roll = math.atan2(2.0 * (w * x + y * z), norm2 - 2.0 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x) / norm2)))
    yaw = math.atan2(2.0 * (w * z + x * y), norm2 - 2.0 * (y * y + z * z))
    return roll, pitch, yaw


@dataclass(frozen=True)
class ImuReading:
    """Readings of the IMU site (on the robot's base or torso).

    Attributes:
        gyro: Angular velocity in the IMU frame, shape (3,), in [rad/s].
        accelerometer: Specific force in the IMU frame, shape (3,), in [m/s^2] (reads +g
            upwards at rest).
        quaternion: Orientation of the IMU frame in the world, (w, x, y, z).
        roll: Z-Y-X Euler angle about x [rad].
        pitch: Z-Y-X Euler angle about y [rad].
        yaw: Z-Y-X Euler angle about z [rad].
    """

    gyro: np.ndarray
    accelerometer: np.ndarray
    quaternion: np.ndarray
    roll: float
    pitch: float
    yaw: float


@dataclass(frozen=True)
class FootContact:
    """Contact wrench of one foot, summed over the contact points of its sole geoms.

    Attributes:
        force: Force the ground exerts on the foot, world frame, shape (3,), in [N].
        torque: Moment of the contact forces about the sole frame origin, world axes,
            shape (3,), in [N m].
        cop: Centre of pressure ``sum p_i f_z,i / sum f_z,i`` (paper M eq. 31), world
            frame, shape (3,), in [m]; NaN when the foot is not in contact.
        in_contact: Whether the vertical force exceeds the contact threshold.
        nb_points: Number of active contact points.
    """

    force: np.ndarray
    torque: np.ndarray
    cop: np.ndarray
    in_contact: bool
    nb_points: int

    @property
    def normal_force(self) -> float:
        """Vertical contact force [N]."""
        return float(self.force[2])


@dataclass(frozen=True)
class Measurements:
    """What a controller may read: sensors, contact wrenches, measured CoP and CoM.

    Attributes:
        imu: IMU readings (with sensor noise, if any).
        left_foot: Contact of the left sole.
        right_foot: Contact of the right sole.
        cop: Overall centre of pressure over the contact points of both feet (paper M eq.
            31), world frame, shape (3,), in [m]; NaN when ``has_cop`` is False.
        has_cop: Whether any foot is in contact (the CoP is defined).
        com: CoM position (MuJoCo ``subtree_com`` of the floating base), shape (3,), in [m].
        com_velocity: CoM velocity, shape (3,), in [m/s].
        joint_positions: Joint encoders in Pinocchio order (``robot.joint_names``), in [rad]
            (with sensor noise, if any).
        joint_velocities: Joint velocities, same order, in [rad/s].
    """

    imu: ImuReading
    left_foot: FootContact
    right_foot: FootContact
    cop: np.ndarray
    has_cop: bool
    com: np.ndarray
    com_velocity: np.ndarray
    joint_positions: np.ndarray
    joint_velocities: np.ndarray

    @property
    def feet(self) -> tuple[FootContact, FootContact]:
        """Left and right foot contacts."""
        return self.left_foot, self.right_foot

    @property
    def total_force(self) -> np.ndarray:
        """Sum of the contact forces on both feet, world frame, shape (3,), in [N]."""
        return self.left_foot.force + self.right_foot.force

    def com_state(self) -> ComState:
        """Horizontal CoM state for a pattern generator (acceleration left unknown)."""
        return ComState(position=self.com[:2], velocity=self.com_velocity[:2])


@dataclass(frozen=True)
class SimState:
    """Snapshot of the simulation after a control period.

    Attributes:
        time: Simulated time [s].
        q: Configuration in Pinocchio's convention (base quaternion x, y, z, w).
        v: Velocity in Pinocchio's convention (base linear velocity in the base frame).
        base_position: Floating-base origin in the world, shape (3,), in [m].
        base_rotation: Floating-base orientation in the world, shape (3, 3).
        sole_positions: Left and right sole frame origins, shape (2, 3), in [m].
        sole_rotations: Left and right sole frame orientations, shape (2, 3, 3).
        measurements: Sensor readings, contacts, CoP and CoM.
    """

    time: float
    q: np.ndarray
    v: np.ndarray
    base_position: np.ndarray
    base_rotation: np.ndarray
    sole_positions: np.ndarray
    sole_rotations: np.ndarray
    measurements: Measurements

    @property
    def base_tilt(self) -> float:
        """Angle between the base z axis and the world vertical [rad]."""
        return float(np.arccos(np.clip(self.base_rotation[2, 2], -1.0, 1.0)))

    @property
    def sole_yaws(self) -> np.ndarray:
        """Heading of the left and right soles, shape (2,), in [rad]."""
        return np.arctan2(self.sole_rotations[:, 1, 0], self.sole_rotations[:, 0, 0])
