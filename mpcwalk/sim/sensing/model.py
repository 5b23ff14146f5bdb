"""How a robot's sensors differ from the truth: noise, bias, quantisation and latency.

A :class:`SensorModel` holds the figures of a robot's sensors (the simulator's
:class:`~mpcwalk.sim.sensing.simulator.SensorSimulator` applies them each control period):

- the IMU: gyroscope and accelerometer white noise (as datasheet noise densities), a constant
  bias drawn once per walk and a slow random walk of that bias;
- the joint encoders: quantisation (the resolution) and white noise;
- the foot force/torque sensors: white noise on the force and on the torque;
- the joint torque sensors of a torque-controlled robot: white noise, a share of each
  joint's torque limit;
- the sensing-to-actuation latency, in control periods: the controller acts on readings that
  many periods old.

:meth:`SensorModel.for_robot` picks the figures of a small servo humanoid or of a large
robot; :meth:`~SensorModel.scaled` multiplies every noise, bias and resolution (0: exact
sensors, the latency kept); :meth:`~SensorModel.ideal` is the exact, immediate sensor.

A white noise of density ``N`` read every ``dt`` seconds has the standard deviation
``N / sqrt(dt)`` per reading; a bias random walk of density ``B`` moves the bias by
``B sqrt(dt)`` per reading (the convention of IMU noise models, e.g. Kalibr's).
"""

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import SimulationModelError

if TYPE_CHECKING:
    from mpcwalk.robot.robot import Robot

SMALL_ROBOT_MASS = 5.0
"""Robots lighter than this [kg] get the small servo humanoid's sensors."""

MAX_LATENCY = 100
"""Largest latency [control periods] a model accepts (1 s at the default 10 ms period)."""

_DEG = math.pi / 180.0

# IMU, the same MEMS 6-axis IMU on every robot: Bosch Sensortec BMI088 data sheet
# (BST-BMI088-DS001): gyroscope noise density 0.014 deg/s/sqrt(Hz), bias stability 2 deg/h,
# zero-rate offset +-1 deg/s; accelerometer noise density 175 ug/sqrt(Hz), zero-g offset
# +-20 mg. The turn-on offsets are the raw chip's: a robot calibrates the gyro at standstill
# before it walks and its accelerometer once (six-position calibration), which leaves the
# residual biases below. The gyroscope's: averaging T seconds of standstill leaves the white
# noise's N / sqrt(T), 0.0063 deg/s for T = 5 s (the in-run bias stability, 2 deg/h = 0.0006
# deg/s, is ten times smaller); 0.01 deg/s keeps a margin for temperature drift. The bias random walks are those of a MEMS IMU of the same class
# calibrated in the EuRoC data set (Burri et al., IJRR 2016, ADIS16448 sensor.yaml: gyroscope
# random walk 1.9e-5 rad/s^2/sqrt(Hz), accelerometer random walk 3.0e-3 m/s^3/sqrt(Hz)).
_GYRO_NOISE_DENSITY = 0.014 * _DEG  # [rad/s/sqrt(Hz)]
_GYRO_BIAS_STD = 0.01 * _DEG  # [rad/s] residual after a 5 s standstill calibration
_GYRO_BIAS_RANDOM_WALK = 1.9e-5  # [rad/s^2/sqrt(Hz)]
_ACCELEROMETER_NOISE_DENSITY = 175e-6 * 9.81  # [m/s^2/sqrt(Hz)]
_ACCELEROMETER_BIAS_STD = 0.05  # [m/s^2] (5 mg) residual after calibration
_ACCELEROMETER_BIAS_RANDOM_WALK = 3.0e-3  # [m/s^3/sqrt(Hz)]


_FIX = "fix it, or start from SensorModel.for_robot(robot) and use scaled(x) or with_latency(n)"


def _error(field: str, value: Any) -> Callable[[str], Exception]:
    """The error of a bad ``field``, from what was expected."""
    return lambda expected: SimulationModelError("SensorModel", field, value, expected, _FIX)


@dataclass(frozen=True)
class SensorModel:
    """Noise, bias, quantisation and latency of a robot's sensors.

    The defaults are the large robots' sensors (high-resolution joint encoders, ATI
    Mini45-class 6-axis force/torque sensors at the ankles) with a MEMS IMU;
    :meth:`small_servo_humanoid` gives the small humanoid's. All figures are >= 0 (0: none).

    Attributes:
        gyro_noise_density: Gyroscope white noise [rad/s/sqrt(Hz)].
        gyro_bias_std: Standard deviation of the constant gyroscope bias drawn per walk
            (per axis) [rad/s].
        gyro_bias_random_walk: Random walk of the gyroscope bias [rad/s^2/sqrt(Hz)].
        accelerometer_noise_density: Accelerometer white noise [m/s^2/sqrt(Hz)].
        accelerometer_bias_std: Standard deviation of the constant accelerometer bias drawn
            per walk (per axis) [m/s^2].
        accelerometer_bias_random_walk: Random walk of the accelerometer bias
            [m/s^3/sqrt(Hz)].
        encoder_resolution: Quantisation step of the joint encoders [rad] (0: continuous).
        encoder_noise_std: White noise of the joint encoders before quantisation [rad].
        force_noise_std: White noise of each force axis of the foot sensors [N].
        torque_noise_std: White noise of each torque axis of the foot sensors [N m].
        joint_torque_noise: White noise of the joint torque sensors (torque motors only), as a
            share of each joint's torque limit (0.005: 0.5 % of it).
        latency: Sensing-to-actuation latency [control periods], an integer in
            [0, :data:`MAX_LATENCY`].

    Raises:
        SimulationModelError: A negative or non-finite figure, or a latency that is not an
            integer in range.
    """

    gyro_noise_density: float = _GYRO_NOISE_DENSITY
    gyro_bias_std: float = _GYRO_BIAS_STD
    gyro_bias_random_walk: float = _GYRO_BIAS_RANDOM_WALK
    accelerometer_noise_density: float = _ACCELEROMETER_NOISE_DENSITY
    accelerometer_bias_std: float = _ACCELEROMETER_BIAS_STD
    accelerometer_bias_random_walk: float = _ACCELEROMETER_BIAS_RANDOM_WALK
    # Joint encoders of the large robots: 17-bit absolute encoders on the joint output
    # (2 pi / 2^17 = 4.8e-5 rad), the class of the RLS AksIM-2 off-axis encoders (17 to 20
    # bit per turn) of torque-controlled humanoids; noise of one count.
    encoder_resolution: float = 2.0 * math.pi / 2**17  # [rad]
    encoder_noise_std: float = 2.0 * math.pi / 2**17  # [rad]
    # Ankle force/torque sensors of the large robots: ATI Mini45 (SI-580-20 calibration)
    # resolution 1/4 N on the forces and 1/188 N m on the torques; a walking robot's readings
    # are a few counts noisier (impacts, cable and temperature drift).
    force_noise_std: float = 0.5  # [N]
    torque_noise_std: float = 0.02  # [N m]
    # Joint torque sensors of a torque-controlled robot: strain gauges on the joint output,
    # or the deflection of a series-elastic spring, read as the output torque (what the
    # motor's torque constant and its gear's losses leave of the command). Their noise is a
    # share of the full scale: 0.5 %, the order of magnitude of the joint torque sensors of
    # torque-controlled arms and legs (no one datasheet; the full scale is the joint's torque
    # limit here).
    joint_torque_noise: float = 0.005  # [share of the torque limit]
    latency: int = 1  # [control periods]

    def __post_init__(self) -> None:
        for name in _NOISE_FIELDS:
            value = getattr(self, name)
            number = checked_number(name, value, low=0.0, error=_error(name, value))
            object.__setattr__(self, name, number)
        latency = self.latency
        if isinstance(latency, bool) or not isinstance(latency, int):
            raise _error("latency", latency)("a whole number of control periods")
        if not 0 <= latency <= MAX_LATENCY:
            raise _error("latency", latency)(f"between 0 and {MAX_LATENCY} control periods")

    @classmethod
    def large_robot(cls) -> "SensorModel":
        """The large robots' sensors (the defaults): MEMS IMU, 17-bit joint encoders, ATI
        Mini45-class ankle force/torque sensors, one period of latency."""
        return cls()

    @classmethod
    def small_servo_humanoid(cls) -> "SensorModel":
        """A small servo humanoid's sensors: MEMS IMU, Dynamixel AX-12 encoders, load-cell
        feet, one period of latency."""
        # Dynamixel AX-12A (ROBOTIS e-Manual): position feedback of 1024 steps over 300 deg,
        # resolution 0.29 deg; its potentiometer reading jitters by about one step.
        resolution = 300.0 / 1024.0 * _DEG  # [rad] 5.1e-3
        return cls(
            encoder_resolution=resolution,
            encoder_noise_std=0.5 * resolution,
            # Foot sensors of a small humanoid: four strain-gauge load cells of 5 kg full scale
            # under each sole (24-bit bridge ADC), the 6-axis wrench rebuilt from them. An
            # order of magnitude, no datasheet: 0.05 N per force axis, the torque that noise
            # makes on a 3 cm lever.
            force_noise_std=0.05,  # [N]
            torque_noise_std=0.0015,  # [N m]
            # A small humanoid driven by torques needs output torque sensors too; those of its
            # size are coarser than the large robots' (an order of magnitude, no datasheet).
            joint_torque_noise=0.02,
        )

    @classmethod
    def for_robot(cls, robot: "Robot") -> "SensorModel":
        """The sensors of ``robot``: the small servo humanoid's below
        :data:`SMALL_ROBOT_MASS`, the large robots' above."""
        if robot.total_mass < SMALL_ROBOT_MASS:
            return cls.small_servo_humanoid()
        return cls.large_robot()

    @classmethod
    def ideal(cls) -> "SensorModel":
        """Exact, immediate sensors: no noise, no bias, no quantisation, no latency."""
        return cls(**dict.fromkeys(_NOISE_FIELDS, 0.0), latency=0)

    @property
    def is_exact(self) -> bool:
        """Whether the readings are exact (no noise, bias or quantisation; any latency)."""
        return all(getattr(self, name) == 0.0 for name in _NOISE_FIELDS)

    def scaled(self, factor: float) -> "SensorModel":
        """This model with every noise, bias and resolution multiplied by ``factor`` (0:
        exact sensors); the latency is kept.

        Raises:
            SimulationModelError: A negative or non-finite factor.
        """
        scale = checked_number("factor", factor, low=0.0, error=_error("scaled(factor)", factor))
        return dataclasses.replace(
            self, **{name: getattr(self, name) * scale for name in _NOISE_FIELDS}
        )

    def with_latency(self, periods: int) -> "SensorModel":
        """This model with a latency of ``periods`` control periods."""
        return dataclasses.replace(self, latency=periods)

    def gyro_std(self, period: float) -> float:
        """Standard deviation of the gyroscope noise of one reading every ``period`` [s],
        in [rad/s]."""
        return self.gyro_noise_density / math.sqrt(period)

    def accelerometer_std(self, period: float) -> float:
        """Standard deviation of the accelerometer noise of one reading every ``period``
        [s], in [m/s^2]."""
        return self.accelerometer_noise_density / math.sqrt(period)

    def to_dict(self) -> dict[str, Any]:
        """The figures by name (SI units, latency in control periods)."""
        return dataclasses.asdict(self)


_NOISE_FIELDS = tuple(f.name for f in dataclasses.fields(SensorModel) if f.name != "latency")
