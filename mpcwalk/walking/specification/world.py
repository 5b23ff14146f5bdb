"""What a simulated walk senses and how its world differs from the model: :class:`WorldSpec`.

The simulated robot is a real one in these ways:

- the sensors: the robot's sensor model (:class:`~mpcwalk.sim.sensing.model.SensorModel`:
  IMU noise and bias, encoder quantisation and noise, foot force/torque noise) scaled by
  ``noise_scale``, with a sensing-to-actuation ``latency``; ``ideal`` sensors (exact and
  immediate) on request;
- where the controller's state comes from: the estimator (from the sensors, the default) or
  the simulator's ground truth (``state="oracle"``, for comparison);
- the :class:`~mpcwalk.sim.model_mismatch.ModelMismatch` of the simulated robot (torso mass, CoM
  offset, friction, servo strength), never applied to the controller's model;
- the :class:`~mpcwalk.robot.ground.Ground` (tilt, bumps), the controller's model staying on
  a level floor;
- the robot's actuators (``actuation``): the position servos of its description, or torque
  motors driven by the whole-body inverse dynamics (:mod:`mpcwalk.sim.actuation`,
  :class:`~mpcwalk.control.torque_controller.TorqueController`);
- the :class:`~mpcwalk.terrain.Terrain` (stairs, slopes, platforms, stepping stones, rough
  patches laid along the robot's initial heading), built into the simulated scene; the
  walk's set-up checks that it fits the robot.

``ideal=True`` is the simulator before sensing: exact sensors, no latency and, unless
``state`` says otherwise, the controller reading the ground truth.
"""

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from mpcwalk.estimation.estimated_state import SOURCES
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.ground import Ground
from mpcwalk.sim.actuation import check_actuation
from mpcwalk.sim.model_mismatch import ModelMismatch
from mpcwalk.terrain import Terrain, terrain_from_dict

if TYPE_CHECKING:
    from mpcwalk.robot.robot import Robot
    from mpcwalk.sim.sensing.model import SensorModel


@dataclass(frozen=True)
class WorldSpec:
    """Sensors, state source, the simulated robot's departure from the model, the ground.

    Attributes:
        noise_scale: Factor on every noise and bias of the robot's sensor model (0: exact
            sensors, 1: the model's levels, 2: twice them), >= 0.
        latency: Sensing-to-actuation latency [s], a multiple of the control period, >= 0;
            None: the sensor model's (one control period).
        ideal: Exact sensors without latency (the simulator before sensing); excludes a
            ``noise_scale`` other than 1 and a ``latency``.
        state: Where the controller's state comes from: ``"estimator"`` (the sensors) or
            ``"oracle"`` (the simulator's ground truth of the current time); None:
            ``"oracle"`` with ``ideal`` sensors, else ``"estimator"``.
        mass_scale: Factor on the torso mass of the simulated robot.
        com_offset: Shift ``(dx, dy)`` [m] of the torso's CoM of the simulated robot.
        friction: Friction coefficient of the floor contacts (None: the model's).
        servo_strength: Factor on the servos' gains and torque limits.
        friction_cone: The simulator's friction cone, ``"pyramidal"`` or ``"elliptic"`` (None:
            MuJoCo's default pyramid, every stored result's).
        impratio: MuJoCo's frictional-to-normal impedance ratio (None: the model's, 1);
            ``friction_cone="elliptic", impratio=10`` keeps loaded soles from creeping on
            slopes (:class:`~mpcwalk.sim.model_mismatch.ModelMismatch`).
        ground_tilt: Slope of the ground [deg], up towards ``ground_tilt_direction``.
        ground_tilt_direction: Azimuth of the uphill direction [deg] (0: forward, 90: left).
        ground_roughness: Largest height of the ground's random bumps [m] (0: flat).
        terrain: The terrain (:class:`~mpcwalk.terrain.Terrain`, or the tables of a terrain
            file as a dict, read as one); None, or a terrain without features: the level
            floor.
        actuation: ``"position"`` (the robot's position servos, fed by the IK) or
            ``"torque"`` (torque motors with the robot's torque limits, fed by the whole-body
            inverse dynamics).

    Raises:
        ConfigurationError: A value out of its range (the model mismatch's and the ground's
            own errors name the range), ``ideal`` with a noise scale or a latency, or a
            terrain with a rough ground (:class:`~mpcwalk.exceptions.TerrainError`: a terrain
            that is not one).
    """

    noise_scale: float = 1.0
    latency: float | None = None
    ideal: bool = False
    state: str | None = None
    mass_scale: float = 1.0
    com_offset: tuple[float, float] = (0.0, 0.0)
    friction: float | None = None
    servo_strength: float = 1.0
    friction_cone: str | None = None
    impratio: float | None = None
    ground_tilt: float = 0.0
    ground_tilt_direction: float = 0.0
    ground_roughness: float = 0.0
    terrain: Terrain | None = None
    actuation: str = "position"

    def __post_init__(self) -> None:
        if not (
            isinstance(self.noise_scale, (int, float))
            and not isinstance(self.noise_scale, bool)
            and math.isfinite(self.noise_scale)
            and self.noise_scale >= 0.0
        ):
            raise ConfigurationError(
                f"noise_scale must be a finite number >= 0, got {self.noise_scale!r}; "
                "0 gives exact sensors, 1 the robot's sensor model."
            )
        object.__setattr__(self, "noise_scale", float(self.noise_scale))
        if self.latency is not None and not (
            isinstance(self.latency, (int, float))
            and not isinstance(self.latency, bool)
            and math.isfinite(self.latency)
            and self.latency >= 0.0
        ):
            raise ConfigurationError(
                f"latency must be a number of seconds >= 0 (or None for the sensor model's "
                f"one control period), got {self.latency!r}."
            )
        if not isinstance(self.ideal, bool):
            raise ConfigurationError(f"ideal must be true or false, got {self.ideal!r}.")
        if self.ideal and (self.noise_scale != 1.0 or self.latency is not None):
            raise ConfigurationError(
                "ideal sensors have no noise and no latency: give ideal=True (--ideal) alone, "
                f"not with noise_scale={self.noise_scale!r} or latency={self.latency!r}."
            )
        if self.state is None:
            object.__setattr__(self, "state", "oracle" if self.ideal else "estimator")
        if self.state not in SOURCES:
            raise ConfigurationError(
                f"state must be one of {', '.join(SOURCES)}, got {self.state!r}; 'estimator' "
                "walks on the sensors, 'oracle' on the simulator's ground truth."
            )
        object.__setattr__(self, "com_offset", _pair(self.com_offset))
        self.model_mismatch  # noqa: B018 - its checks, now
        self.ground(seed=0)  # likewise
        object.__setattr__(self, "terrain", _terrain(self.terrain))
        check_actuation(self.actuation)
        if self.terrain is not None and self.ground_roughness != 0.0:
            raise ConfigurationError(
                f"A terrain and ground_roughness = {self.ground_roughness!r} do not go together "
                "(the bumps lie on the level floor, under the terrain's blocks); lay a [[rough]] "
                "patch in the terrain instead."
            )

    @property
    def model_mismatch(self) -> ModelMismatch:
        """How the simulated robot differs from the controller's model."""
        return ModelMismatch(
            mass_scale=self.mass_scale,
            com_offset=self.com_offset,
            friction=self.friction,
            servo_strength=self.servo_strength,
            friction_cone=self.friction_cone,
            impratio=self.impratio,
        )

    def ground(self, *, seed: int) -> Ground:
        """The simulated ground; its bumps are drawn with ``seed``."""
        return Ground(
            self.ground_tilt, self.ground_tilt_direction, self.ground_roughness, seed=seed
        )

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
        """The robot's sensor model in this world (noise scale, latency, ideal)."""
        from mpcwalk.sim.sensing.model import SensorModel

        model = SensorModel.for_robot(robot)
        if self.ideal:
            return model.ideal()
        model = model.scaled(float(self.noise_scale))
        periods = self.latency_periods(control_period)
        return model if periods is None else model.with_latency(periods)

    def to_config(self, robot: "Robot", control_period: float, seed: int) -> dict[str, Any]:
        """The entries of the ``config`` block of ``metrics.json``
        (:class:`~mpcwalk.walking.result.WalkConfig`): ``state_source``, ``ideal_sensors``,
        ``noise_scale``, ``sensors`` (the simulated sensor model's figures), ``latency_s``
        (the latency the controller's state had: 0 on the oracle), ``model_mismatch`` (with
        the ground's ``ground_*`` keys that differ from the level floor) and ``seed``."""
        sensors = self.sensor_model(robot, control_period)
        return {
            "state_source": self.state,
            "ideal_sensors": bool(self.ideal),
            "noise_scale": float(self.noise_scale),
            "sensors": sensors.to_dict(),
            # the oracle is the exact state of the current time: no latency
            "latency_s": 0.0 if self.state == "oracle" else sensors.latency * control_period,
            "model_mismatch": {
                **self.model_mismatch.to_dict(),
                **self.ground(seed=seed).changes(),
            },
            "seed": int(seed),
        }


def _terrain(value: Any) -> Terrain | None:
    """The terrain of a walk: None for the level floor."""
    if isinstance(value, dict):
        value = terrain_from_dict(value, source="[world.terrain]")
    if value is not None and not isinstance(value, Terrain):
        raise ConfigurationError(
            f"terrain must be a Terrain, the tables of a terrain file or None, got {value!r}; "
            "e.g. terrain=mpcwalk.terrain.read_terrain('stairs.toml')."
        )
    return None if value is None or value.is_flat else value


def _pair(value: Any) -> tuple[float, float]:
    """``(dx, dy)`` of a CoM offset [m], from a sequence of two numbers."""
    try:
        dx, dy = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ConfigurationError(
            f"com_offset must be two numbers (dx, dy) in [m], got {value!r}; e.g. (0.01, 0.0)."
        ) from None
    return dx, dy


__all__ = ["WorldSpec"]
