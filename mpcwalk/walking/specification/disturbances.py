"""What happens to a walk from outside: :class:`DisturbanceSpec` (pushes, sensor faults)."""

import math
from dataclasses import dataclass
from typing import Any

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.sim.sensing.faults import SensorFaults

Push = tuple[float, float, float, float, float]
"""A push on the torso: start [s], duration [s], world force (fx, fy, fz) [N]."""


@dataclass(frozen=True)
class DisturbanceSpec:
    """Pushes on the torso and faults of the sensor stream during a walk.

    Attributes:
        pushes: Pushes on the torso (:data:`Push`); an
            :class:`~mpcwalk.sim.pushes.ExternalForce` on the torso is taken too.
        sensor_nan: ``(start, end)`` windows [s] in which every sensor reading is NaN.
        sensor_dropout: ``(start, end)`` windows [s] in which no reading arrives.
        yaw_reference: With pushes, also walk the same walk without them and report
            ``metrics.yaw_deviation_deg``, the largest yaw difference after the last push
            (paper M's measure of its stabilizer); doubles the cost.

    Raises:
        ConfigurationError: A push that is not five finite numbers with a start >= 0 and a
            positive duration, or a fault window that is not ``0 <= start < end``.
    """

    pushes: tuple[Push, ...] = ()
    sensor_nan: tuple[tuple[float, float], ...] = ()
    sensor_dropout: tuple[tuple[float, float], ...] = ()
    yaw_reference: bool = False

    def __post_init__(self) -> None:
        if isinstance(self.pushes, (str, bytes)):
            raise ConfigurationError(
                f"pushes must be a list of (start, duration, fx, fy, fz), got {self.pushes!r}; "
                "e.g. [(3.0, 0.1, 10.0, 0.0, 0.0)]."
            )
        object.__setattr__(self, "pushes", tuple(_push(push) for push in self.pushes))
        faults = self.sensor_faults  # checks the windows
        object.__setattr__(self, "sensor_nan", faults.nan)
        object.__setattr__(self, "sensor_dropout", faults.dropout)
        if not isinstance(self.yaw_reference, bool):
            raise ConfigurationError(
                f"yaw_reference must be true or false, got {self.yaw_reference!r}."
            )

    @property
    def sensor_faults(self) -> SensorFaults:
        """The faults injected into the sensor stream."""
        return SensorFaults(nan=self.sensor_nan, dropout=self.sensor_dropout)

    def external_forces(self) -> list:
        """The pushes as :class:`~mpcwalk.sim.pushes.ExternalForce` on the torso."""
        import numpy as np

        from mpcwalk.sim import ExternalForce

        return [
            ExternalForce(start, duration, np.array([fx, fy, fz], dtype=float))
            for start, duration, fx, fy, fz in self.pushes
        ]


def _push(value: Any) -> Push:
    """A push as five floats."""
    force = getattr(value, "force", None)
    if force is not None:  # an ExternalForce
        if (
            getattr(value, "body", "torso") != "torso"
            or value.point is not None
            or (value.torque is not None)
        ):
            raise ConfigurationError(
                "A walk's pushes act on the torso's centre of mass without torque; for other "
                "bodies, points or torques build a Simulation with the ExternalForce."
            )
        value = (value.start, value.duration, *(float(f) for f in force))
    try:
        numbers = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        numbers = ()
    if len(numbers) != 5 or not all(map(math.isfinite, numbers)):
        raise ConfigurationError(
            f"A push is five finite numbers (start [s], duration [s], fx, fy, fz [N]), got "
            f"{value!r}; e.g. (3.0, 0.1, 10.0, 0.0, 0.0)."
        )
    start, duration, fx, fy, fz = numbers
    if start < 0.0 or duration <= 0.0:
        raise ConfigurationError(
            f"A push needs a start >= 0 s and a duration > 0 s, got {value!r}."
        )
    return start, duration, fx, fy, fz


__all__ = ["DisturbanceSpec", "Push"]
