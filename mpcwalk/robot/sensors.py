"""What a robot's sensors give each tick, typed below the controller.

:class:`SensorReadings` are the raw readings a robot's drivers deliver: the IMU's angular
velocity and specific force, the joint encoders, the force/torque sensors of both feet and,
on a torque-controlled robot, the joint torque sensors.
The simulator (:class:`mpcwalk.sim.Simulation`) fills them with the noise, bias, quantisation
and latency of its sensor model; a real robot's drivers would fill the same. The state the
controller works on is estimated from them
(:class:`~mpcwalk.estimation.estimated_state.EstimatedState`). :class:`FootContact` is one
foot's contact as estimated (world frame). All arrays are read-only.
"""

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ImuReading:
    """Readings of the IMU (on the robot's base or torso), in the IMU's own frame.

    Attributes:
        gyro: Angular velocity, shape (3,), in [rad/s].
        accelerometer: Specific force, shape (3,), in [m/s^2] (reads +g upwards at rest).
    """

    gyro: np.ndarray
    accelerometer: np.ndarray


@dataclass(frozen=True)
class ForceTorqueReading:
    """Reading of one foot's 6-axis force/torque sensor, in the sole frame.

    Attributes:
        force: Force the ground exerts on the foot, sole frame, shape (3,), in [N].
        torque: Moment of the contact forces about the sole frame origin, sole frame,
            shape (3,), in [N m].
    """

    force: np.ndarray
    torque: np.ndarray

    @property
    def normal_force(self) -> float:
        """Force along the sole's normal [N]."""
        return float(self.force[2])


@dataclass(frozen=True)
class SensorReadings:
    """Everything the robot's sensors report at one time.

    Attributes:
        time: Time the readings were taken [s] (with a latency, earlier than the time they
            are used).
        imu: IMU readings.
        joint_positions: Joint encoders in Pinocchio order (``robot.joint_names``), in [rad].
        left_wrench: Left foot force/torque sensor.
        right_wrench: Right foot force/torque sensor.
        joint_torques: Joint torque sensors, the torque each actuator applies to its joint,
            same order as ``joint_positions``, in [N m]; None for a robot without them
            (position servos).
    """

    time: float
    imu: ImuReading
    joint_positions: np.ndarray
    left_wrench: ForceTorqueReading
    right_wrench: ForceTorqueReading
    joint_torques: np.ndarray | None = None

    @property
    def wrenches(self) -> tuple[ForceTorqueReading, ForceTorqueReading]:
        """Left and right force/torque readings."""
        return self.left_wrench, self.right_wrench


@dataclass(frozen=True)
class FootContact:
    """Contact of one foot, world frame (estimated from its force/torque sensor and the
    estimated sole pose, or the simulator's ground truth).

    Attributes:
        force: Force the ground exerts on the foot, world frame, shape (3,), in [N].
        torque: Moment of the contact forces about the sole frame origin, world axes,
            shape (3,), in [N m].
        cop: Centre of pressure of the foot, world frame, shape (3,), in [m]; NaN when the
            foot is not in contact.
        in_contact: Whether the foot is in contact.
    """

    force: np.ndarray
    torque: np.ndarray
    cop: np.ndarray
    in_contact: bool

    @property
    def normal_force(self) -> float:
        """Vertical contact force [N]."""
        return float(self.force[2])
