"""A robot's walking defaults: the ``[gait]`` table of its preset, read in one place.

Every module that needs a robot's step timing, step height, leg reach, MPC horizon or
feedback gains takes them from :class:`GaitDefaults`; none reads the preset's table itself,
so a default is written once and a misspelled key is refused when the preset is loaded.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.leg_limits import LegLimits

_LEG_LIMIT_KEYS = (
    "max_step_forward",
    "max_step_backward",
    "max_step_lateral",
    "max_step_yaw",
    "max_step_yaw_inward",
    "y_sep",
    "half_stance_width",
)
_INTEGER_KEYS = ("mpc_horizon",)


@dataclass(frozen=True)
class GaitDefaults:
    """Walking defaults of one robot (the ``[gait]`` table of its preset).

    A field left at ``None`` is not set by the preset: the component that uses it keeps its
    own default (the generator's MPC horizon, the controller's feedback gains, the
    :class:`~mpcwalk.footsteps.LegLimits` defaults, the half stance width of the nominal
    posture).
    """

    step_duration: float = 0.5  # [s] T, one step (paper M, Table 1)
    double_support_ratio: float = 0.2  # r_ds = T_ds / T (paper M, Table 1)
    step_height: float = 0.04  # [m] z_step, top of the swing-foot arc (paper M, Table 1)
    max_step_forward: float | None = None  # [m] leg reach per step, forward
    max_step_backward: float | None = None  # [m] leg reach per step, backward
    max_step_lateral: float | None = None  # [m] leg reach per step, outward
    max_step_yaw: float | None = None  # [rad] outward turn per step
    max_step_yaw_inward: float | None = None  # [rad] inward turn per step
    y_sep: float | None = None  # [m] half of the minimum separation of the sole centres
    half_stance_width: float | None = None  # [m] sole centres from the torso line
    mpc_sampling_period: float | None = None  # [s] MPC sampling period
    mpc_horizon: int | None = None  # number of MPC samples
    mpc_jerk_weight: float | None = None  # weight of the jerk in the MPC cost
    dcm_gain: float | None = None  # DCM feedback gain of the controller [1]
    observer_gain: float | None = None  # share of the measured CoM state per tick [1]

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if value is None:
                continue
            if f.name in _INTEGER_KEYS:
                if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                    raise ConfigurationError(
                        f"[gait] {f.name} must be a positive integer, got {value!r}"
                    )
                continue
            checked_number(f"[gait] {f.name}", value, low=0.0)
        if self.step_duration <= 0.0:
            raise ConfigurationError(
                f"[gait] step_duration must be positive, got {self.step_duration!r} s"
            )
        if not 0.0 <= self.double_support_ratio < 1.0:
            raise ConfigurationError(
                f"[gait] double_support_ratio must be in [0, 1), got {self.double_support_ratio!r}"
            )

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        """The keys a ``[gait]`` table may hold."""
        return tuple(f.name for f in fields(cls))

    @classmethod
    def from_table(cls, table: Mapping[str, Any], *, source: str = "preset") -> GaitDefaults:
        """Read a ``[gait]`` table; unknown keys are refused with the valid names.

        Raises:
            ConfigurationError: An unknown key, or a value of the wrong type or range.
        """
        unknown = sorted(set(table) - set(cls.keys()))
        if unknown:
            raise ConfigurationError(
                f"{source}: unknown [gait] key(s) {', '.join(unknown)}; "
                f"valid keys: {', '.join(cls.keys())}"
            )
        values = dict(table)
        for key, value in values.items():
            if key not in _INTEGER_KEYS and isinstance(value, int) and not isinstance(value, bool):
                values[key] = float(value)
        try:
            return cls(**values)
        except ConfigurationError as error:
            raise ConfigurationError(f"{source}: {error}") from None

    def leg_limits(self, half_stance_width: float) -> LegLimits:
        """The robot's :class:`LegLimits`: the table's values, ``half_stance_width`` (of the
        nominal posture) where the table has none, and the defaults for the rest."""
        values: dict[str, float] = {"half_stance_width": float(half_stance_width)}
        for key in _LEG_LIMIT_KEYS:
            value = getattr(self, key)
            if value is not None:
                values[key] = float(value)
        values.setdefault("y_sep", min(LegLimits().y_sep, values["half_stance_width"]))
        return LegLimits(**values)
