"""Orientation of the IMU from its gyroscope and accelerometer: a Mahony complementary filter.

The filter integrates the gyroscope (bias removed) on SO(3) and pulls the estimated vertical
towards the direction of the specific force the accelerometer reads (Mahony, Hamel and
Pflimlin 2008, "Nonlinear complementary filters on the special orthogonal group", IEEE TAC
53(5), the "explicit complementary filter" with bias estimation). Gravity only observes roll
and pitch: the heading is the integral of the gyroscope and drifts with its residual bias.

The accelerometer reads gravity only when the IMU does not accelerate: the caller may give
the IMU's linear acceleration known otherwise (a walking robot's, from its leg kinematics),
which is removed from the reading first. What is left is trusted less as its norm departs
from g, down to zero at a relative departure of ``accelerometer_tolerance``. While the robot
stands at the start (the first ``bias_window`` seconds), the heading part of the gyroscope's
bias is the mean of its readings; the integral gain estimates the roll and pitch part.
"""

import math

import numpy as np
import pinocchio as pin

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError, NotReset


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a x b`` of 3-vectors (np.cross is slow on small arrays)."""
    return np.array(
        (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    )


def _check_non_negative(name: str, value: float, unit: str) -> float:
    return checked_number(name, value, low=0.0, unit=unit)


class AttitudeFilter:
    """Orientation of the IMU frame in the world, from its gyroscope and accelerometer.

    Args:
        gravity: Norm of gravity g [m/s^2].
        gain: Proportional gain k_P of the accelerometer correction [rad/s]: the tilt error
            decays with the time constant ``1 / gain`` [s].
        integral_gain: Integral gain k_I of the bias estimate [rad/s^2 per unit error].
        accelerometer_tolerance: Relative departure of the accelerometer norm from g at which
            its correction weight reaches zero (0.2: readings outside 0.8 g .. 1.2 g are not
            trusted).
        bias_window: Time [s] after :meth:`reset` during which the heading part of the
            gyroscope bias is averaged (the robot must stand still then); 0 disables it.
        still_rate: Angular speed [rad/s] below which a tick of the bias window counts as
            standing still.

    Raises:
        ConfigurationError: A negative or non-finite parameter, or a tolerance of zero.
    """

    def __init__(
        self,
        *,
        gravity: float = 9.81,
        gain: float = 0.3,
        integral_gain: float = 0.05,
        accelerometer_tolerance: float = 0.2,
        bias_window: float = 0.0,
        still_rate: float = 0.1,
    ) -> None:
        if not (math.isfinite(gravity) and gravity > 0.0):
            raise ConfigurationError(f"gravity must be > 0 m/s^2, got {gravity!r}.")
        if not (math.isfinite(accelerometer_tolerance) and accelerometer_tolerance > 0.0):
            raise ConfigurationError(
                "accelerometer_tolerance must be a relative departure > 0 (e.g. 0.2), got "
                f"{accelerometer_tolerance!r}."
            )
        self.gravity = float(gravity)
        self.gain = _check_non_negative("gain", gain, "rad/s")
        self.integral_gain = _check_non_negative("integral_gain", integral_gain, "rad/s^2")
        self.accelerometer_tolerance = float(accelerometer_tolerance)
        self.bias_window = _check_non_negative("bias_window", bias_window, "s")
        self.still_rate = _check_non_negative("still_rate", still_rate, "rad/s")
        self._rotation: np.ndarray | None = None
        self._bias = np.zeros(3)
        self._gyro_sum = np.zeros(3)
        self._nb_still = 0
        self._elapsed = 0.0
        self._nb_updates = 0

    @property
    def rotation(self) -> np.ndarray:
        """Estimated orientation of the IMU frame in the world, shape (3, 3) (a copy)."""
        return self._checked_rotation().copy()

    @property
    def bias(self) -> np.ndarray:
        """Estimated gyroscope bias, IMU frame, shape (3,), in [rad/s] (a copy)."""
        return self._bias.copy()

    def reset(self, rotation: np.ndarray, *, bias: np.ndarray | None = None) -> None:
        """Start from ``rotation`` (IMU frame in the world), with a known bias or none.

        Args:
            rotation: Initial orientation, shape (3, 3).
            bias: Initial gyroscope bias [rad/s], shape (3,); None for zero. The bias window
                replaces its heading part by the average of the gyroscope.
        """
        self._rotation = np.array(rotation, dtype=float).reshape(3, 3)
        self._bias = np.zeros(3) if bias is None else np.array(bias, dtype=float).reshape(3)
        self._gyro_sum = np.zeros(3)
        self._nb_still = 0
        self._elapsed = 0.0
        self._nb_updates = 0

    def accelerometer_weight(self, accelerometer: np.ndarray) -> float:
        """Trust in ``accelerometer`` as a gravity reading, in [0, 1]."""
        norm = math.sqrt(float(accelerometer @ accelerometer))
        departure = abs(norm - self.gravity) / (self.accelerometer_tolerance * self.gravity)
        return max(0.0, 1.0 - departure)

    def corrected_gyro(self, gyro: np.ndarray) -> np.ndarray:
        """``gyro`` minus the estimated bias, IMU frame, shape (3,), in [rad/s]."""
        return gyro - self._bias

    def predict(self, gyro: np.ndarray, dt: float) -> np.ndarray:
        """Integrate one gyroscope reading (bias removed) over ``dt``.

        Args:
            gyro: Angular velocity, IMU frame, shape (3,), in [rad/s].
            dt: Time since the previous reading [s] (0: nothing to integrate).

        Returns:
            The orientation of the IMU frame in the world, shape (3, 3) (the filter's own
            array: copy it to keep it).

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        rotation = self._checked_rotation()
        self._collect_bias(gyro, dt, rotation[2])
        if dt > 0.0:
            self._rotate(rotation, (gyro - self._bias) * dt)
        return self._checked_rotation()

    def correct(
        self, accelerometer: np.ndarray, dt: float, *, acceleration: np.ndarray | None = None
    ) -> np.ndarray:
        """Pull the estimated vertical towards gravity as the accelerometer reads it.

        Args:
            accelerometer: Specific force, IMU frame, shape (3,), in [m/s^2].
            dt: Time since the previous reading [s].
            acceleration: The IMU's linear acceleration as known otherwise (e.g. from the leg
                kinematics), world frame, shape (3,), in [m/s^2]: removed from the specific
                force before it is compared with gravity. None: the IMU is taken as not
                accelerating.

        Returns:
            The orientation of the IMU frame in the world, shape (3, 3) (the filter's own
            array: copy it to keep it).

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        rotation = self._checked_rotation()
        gravity = accelerometer if acceleration is None else accelerometer - acceleration @ rotation
        weight = self.accelerometer_weight(gravity)
        if weight > 0.0 and dt > 0.0:
            measured_up = gravity / math.sqrt(float(gravity @ gravity))
            estimated_up = rotation[2]  # R^T e_z: the world vertical in the IMU frame
            error = weight * _cross(measured_up, estimated_up)
            if self._elapsed >= self.bias_window:
                self._bias -= self.integral_gain * error * dt
            self._rotate(rotation, self.gain * error * dt)
        return self._checked_rotation()

    def correct_vertical(self, measured_up: np.ndarray, dt: float, gain: float) -> np.ndarray:
        """Pull the estimated vertical towards one measured otherwise (e.g. through the leg
        kinematics from a foot flat on the floor); the bias is left to the accelerometer.

        Args:
            measured_up: The world's vertical in the IMU frame, shape (3,), unit norm.
            dt: Time since the previous reading [s].
            gain: Gain [rad/s]: the tilt error decays with the time constant ``1 / gain``.

        Returns:
            The orientation of the IMU frame in the world, shape (3, 3) (the filter's own
            array: copy it to keep it).

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        rotation = self._checked_rotation()
        if gain > 0.0 and dt > 0.0:
            self._rotate(rotation, gain * dt * _cross(measured_up, rotation[2]))
        return self._checked_rotation()

    def update(
        self,
        gyro: np.ndarray,
        accelerometer: np.ndarray,
        dt: float,
        *,
        acceleration: np.ndarray | None = None,
    ) -> np.ndarray:
        """:meth:`predict` with the gyroscope, then :meth:`correct` with the accelerometer.

        Returns:
            The orientation of the IMU frame in the world, shape (3, 3) (the filter's own
            array: copy it to keep it).
        """
        self.predict(gyro, dt)
        return self.correct(accelerometer, dt, acceleration=acceleration)

    def _rotate(self, rotation: np.ndarray, angle: np.ndarray) -> None:
        """Turn the orientation by the rotation vector ``angle`` [rad] in the IMU frame."""
        rotation = rotation @ pin.exp3(angle)
        self._nb_updates += 1
        if self._nb_updates % 200 == 0:  # re-orthonormalise against round-off
            rotation = pin.Quaternion(rotation).normalized().matrix()
        self._rotation = rotation

    def _collect_bias(self, gyro: np.ndarray, dt: float, up: np.ndarray) -> None:
        """Average the gyroscope's vertical component over the bias window.

        Only the heading rate is averaged: a robot settling on its feet pitches and rolls a
        little but does not turn, and the accelerometer observes the roll and pitch part of
        the bias anyway (the integral gain).
        """
        if self._elapsed >= self.bias_window:
            return
        self._elapsed += dt
        if float(np.max(np.abs(gyro))) < self.still_rate:
            self._gyro_sum += gyro
            self._nb_still += 1
            vertical = float(self._gyro_sum @ up) / self._nb_still
            self._bias += (vertical - float(self._bias @ up)) * up

    def _checked_rotation(self) -> np.ndarray:
        if self._rotation is None:
            raise NotReset("AttitudeFilter.update was called before reset; call reset first.")
        return self._rotation


def tilt_from_accelerometer(up: np.ndarray) -> tuple[float, float]:
    """Roll and pitch [rad] (Z-Y-X Euler angles) of a frame in which the world's vertical
    reads ``up`` (any norm), e.g. an accelerometer at rest rotated into that frame."""
    roll = math.atan2(float(up[1]), float(up[2]))
    pitch = math.atan2(-float(up[0]), math.hypot(float(up[1]), float(up[2])))
    return roll, pitch


__all__ = ["AttitudeFilter", "tilt_from_accelerometer"]
