"""Fall detection: the base too low or too tilted ends a run early and says why."""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.sim.sim_state import SimState


@dataclass(frozen=True)
class FallStatus:
    """Verdict of a :class:`FallDetector`.

    Attributes:
        fell: Whether the robot has fallen.
        reason: Why (base height or tilt against its threshold); empty when it has not.
        time: Simulated time of the verdict [s].
    """

    fell: bool
    reason: str
    time: float

    def __bool__(self) -> bool:
        return self.fell


class FallDetector:
    """Declares a fall when the base drops or tilts beyond a threshold.

    Args:
        nominal_base_height: Base height above the ground when standing [m] (``robot.q0[2]``).
        min_base_height_ratio: Fall when the base height drops below this fraction of the
            nominal height.
        max_tilt_deg: Fall when the angle between the base z axis and the vertical exceeds
            this [deg].

    Raises:
        ConfigurationError: A threshold outside its range.
    """

    def __init__(
        self,
        nominal_base_height: float,
        *,
        min_base_height_ratio: float = 0.5,
        max_tilt_deg: float = 45.0,
    ) -> None:
        if not (math.isfinite(nominal_base_height) and nominal_base_height > 0.0):
            raise ConfigurationError(
                f"nominal_base_height must be > 0 m, got {nominal_base_height!r}."
            )
        if not 0.0 < min_base_height_ratio < 1.0:
            raise ConfigurationError(
                f"min_base_height_ratio must lie in (0, 1), got {min_base_height_ratio!r}."
            )
        if not 0.0 < max_tilt_deg < 180.0:
            raise ConfigurationError(f"max_tilt_deg must lie in (0, 180), got {max_tilt_deg!r}.")
        self.nominal_base_height = float(nominal_base_height)
        self.min_base_height_ratio = float(min_base_height_ratio)
        self.max_tilt_deg = float(max_tilt_deg)

    @classmethod
    def for_robot(cls, robot, **thresholds) -> "FallDetector":
        """Detector with the base height of ``robot.q0`` (soles on the ground) as nominal."""
        return cls(float(robot.q0[2]), **thresholds)

    @property
    def min_base_height(self) -> float:
        """Base height [m] below which the robot has fallen."""
        return self.min_base_height_ratio * self.nominal_base_height

    def check(self, state: SimState) -> FallStatus:
        """Whether the robot in ``state`` has fallen, and why."""
        if not (np.all(np.isfinite(state.q)) and np.all(np.isfinite(state.v))):
            return FallStatus(True, "the simulation state is not finite", state.time)
        height = float(state.base_position[2])
        if height < self.min_base_height:
            return FallStatus(
                True,
                f"base height {height:.3f} m below {self.min_base_height:.3f} m "
                f"({self.min_base_height_ratio:g} x nominal {self.nominal_base_height:.3f} m)",
                state.time,
            )
        tilt_deg = math.degrees(state.base_tilt)
        if tilt_deg > self.max_tilt_deg:
            return FallStatus(
                True, f"base tilt {tilt_deg:.1f} deg above {self.max_tilt_deg:g} deg", state.time
            )
        return FallStatus(False, "", state.time)
