"""Gains of the balance stabilizer, with their units and why they are what they are."""

import math
from dataclasses import dataclass, fields

from mpcwalk.exceptions import ConfigurationError


@dataclass(frozen=True)
class BalanceOptions:
    """Parameters of :class:`~mpcwalk.control.stabilizers.balance.BalanceStabilizer`.

    Each part is off when its gain is 0. Lengths left at None are fractions of the robot's
    sole, resolved by :meth:`resolved` (the same options then fit a 2 kg and a 40 kg robot).

    Attributes:
        integral_gain: ``k_i`` [1/s] of the integral action on the DCM error: ZMP shift
            per metre-second of integrated error. With the proportional gain ``k_p`` of the
            DCM feedback (3 by default) the integral's slow pole is about
            ``k_i / (k_p - 1)`` [1/s]: 2 gives a bias removed in about a second, two steps.
        integral_leak_time: Leak time constant [s] of the integral (inf: none): what a push
            winds up is forgotten over this time; a constant bias keeps
            ``(k_p - 1) / (k_p - 1 + k_i T)`` of its error (1/11 with the defaults).
        integral_limit: Bound of the integral's ZMP shift per axis [m]; None: a quarter of
            the sole's width.
        damping_gain: ``K`` [rad/(m s)] of the foot damping: foot rotation rate per metre
            of weight-normalised CoP error (Caron's HRP-4 admittance is about 4).
        damping_time_constant: Leak time constant ``T`` [s] of the foot rotations.
        damping_max_offset: Bound of each foot rotation [rad].
        com_offset_time_constant: Time constant [s] of the CoM offset estimate (the CoP
            error is integrated over this time); 0 turns the estimate off. Several step
            durations, so that the CoP's swing from foot to foot averages out.
        com_offset_limit: Bound of the CoM offset estimate per axis [m]; None: a quarter of
            the sole's width.
        com_offset_dcm_threshold: The estimate moves only while the DCM error (low-pass
            filtered over a second) is below this [m]; None: a quarter of the sole's width
            (walking's own DCM error averages below it, a push's does not).
        ground_tilt: Lean into a tilted gravity (the estimated state's ``ground_tilt``):
            on a ground sloping by ``theta`` the pendulum's ZMP lies ``z_c tan(theta)``
            downhill of its CoM, so the robot's CoM is kept that far uphill of the model's
            plan (a CoM offset known from the accelerometer, beside the one learnt).
    """

    integral_gain: float = 2.0
    integral_leak_time: float = 10.0
    integral_limit: float | None = None
    damping_gain: float = 4.0
    damping_time_constant: float = 1.0
    damping_max_offset: float = 0.05
    com_offset_time_constant: float = 4.0
    com_offset_limit: float | None = None
    com_offset_dcm_threshold: float | None = None
    ground_tilt: bool = True

    def __post_init__(self) -> None:
        if not isinstance(self.ground_tilt, bool):
            raise ConfigurationError(
                f"BalanceOptions.ground_tilt must be True or False, got {self.ground_tilt!r}."
            )
        for item in fields(self):
            value = getattr(self, item.name)
            if item.name == "ground_tilt" or (value is None and item.name in _SOLE_FRACTIONS):
                continue
            number = isinstance(value, (int, float)) and not isinstance(value, bool)
            if not number or math.isnan(value) or value < 0.0:
                raise ConfigurationError(
                    f"BalanceOptions.{item.name} must be a non-negative number, got {value!r}."
                )
            if math.isinf(value) and item.name not in _MAY_BE_INFINITE:
                raise ConfigurationError(
                    f"BalanceOptions.{item.name} must be finite, got {value!r}."
                )
        if self.integral_leak_time == 0.0 or self.damping_time_constant == 0.0:
            raise ConfigurationError(
                "BalanceOptions leak times must be positive seconds (inf: no leak), got "
                f"integral_leak_time={self.integral_leak_time!r}, "
                f"damping_time_constant={self.damping_time_constant!r}."
            )

    def resolved(self, sole_size: tuple[float, float]) -> "BalanceOptions":
        """These options with every length left at None set from ``sole_size`` (length,
        width [m])."""
        width = float(min(sole_size))
        values = {
            name: width * fraction if getattr(self, name) is None else getattr(self, name)
            for name, fraction in _SOLE_FRACTIONS.items()
        }
        return BalanceOptions(
            **{item.name: getattr(self, item.name) for item in fields(self)} | values
        )


#: Lengths that default to a fraction of the sole's width (the smaller side).
_SOLE_FRACTIONS = {
    "integral_limit": 0.25,
    "com_offset_limit": 0.25,
    "com_offset_dcm_threshold": 0.25,
}
_MAY_BE_INFINITE = {"integral_leak_time", "damping_time_constant", "com_offset_dcm_threshold"}
