"""The inputs of :meth:`~mpcwalk.estimation.estimator.Estimator.reset` checked: named errors,
never a shape error deep in the estimator."""

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.sensors import SensorReadings


def checked_reset_inputs(
    model: pin.Model, readings: SensorReadings, q_initial: np.ndarray
) -> np.ndarray:
    """The initial configuration as a float array, once it and the readings fit ``model``.

    Raises:
        ConfigurationError: A configuration, joint positions or a reading of the wrong size
            or not finite.
    """

    q = np.asarray(q_initial, dtype=float)
    if q.shape != (model.nq,) or not np.all(np.isfinite(q)):
        raise ConfigurationError(
            f"Estimator.reset expects a finite initial configuration of size nq = "
            f"{model.nq}, got shape {q.shape}; pass the configuration the walk starts from."
        )
    joints = np.asarray(readings.joint_positions, dtype=float)
    if joints.shape != (model.nq - 7,) or not np.all(np.isfinite(joints)):
        raise ConfigurationError(
            f"The readings have {joints.shape} finite joint positions; the estimator "
            f"expects {model.nq - 7} in Pinocchio order (robot.joint_names)."
        )
    for name, vector in (
        ("gyro", readings.imu.gyro),
        ("accelerometer", readings.imu.accelerometer),
        ("left force", readings.left_wrench.force),
        ("left torque", readings.left_wrench.torque),
        ("right force", readings.right_wrench.force),
        ("right torque", readings.right_wrench.torque),
    ):
        if np.shape(vector) != (3,):
            raise ConfigurationError(
                f"The readings' {name} must have shape (3,), got {np.shape(vector)}."
            )
    return q


__all__ = ["checked_reset_inputs"]
