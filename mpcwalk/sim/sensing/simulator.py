"""The readings a robot's sensors give: the truth with noise, bias, quantisation and latency.

:class:`SensorSimulator` turns the exact readings of each control period (from the
simulator's ground truth) into what the robot's drivers would report, following a
:class:`~mpcwalk.sim.sensing.model.SensorModel`:

- IMU: ``gyro = truth + bias + noise``, the bias a constant drawn at :meth:`reset` plus a
  random walk; the same for the accelerometer;
- encoders: ``resolution * round((truth + noise) / resolution)``;
- foot force/torque sensors (sole frame): ``truth + noise`` on each axis;
- joint torque sensors (torque motors only): ``truth + noise``, the noise a share of each
  joint's torque limit, drawn from a generator of its own (the other readings of a seed are
  the same with or without them);
- latency: the readings go through a FIFO of ``latency + 1`` readings; :meth:`read` returns
  the oldest. Before ``latency`` periods have passed it returns the first reading (the robot
  stood still before time 0).

Reproducible: :meth:`reset` restarts the random generator from the seed, so the same seed
gives the same readings, walk after walk.
"""

from collections import deque

import numpy as np

from mpcwalk._checks import freeze
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.sensors import ForceTorqueReading, ImuReading, SensorReadings
from mpcwalk.sim.sensing.model import SensorModel


class SensorSimulator:
    """Applies a sensor model to the exact readings of each control period.

    Args:
        model: The sensor model.
        period: Time between two readings (the control period) [s].
        nb_joints: Number of joint encoders.
        seed: Seed of the noise and biases (None: fresh entropy, drawn once here).
        torque_limits: Torque limit of each joint [N m] (the scale of the joint torque
            sensors' noise; an infinite limit gets none), shape (nb_joints,); None: no noise
            on them.

    Raises:
        ConfigurationError: A non-positive period, a negative number of joints or torque
            limits of the wrong shape.
    """

    def __init__(
        self,
        model: SensorModel,
        *,
        period: float,
        nb_joints: int,
        seed: int | None = None,
        torque_limits: np.ndarray | None = None,
    ) -> None:
        if not (np.isfinite(period) and period > 0.0):
            raise ConfigurationError(f"period must be > 0 s, got {period!r}.")
        if nb_joints < 0:
            raise ConfigurationError(f"nb_joints must be >= 0, got {nb_joints!r}.")
        self.model = model
        self.period = float(period)
        self.nb_joints = int(nb_joints)
        self._seed = np.random.SeedSequence(seed)
        self._rng = np.random.default_rng(self._seed)
        # standard deviations of one draw of 12 + nj + 12 normals: gyro and accelerometer
        # noise, gyro and accelerometer bias steps, encoders, left and right force/torque
        imu = (
            model.gyro_std(period),
            model.accelerometer_std(period),
            model.gyro_bias_random_walk * np.sqrt(period),
            model.accelerometer_bias_random_walk * np.sqrt(period),
        )
        wrench = (model.force_noise_std, model.torque_noise_std)
        self._std = np.concatenate(
            [
                np.repeat(imu, 3),
                np.full(nb_joints, model.encoder_noise_std),
                np.tile(np.repeat(wrench, 3), 2),
            ]
        )
        self._bias_std = np.repeat([model.gyro_bias_std, model.accelerometer_bias_std], 3)
        self._torque_std = np.zeros(self.nb_joints)
        if torque_limits is not None:
            limits = np.asarray(torque_limits, dtype=float)
            if limits.shape != (self.nb_joints,):
                raise ConfigurationError(
                    f"torque_limits must give one limit per joint, shape ({self.nb_joints},), "
                    f"got shape {limits.shape}."
                )
            finite = np.isfinite(limits)
            self._torque_std[finite] = model.joint_torque_noise * np.abs(limits[finite])
        self._torque_seed = self._seed.spawn(1)[0]
        self._torque_rng = np.random.default_rng(self._torque_seed)
        self._exact = model.is_exact
        self._bias = np.zeros(6)
        self._fifo: deque[SensorReadings] = deque(maxlen=model.latency + 1)

    @property
    def gyro_bias(self) -> np.ndarray:
        """Current gyroscope bias [rad/s], shape (3,)."""
        return self._bias[:3].copy()

    @property
    def accelerometer_bias(self) -> np.ndarray:
        """Current accelerometer bias [m/s^2], shape (3,)."""
        return self._bias[3:].copy()

    def reset(self, truth: SensorReadings) -> SensorReadings:
        """Restart a walk: the generator from the seed, the constant biases drawn from it
        (the same for the same seed), the FIFO filled with the reading of ``truth``.

        Returns:
            The reading of ``truth`` (what :meth:`read` gives until the latency has passed).
        """
        self._rng = np.random.default_rng(self._seed)
        self._torque_rng = np.random.default_rng(self._torque_seed)
        self._bias = self._bias_std * self._rng.standard_normal(6)
        reading = self._corrupt(truth)
        self._fifo.clear()
        self._fifo.extend([reading] * (self.model.latency + 1))
        return reading

    def read(self, truth: SensorReadings) -> SensorReadings:
        """Take the readings of ``truth`` (one control period after the previous ones) and
        return those of ``latency`` periods ago."""
        self._fifo.append(self._corrupt(truth))
        return self._fifo[0]

    def _corrupt(self, truth: SensorReadings) -> SensorReadings:
        """``truth`` with noise, bias and quantisation (advances the bias random walk)."""
        if self._exact:
            return truth
        model, nj = self.model, self.nb_joints
        draw = self._std * self._rng.standard_normal(self._std.shape[0])
        self._bias += draw[6:12]
        gyro = truth.imu.gyro + self._bias[:3] + draw[0:3]
        accelerometer = truth.imu.accelerometer + self._bias[3:] + draw[3:6]
        encoders = truth.joint_positions + draw[12 : 12 + nj]
        if model.encoder_resolution > 0.0:
            encoders = model.encoder_resolution * np.round(encoders / model.encoder_resolution)
        wrenches = draw[12 + nj :].reshape(2, 2, 3)  # (left, right) x (force, torque)
        left, right = (  # fresh arrays: frozen without a copy
            ForceTorqueReading(
                force=freeze(wrench.force + noise[0]), torque=freeze(wrench.torque + noise[1])
            )
            for wrench, noise in zip(truth.wrenches, wrenches)
        )
        torques = truth.joint_torques
        if torques is not None:
            draw = self._torque_rng.standard_normal(nj)
            torques = freeze(torques + self._torque_std * draw)
        return SensorReadings(
            time=truth.time,
            imu=ImuReading(gyro=freeze(gyro), accelerometer=freeze(accelerometer)),
            joint_positions=freeze(encoders),
            left_wrench=left,
            right_wrench=right,
            joint_torques=torques,
        )
