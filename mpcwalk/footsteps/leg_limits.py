"""Per-step reach of the legs (paper M's leg limits, the planner's and the MPCs' input)."""

from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.reachability import ReachabilityRectangle


@dataclass(frozen=True)
class LegLimits:
    """Per-step reach of the legs, in the support-foot frame.

    Defaults fit the small servo humanoid of paper M (legs about 0.2 m long,
    T = 0.5 s, so 0.1 m/s forward is 0.05 m per step). With T = 0.5 s they
    admit commands up to vx in [-0.08, 0.16] m/s, |vy| <= 0.06 m/s and
    |vyaw| <= 0.55 rad/s (31.5 deg/s); see
    :meth:`~mpcwalk.footsteps.velocity_planner.VelocityPlanner.check_command`.

    Attributes:
        max_step_forward: Landing ahead of the support foot, in [m]
            (0.08 m: 0.16 m/s at T = 0.5 s, a stride of 0.16 m between
            consecutive positions of the swing foot).
        max_step_backward: Landing behind the support foot, in [m] (half of
            forward: the knee bends one way).
        max_step_lateral: Landing outward beyond the nominal stance, in [m]
            (0.04 m: the hip-roll range of such robots).
        max_step_yaw: Outward toe turn relative to the support foot, in [rad]
            (0.35 rad, about 20 deg: the hip-yaw range).
        max_step_yaw_inward: Inward toe turn, in [rad]. An inward turn swings
            the toe towards the other foot by about ``length/2 * sin(yaw)``:
            0.2 rad moves the toe of the 0.10 m foot 0.01 m, half of the 0.02 m
            gap between 0.06 m wide soles at the minimum separation.
        y_sep: Half of the minimum separation of the sole centres, in [m]
            (paper M, Table 1: 0.04 m in simulation).
        half_stance_width: Nominal lateral distance of each foot from the
            torso, in [m].
    """

    max_step_forward: float = 0.08  # [m]
    max_step_backward: float = 0.04  # [m]
    max_step_lateral: float = 0.04  # [m]
    max_step_yaw: float = 0.35  # [rad]
    max_step_yaw_inward: float = 0.2  # [rad]
    y_sep: float = 0.04  # [m]
    half_stance_width: float = 0.05  # [m]

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not np.isfinite(value) or value < 0.0:
                raise ConfigurationError(
                    f"LegLimits.{name} must be a non-negative number, got {value!r}."
                )
        if not 0.0 < self.y_sep <= self.half_stance_width:
            raise ConfigurationError(
                f"LegLimits needs 0 < y_sep <= half_stance_width, got y_sep={self.y_sep:g} m and "
                f"half_stance_width={self.half_stance_width:g} m; the nominal stance must respect "
                "the minimum separation."
            )

    def rectangle(self) -> ReachabilityRectangle:
        """The same limits as a reachability rectangle (LEFT swing over RIGHT support)."""
        return ReachabilityRectangle(
            x_min=-self.max_step_backward,
            x_max=self.max_step_forward,
            y_min=2.0 * self.y_sep,
            y_max=2.0 * self.half_stance_width + self.max_step_lateral,
            yaw_min=-self.max_step_yaw_inward,
            yaw_max=self.max_step_yaw,
        )
