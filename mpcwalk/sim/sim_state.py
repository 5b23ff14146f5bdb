"""What the simulation reports each tick: ground truth, sensor readings and the oracle.

A :class:`SimState` carries the simulator's ground truth (configuration, velocity, base and
sole poses: for the metrics and the fall detector), what the robot senses
(:class:`~mpcwalk.robot.sensors.SensorReadings`, with the noise, bias, quantisation and
latency of the sensor model) and the ground truth in the type the controller receives
(:class:`~mpcwalk.estimation.estimated_state.EstimatedState`, ``source="oracle"``), for the
explicit ``state="oracle"`` comparison only.

All arrays are read-only copies: a :class:`SimState` is a snapshot that later steps of the
simulation never change.
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.robot.sensors import SensorReadings


def quaternion_to_rpy(quaternion_wxyz: np.ndarray) -> tuple[float, float, float]:
    """Roll, pitch, yaw [rad] (Z-Y-X Euler angles) of a unit quaternion (w, x, y, z)."""
    w, x, y, z = np.asarray(quaternion_wxyz, dtype=float).tolist()
    norm2 = w * w + x * x + y * y + z * z
    roll = math.atan2(2.0 * (w * x + y * z), norm2 - 2.0 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x) / norm2)))
    yaw = math.atan2(2.0 * (w * z + x * y), norm2 - 2.0 * (y * y + z * z))
    return roll, pitch, yaw


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
        sensors: What the robot's sensors report at this tick (IMU, encoders, foot
            force/torque sensors), taken ``latency`` control periods earlier, with the
            sensor model's noise, bias and quantisation: the estimator's input.
        oracle: The ground truth as the controller's state type (``source="oracle"``, its
            ``sensors`` the exact readings of this time): for the metrics, or for the
            controller behind an explicit ``state="oracle"``.
    """

    time: float
    q: np.ndarray
    v: np.ndarray
    base_position: np.ndarray
    base_rotation: np.ndarray
    sole_positions: np.ndarray
    sole_rotations: np.ndarray
    sensors: SensorReadings
    oracle: EstimatedState

    @property
    def base_tilt(self) -> float:
        """Angle between the base z axis and the world vertical [rad]."""
        return float(np.arccos(min(max(self.base_rotation[2, 2], -1.0), 1.0)))

    @property
    def sole_yaws(self) -> np.ndarray:
        """Heading of the left and right soles, shape (2,), in [rad]."""
        return np.arctan2(self.sole_rotations[:, 1, 0], self.sole_rotations[:, 0, 0])


__all__ = ["SimState", "quaternion_to_rpy"]
