"""What a walking controller may read of the robot each tick: sensors and measured state.

These types sit below the controller so that it reads typed fields, never a simulator's
object: :class:`mpcwalk.sim.Simulation` fills a :class:`Measurements` in every control
period (its ground truth, :class:`mpcwalk.sim.SimState`, stays in the simulator), and a real
robot's drivers would fill the same. All arrays are read-only.
"""

from dataclasses import dataclass

import numpy as np

from mpcwalk.models.com_state import ComState


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
    """What a controller may read: sensors, contact wrenches, measured CoP, CoM and soles.

    Attributes:
        imu: IMU readings (with sensor noise, if any).
        left_foot: Contact of the left sole.
        right_foot: Contact of the right sole.
        cop: Overall centre of pressure over the contact points of both feet (paper M eq.
            31), world frame, shape (3,), in [m]; NaN when ``has_cop`` is False.
        has_cop: Whether any foot is in contact (the CoP is defined).
        com: CoM position, shape (3,), in [m].
        com_velocity: CoM velocity, shape (3,), in [m/s].
        joint_positions: Joint encoders in Pinocchio order (``robot.joint_names``), in [rad]
            (with sensor noise, if any).
        joint_velocities: Joint velocities, same order, in [rad/s].
        sole_positions: Left and right sole frame origins, world frame, shape (2, 3), in [m].
        sole_rotations: Left and right sole frame orientations, shape (2, 3, 3).
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
    sole_positions: np.ndarray
    sole_rotations: np.ndarray

    @property
    def feet(self) -> tuple[FootContact, FootContact]:
        """Left and right foot contacts."""
        return self.left_foot, self.right_foot

    @property
    def total_force(self) -> np.ndarray:
        """Sum of the contact forces on both feet, world frame, shape (3,), in [N]."""
        return self.left_foot.force + self.right_foot.force

    @property
    def sole_yaws(self) -> np.ndarray:
        """Heading of the left and right soles, shape (2,), in [rad]."""
        return np.arctan2(self.sole_rotations[:, 1, 0], self.sole_rotations[:, 0, 0])

    def com_state(self) -> ComState:
        """Horizontal CoM state for a pattern generator (acceleration left unknown)."""
        return ComState(position=self.com[:2], velocity=self.com_velocity[:2])
