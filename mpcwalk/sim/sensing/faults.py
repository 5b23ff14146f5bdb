"""Faults injected into a walk's sensor stream: what the controller must survive.

Real sensor buses drop messages and drivers hand out garbage. :class:`SensorFaults` makes a
simulated walk do the same, through the fields of its specification
(``run_walk(WalkSpec.build(..., sensor_nan=[(2.0, 2.05)], sensor_dropout=[(3.0, 3.1)]))``):
during a ``nan`` window every reading (IMU, encoders, foot force/torque sensors, joint torque
sensors) is NaN;
during a ``dropout`` window no reading arrives. The control loop checks the readings at its
boundary (:func:`readings_are_finite`): a bad or missing one is a sensor fault, the
estimator is not updated with it and the controller keeps the last good estimate, for a
bounded number of ticks (:mod:`mpcwalk.control.faults`).
"""

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from mpcwalk._checks import all_finite
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.sensors import ForceTorqueReading, ImuReading, SensorReadings


def _windows(name: str, value: Sequence) -> tuple[tuple[float, float], ...]:
    windows = []
    for item in value:
        try:
            start, end = (float(x) for x in item)
        except (TypeError, ValueError):
            raise ConfigurationError(
                f"SensorFaults.{name} must be (start [s], end [s]) pairs, got {item!r}."
            ) from None
        if not (np.isfinite(start) and np.isfinite(end) and 0.0 <= start < end):
            raise ConfigurationError(
                f"SensorFaults.{name}: a window needs 0 <= start < end [s], got {item!r}."
            )
        windows.append((start, end))
    return tuple(windows)


@dataclass(frozen=True)
class SensorFaults:
    """Windows of time [s] in which the sensor stream is NaN or absent.

    Attributes:
        nan: ``(start, end)`` windows in which every reading is NaN.
        dropout: ``(start, end)`` windows in which no reading arrives.
    """

    nan: tuple[tuple[float, float], ...] = ()
    dropout: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "nan", _windows("nan", self.nan))
        object.__setattr__(self, "dropout", _windows("dropout", self.dropout))

    def apply(self, readings: SensorReadings) -> SensorReadings | None:
        """The readings as the controller's computer receives them: NaN, None (dropped) or
        unchanged."""
        t = readings.time
        if any(start <= t < end for start, end in self.dropout):
            return None
        if any(start <= t < end for start, end in self.nan):
            return _nan_readings(readings)
        return readings


def _nan_readings(readings: SensorReadings) -> SensorReadings:
    def nan(array) -> np.ndarray:
        return np.full(np.shape(array), np.nan)

    wrench = [
        ForceTorqueReading(nan(w.force), nan(w.torque))
        for w in (readings.left_wrench, readings.right_wrench)
    ]
    return replace(
        readings,
        imu=ImuReading(nan(readings.imu.gyro), nan(readings.imu.accelerometer)),
        joint_positions=nan(readings.joint_positions),
        left_wrench=wrench[0],
        right_wrench=wrench[1],
        joint_torques=None if readings.joint_torques is None else nan(readings.joint_torques),
    )


def readings_are_finite(readings: SensorReadings | None) -> bool:
    """Whether ``readings`` arrived and every value in them is finite."""
    if readings is None:
        return False
    values: tuple[np.ndarray, ...] = (
        readings.imu.gyro,
        readings.imu.accelerometer,
        readings.joint_positions,
        readings.left_wrench.force,
        readings.left_wrench.torque,
        readings.right_wrench.force,
        readings.right_wrench.torque,
    )
    if readings.joint_torques is not None:
        values = (*values, readings.joint_torques)
    return all_finite(values, (readings.time,))
