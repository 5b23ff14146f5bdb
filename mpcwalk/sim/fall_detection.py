"""Fall detection: the base too low or too tilted ends a run early and says why.

The base's height is measured from the ground under the robot: the level floor z = 0, or on
a :class:`~mpcwalk.terrain.Terrain` the lowest ground under its base and its soles (a robot
standing on a stair is as high above its ground as on the floor; one lying across the steps
is low above the lowest of them).
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.sim.sim_state import SimState
from mpcwalk.terrain import Terrain


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
        terrain: The ground the robot walks on; None for the level floor z = 0.

    Raises:
        ConfigurationError: A threshold outside its range.
    """

    def __init__(
        self,
        nominal_base_height: float,
        *,
        min_base_height_ratio: float = 0.5,
        max_tilt_deg: float = 45.0,
        terrain: Terrain | None = None,
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
        self.terrain = None if terrain is None or terrain.is_flat else terrain

    @classmethod
    def for_robot(cls, robot, *, terrain: Terrain | None = None, **thresholds) -> "FallDetector":
        """Detector with the base height of ``robot.q0`` (soles on the ground) as nominal, on
        ``terrain`` (None: the level floor)."""
        return cls(float(robot.q0[2]), terrain=terrain, **thresholds)

    @property
    def min_base_height(self) -> float:
        """Base height [m] below which the robot has fallen."""
        return self.min_base_height_ratio * self.nominal_base_height

    def ground_height(self, state: SimState) -> float:
        """Height [m] of the ground the base's height is measured from: 0 on the level
        floor, else the lowest ground under the base and the soles."""
        if self.terrain is None:
            return 0.0
        points = np.vstack([np.asarray(state.base_position)[:2], state.sole_positions[:, :2]])
        return float(np.min(self.terrain.height(points[:, 0], points[:, 1])))

    def check(self, state: SimState) -> FallStatus:
        """Whether the robot in ``state`` has fallen, and why."""
        if not (np.isfinite(state.q).all() and np.isfinite(state.v).all()):
            return FallStatus(True, "the simulation state is not finite", state.time)
        ground = self.ground_height(state)
        height = float(state.base_position[2]) - ground
        if height < self.min_base_height:
            above = f" above the ground at {ground:.3f} m" if self.terrain is not None else ""
            return FallStatus(
                True,
                f"base height {height:.3f} m{above} below {self.min_base_height:.3f} m "
                f"({self.min_base_height_ratio:g} x nominal {self.nominal_base_height:.3f} m)",
                state.time,
            )
        tilt_deg = math.degrees(state.base_tilt)
        if tilt_deg > self.max_tilt_deg:
            return FallStatus(
                True, f"base tilt {tilt_deg:.1f} deg above {self.max_tilt_deg:g} deg", state.time
            )
        return FallStatus(False, "", state.time)
