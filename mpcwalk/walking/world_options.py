"""What a simulated walk senses and how its world differs from the model: :class:`WorldOptions`.

The options of :func:`~mpcwalk.walking.runner.run_walk` (and ``mpcwalk walk``) that make the
simulated robot a real one, in one typed place, validated once:

- the sensors: the robot's sensor model (:class:`~mpcwalk.sim.sensor_model.SensorModel`:
  IMU noise and bias, encoder quantisation and noise, foot force/torque noise) scaled by
  ``noise_scale``, with a sensing-to-actuation ``latency``; ``ideal`` sensors (exact and
  immediate) on request;
- where the controller's state comes from: the estimator (from the sensors, the default) or
  the simulator's ground truth (``state="oracle"``, for comparison);
- the :class:`~mpcwalk.sim.perturbation.Perturbation` of the simulated robot (torso mass, CoM
  offset, friction, servo strength), never applied to the controller's model;
- the :class:`~mpcwalk.robot.ground.Ground` (tilt, bumps), the controller's model staying on
  a level floor;
- the seed of the sensor noise.

``ideal=True`` is the old behaviour of the simulator: exact sensors, no latency and, unless
``state`` says otherwise, the controller reading the ground truth.
"""

import dataclasses
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from mpcwalk.estimation.estimated_state import SOURCES
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.ground import Ground
from mpcwalk.sim.perturbation import Perturbation

if TYPE_CHECKING:
    from mpcwalk.robot.robot import Robot
    from mpcwalk.sim.sensor_model import SensorModel


@dataclass(frozen=True)
class WorldOptions:
    """Sensors, state source, perturbation and seed of a simulated walk.

    Attributes:
        noise_scale: Factor on every noise and bias of the robot's sensor model (0: exact
            sensors, 1: the model's levels, 2: twice them), >= 0.
        latency: Sensing-to-actuation latency [s], a multiple of the control period, >= 0;
            None: the sensor model's (one control period).
        ideal: Exact sensors without latency (the old simulator); excludes ``noise_scale``
            other than 1 and a ``latency``.
        state: Where the controller's state comes from: ``"estimator"`` (the sensors) or
            ``"oracle"`` (the simulator's ground truth of the current time: the sensor noise
            and the latency then reach the controller no more).
        perturbation: How the simulated robot differs from the controller's model.
        seed: Seed of the sensor noise and of the ground's bumps (same seed, same walk).
        ground: Tilt and bumps of the simulated ground (its seed is ``seed``).

    Raises:
        ConfigurationError: A value out of its range, or ``ideal`` with a noise scale or a
            latency.
    """

    noise_scale: float = 1.0
    latency: float | None = None
    ideal: bool = False
    state: str = "estimator"
    perturbation: Perturbation = field(default_factory=Perturbation)
    seed: int = 0
    ground: Ground = field(default_factory=Ground)

    def __post_init__(self) -> None:
        if not (isinstance(self.noise_scale, (int, float)) and math.isfinite(self.noise_scale)):
            raise ConfigurationError(
                f"noise_scale must be a finite number >= 0, got {self.noise_scale!r}; "
                "0 gives exact sensors, 1 the robot's sensor model."
            )
        if self.noise_scale < 0.0:
            raise ConfigurationError(
                f"noise_scale must be >= 0, got {self.noise_scale!r}; 0 gives exact sensors, "
                "1 the robot's sensor model."
            )
        if self.latency is not None and not (
            isinstance(self.latency, (int, float))
            and math.isfinite(self.latency)
            and self.latency >= 0.0
        ):
            raise ConfigurationError(
                f"latency must be a number of seconds >= 0 (or None for the sensor model's "
                f"one control period), got {self.latency!r}."
            )
        if self.ideal and (self.noise_scale != 1.0 or self.latency is not None):
            raise ConfigurationError(
                "ideal sensors have no noise and no latency: give ideal=True (--ideal) alone, "
                f"not with noise_scale={self.noise_scale!r} or latency={self.latency!r}."
            )
        if self.state not in SOURCES:
            raise ConfigurationError(
                f"state must be one of {', '.join(SOURCES)}, got {self.state!r}; 'estimator' "
                "walks on the sensors, 'oracle' on the simulator's ground truth."
            )
        if not isinstance(self.perturbation, Perturbation):
            raise ConfigurationError(
                "perturbation must be a mpcwalk.sim.perturbation.Perturbation, got "
                f"{type(self.perturbation).__name__}; build one with Perturbation(mass_scale=...)."
            )
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ConfigurationError(f"seed must be an integer >= 0, got {self.seed!r}.")
        if not isinstance(self.ground, Ground):
            raise ConfigurationError(
                "ground must be a mpcwalk.robot.ground.Ground, got "
                f"{type(self.ground).__name__}; build one with Ground(tilt=..., roughness=...)."
            )

    @classmethod
    def build(
        cls,
        *,
        noise_scale: float = 1.0,
        latency: float | None = None,
        ideal: bool = False,
        state: str | None = None,
        perturbation: Perturbation | None = None,
        mass_scale: float | None = None,
        com_offset: tuple[float, float] | None = None,
        friction: float | None = None,
        servo_strength: float | None = None,
        seed: int = 0,
        ground_tilt: float = 0.0,
        ground_tilt_direction: float = 0.0,
        ground_roughness: float = 0.0,
    ) -> "WorldOptions":
        """The options from the keywords of :func:`~mpcwalk.walking.runner.run_walk`.

        ``state`` None is ``"oracle"`` with ``ideal`` sensors, else ``"estimator"``. The
        perturbation is given either whole (``perturbation``) or by its keywords
        (``mass_scale``, ``com_offset`` (dx, dy) [m], ``friction``, ``servo_strength``), not
        both. The ground slopes up by ``ground_tilt`` [deg] towards the azimuth
        ``ground_tilt_direction`` [deg] and has bumps up to ``ground_roughness`` [m].

        Raises:
            ConfigurationError: Both a perturbation and its keywords, or a bad value.
        """
        keywords: dict[str, Any] = {
            name: value
            for name, value in (
                ("mass_scale", mass_scale),
                ("com_offset", com_offset),
                ("friction", friction),
                ("servo_strength", servo_strength),
            )
            if value is not None
        }
        if perturbation is not None and keywords:
            raise ConfigurationError(
                f"Give a Perturbation or its keywords ({', '.join(keywords)}), not both: "
                "put them into the Perturbation."
            )
        if perturbation is None:
            if "com_offset" in keywords:
                keywords["com_offset"] = _pair(keywords["com_offset"])
            perturbation = Perturbation(**keywords)
        if state is None:
            state = "oracle" if ideal else "estimator"
        options = cls(
            noise_scale=noise_scale,
            latency=latency,
            ideal=ideal,
            state=state,
            perturbation=perturbation,
            seed=seed,
        )  # the seed checked, it draws the ground's bumps
        ground = Ground(ground_tilt, ground_tilt_direction, ground_roughness, seed=seed)
        return dataclasses.replace(options, ground=ground)

    def latency_periods(self, control_period: float) -> int | None:
        """The latency in control periods (None: the sensor model's default).

        Raises:
            ConfigurationError: A latency that is not a multiple of ``control_period``.
        """
        if self.ideal:
            return 0
        if self.latency is None:
            return None
        periods = round(self.latency / control_period)
        if abs(periods * control_period - self.latency) > 1e-9:
            raise ConfigurationError(
                f"latency = {self.latency:g} s is not a multiple of the control period "
                f"{control_period:g} s; choose e.g. {periods * control_period:g} s."
            )
        return int(periods)

    def sensor_model(self, robot: "Robot", control_period: float) -> "SensorModel":
        """The robot's sensor model with these options (noise scale, latency, ideal)."""
        from mpcwalk.sim.sensor_model import SensorModel

        model = SensorModel.for_robot(robot)
        if self.ideal:
            return model.ideal()
        model = model.scaled(float(self.noise_scale))
        periods = self.latency_periods(control_period)
        return model if periods is None else model.with_latency(periods)

    def to_config(self, robot: "Robot", control_period: float) -> dict[str, Any]:
        """The entries of the ``config`` block of ``metrics.json``
        (:class:`~mpcwalk.walking.result.WalkConfig`): ``state_source``, ``ideal_sensors``,
        ``noise_scale``, ``sensors`` (the simulated sensor model's figures), ``latency_s``
        (the latency the controller's state had: 0 on the oracle), ``perturbation`` (with
        the ground's ``ground_*`` keys that differ from the level floor) and ``seed``."""
        sensors = self.sensor_model(robot, control_period)
        return {
            "state_source": self.state,
            "ideal_sensors": bool(self.ideal),
            "noise_scale": float(self.noise_scale),
            "sensors": sensors.to_dict(),
            # the oracle is the exact state of the current time: no latency
            "latency_s": 0.0 if self.state == "oracle" else sensors.latency * control_period,
            "perturbation": {
                **self.perturbation.to_dict(),
                **self.ground.changes(),
            },
            "seed": int(self.seed),
        }


def _pair(value: Any) -> tuple[float, float]:
    """``(dx, dy)`` of a CoM offset [m], from a sequence of two numbers."""
    try:
        dx, dy = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ConfigurationError(
            f"com_offset must be two numbers (dx, dy) in [m], got {value!r}; e.g. (0.01, 0.0)."
        ) from None
    return dx, dy
