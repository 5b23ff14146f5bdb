"""A walk's step timing and its feet's sole (re-exported by :mod:`~mpcwalk.footsteps.footstep`)."""

from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError


@dataclass(frozen=True)
class StepTiming:
    """Timing of a walk (paper M sec. 3: each step starts and ends in double support).

    Attributes:
        step_duration: Duration ``T`` of one step (one foot moves), in [s].
        double_support_ratio: ``r_ds = T_ds / T`` in [0, 1); half of the double
            support opens the step, half closes it.
        initial_duration: Standing double support before the first step, in [s].
        final_duration: Double support after the last step, in [s].
    """

    step_duration: float = 0.5  # [s] (paper M, Table 1)
    double_support_ratio: float = 0.2  # [] (paper M, Table 1)
    initial_duration: float = 1.0  # [s]
    final_duration: float = 1.0  # [s]

    def __post_init__(self) -> None:
        T = self.step_duration
        if isinstance(T, (bool, str)) or not np.isfinite(T) or T <= 0.0 or T > 60.0:
            raise ConfigurationError(
                f"step_duration must be a number of seconds in (0, 60], got {T!r}; "
                "paper M uses 0.5 s, paper A 12 s."
            )
        r = self.double_support_ratio
        if not np.isfinite(r) or not 0.0 <= r < 1.0:
            raise ConfigurationError(
                f"double_support_ratio must lie in [0, 1), got {r!r}; it is the "
                "fraction of each step spent with both feet down (paper M: 0.2)."
            )
        for name in ("initial_duration", "final_duration"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0.0:
                raise ConfigurationError(
                    f"{name} must be a non-negative number of seconds, got {value!r}."
                )

    @property
    def single_support_begin(self) -> float:
        """``t_b = r_ds T / 2``: time in the step when single support begins, in [s]."""
        return 0.5 * self.double_support_ratio * self.step_duration

    @property
    def single_support_end(self) -> float:
        """``t_e = T - r_ds T / 2``: time in the step when single support ends, in [s]."""
        return self.step_duration - self.single_support_begin


@dataclass(frozen=True)
class FootGeometry:
    """Flat rectangular sole.

    Attributes:
        length: Along the foot x axis, in [m].
        width: Along the foot y axis, in [m].
    """

    length: float = 0.10  # [m] small servo humanoid
    width: float = 0.06  # [m]

    def __post_init__(self) -> None:
        if (
            not (np.isfinite(self.length) and np.isfinite(self.width))
            or min(self.length, self.width) <= 0.0
        ):
            raise ConfigurationError(
                f"Foot length and width must be positive, got {self.length!r} x {self.width!r} m."
            )
