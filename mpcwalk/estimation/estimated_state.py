"""What the walking controller knows of the robot each tick: its estimated state.

An :class:`EstimatedState` is computed from the robot's sensors alone
(:class:`~mpcwalk.robot.sensors.SensorReadings`: IMU, joint encoders, foot force/torque
sensors) by :class:`~mpcwalk.estimation.estimator.Estimator`. For comparison, the simulator
can build the same type from its ground truth (``source="oracle"``); that path is taken only
behind an explicit switch (``state="oracle"``), never by default.

All arrays are read-only.
"""

from dataclasses import dataclass, field

import numpy as np

from mpcwalk.models.com_state import ComState
from mpcwalk.robot.sensors import FootContact, ImuReading, SensorReadings

_LEVEL = np.zeros(2)
_LEVEL.flags.writeable = False

#: Where an estimated state comes from.
SOURCES = ("estimator", "oracle")


@dataclass(frozen=True)
class EstimatedState:
    """The robot's state as the controller knows it.

    Attributes:
        time: Time of the sensor readings it was estimated from [s].
        source: ``"estimator"`` (from the sensors) or ``"oracle"`` (the simulator's ground
            truth, for comparison only).
        sensors: The raw readings of that time (IMU, encoders, foot force/torque sensors).
        q: Configuration in Pinocchio's convention (base position, base quaternion
            x, y, z, w, joint angles), shape (nq,).
        v: Velocity in Pinocchio's convention (base linear and angular velocity in the base
            frame, joint velocities), shape (nv,).
        base_position: Floating-base origin in the world, shape (3,), in [m].
        base_rotation: Floating-base orientation in the world, shape (3, 3).
        base_linear_velocity: Floating-base origin velocity, world frame, shape (3,), in
            [m/s].
        roll: Z-Y-X Euler angle of the base about x [rad].
        pitch: Z-Y-X Euler angle of the base about y [rad].
        yaw: Z-Y-X Euler angle of the base about z [rad].
        left_foot: Contact of the left sole (world frame).
        right_foot: Contact of the right sole (world frame).
        cop: Overall centre of pressure of both feet (paper M eq. 31), world frame, shape
            (3,), in [m]; NaN when ``has_cop`` is False.
        has_cop: Whether any foot is in contact (the CoP is defined).
        com: CoM position, world frame, shape (3,), in [m].
        com_velocity: CoM velocity, world frame, shape (3,), in [m/s].
        dcm: Horizontal divergent component of motion ``com + com_velocity / omega``, shape
            (2,), in [m].
        joint_positions: Joint angles in Pinocchio order (``robot.joint_names``), in [rad].
        joint_velocities: Joint velocities, same order, in [rad/s].
        sole_positions: Left and right sole frame origins, world frame, shape (2, 3), in [m].
        sole_rotations: Left and right sole frame orientations, shape (2, 3, 3).
        ground_tilt: Gravity's tilt in the world frame, the slope of the ground the feet
            stand on (the estimator's world is the soles' frame): the horizontal part of
            gravity's upward specific force over its vertical part, ``tan(tilt)`` towards
            the uphill azimuth, shape (2,); zeros on a level floor (the estimator's is zero
            within its deadband, see :class:`~mpcwalk.estimation.estimator.Estimator`).
    """

    time: float
    source: str
    sensors: SensorReadings
    q: np.ndarray
    v: np.ndarray
    base_position: np.ndarray
    base_rotation: np.ndarray
    base_linear_velocity: np.ndarray
    roll: float
    pitch: float
    yaw: float
    left_foot: FootContact
    right_foot: FootContact
    cop: np.ndarray
    has_cop: bool
    com: np.ndarray
    com_velocity: np.ndarray
    dcm: np.ndarray
    joint_positions: np.ndarray
    joint_velocities: np.ndarray
    sole_positions: np.ndarray
    sole_rotations: np.ndarray
    ground_tilt: np.ndarray = field(default_factory=lambda: _LEVEL)

    @property
    def imu(self) -> ImuReading:
        """The raw IMU reading of this tick."""
        return self.sensors.imu

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

    @property
    def base_tilt(self) -> float:
        """Angle between the base z axis and the world vertical [rad]."""
        return float(np.arccos(min(max(self.base_rotation[2, 2], -1.0), 1.0)))

    def com_state(self) -> ComState:
        """Horizontal CoM state for a pattern generator (acceleration left unknown)."""
        return ComState.trusted(
            np.array(self.com[:2], dtype=float), np.array(self.com_velocity[:2], dtype=float)
        )
