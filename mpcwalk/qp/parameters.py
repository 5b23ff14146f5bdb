"""Parameters of the walking MPC quadratic program."""

import dataclasses
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError


@dataclass(frozen=True)
class MpcParameters:
    """Horizon, weights and margins of the walking MPC (Wieber 2006).

    The cost summed over the ``horizon`` samples ``i = 1..N`` is::

        zmp_weight * ||Z - Z_ref||^2 + jerk_weight * ||U||^2
        + velocity_weight * ||V - V_ref||^2 + sum_i w_i ||C_i - C_ref_i||^2

    with ``w_i = com_weight`` (or 0 in double support when
    ``com_weight_single_support_only``). Weights are per sample and per axis.

    Attributes:
        sampling_period: Time between two samples of the horizon, in [s].
        horizon: Number of samples N (the horizon lasts N sampling periods).
        zmp_weight: Weight of the ZMP tracking error, in [1/m^2].
        jerk_weight: Weight of the CoM jerk, in [s^6/m^2].
        velocity_weight: Weight of the CoM velocity error, in [s^2/m^2].
        com_weight: Weight of the CoM tracking error, in [1/m^2].
        com_weight_single_support_only: Apply ``com_weight`` in single
            support only (zero in double support), so that the QP is free to
            choose when to shift the CoM inside double support.
        constrained: Add the support polygon inequalities; False gives an
            unconstrained QP (comparison with preview control).
        zmp_margin: Distance kept between the ZMP and the support polygon
            edges, in [m].
        com_margin: Distance kept between the CoM ground projection and the
            support polygon edges, in [m]; None leaves the CoM unconstrained.
        terminal_dcm: Also constrain the divergent component of motion at the
            last sample inside that sample's support polygon (shrunk by
            ``zmp_margin``): the plan must end capturable. A measured state
            that cannot be captured then makes the QP infeasible.
    """

    sampling_period: float = 0.1  # [s]
    horizon: int = 16  # [] samples (16 x 0.1 s = 1.6 s)
    zmp_weight: float = 1.0  # [1/m^2]
    jerk_weight: float = 1e-6  # [s^6/m^2]
    velocity_weight: float = 0.0  # [s^2/m^2]
    com_weight: float = 0.0  # [1/m^2]
    com_weight_single_support_only: bool = False
    constrained: bool = True
    zmp_margin: float = 0.0  # [m]
    com_margin: float | None = None  # [m], None: CoM not constrained
    terminal_dcm: bool = False

    def __post_init__(self) -> None:
        if not np.isfinite(self.sampling_period) or self.sampling_period <= 0.0:
            raise ConfigurationError(
                f"MpcParameters.sampling_period must be a positive number of seconds, "
                f"got {self.sampling_period!r}; 0.1 s is usual for walking MPC."
            )
        if isinstance(self.horizon, bool) or int(self.horizon) != self.horizon or self.horizon < 1:
            raise ConfigurationError(
                f"MpcParameters.horizon is a number of samples and must be an integer "
                f">= 1, got {self.horizon!r}; use MpcParameters.with_duration() to "
                "give it in seconds."
            )
        object.__setattr__(self, "horizon", int(self.horizon))
        for name in ("zmp_weight", "jerk_weight", "velocity_weight", "com_weight"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0.0:
                raise ConfigurationError(
                    f"MpcParameters.{name} must be a non-negative number, got {value!r}."
                )
        if self.jerk_weight <= 0.0:
            raise ConfigurationError(
                "MpcParameters.jerk_weight must be positive (it makes the QP strictly "
                f"convex), got {self.jerk_weight!r}; 1e-6 is a usual value."
            )
        for name in ("zmp_margin", "com_margin"):
            value = getattr(self, name)
            if value is not None and not np.isfinite(value):
                raise ConfigurationError(
                    f"MpcParameters.{name} must be a finite distance in metres, got {value!r}."
                )

    @property
    def duration(self) -> float:
        """Horizon duration ``horizon * sampling_period``, in [s]."""
        return self.horizon * self.sampling_period

    @property
    def constrain_com(self) -> bool:
        """Whether the CoM projection is constrained in the support polygon."""
        return self.constrained and self.com_margin is not None

    def replace(self, **changes) -> "MpcParameters":
        """Copy with some fields changed; unknown names raise ConfigurationError."""
        names = [f.name for f in dataclasses.fields(self)]
        unknown = sorted(set(changes) - set(names))
        if unknown:
            raise ConfigurationError(
                f"Unknown MPC parameter(s) {', '.join(unknown)}; the parameters are "
                f"{', '.join(names)}."
            )
        return dataclasses.replace(self, **changes)

    @staticmethod
    def with_duration(duration: float, sampling_period: float, **kwargs) -> "MpcParameters":
        """Parameters for a horizon given in seconds.

        Args:
            duration: Horizon length, in [s] (rounded to whole samples).
            sampling_period: In [s].
            kwargs: Other fields.
        """
        if not np.isfinite(sampling_period) or sampling_period <= 0.0:
            raise ConfigurationError(
                f"sampling_period must be a positive number of seconds, got {sampling_period!r}."
            )
        if not np.isfinite(duration) or duration <= 0.0:
            raise ConfigurationError(
                f"Horizon duration must be a positive number of seconds, got {duration!r}."
            )
        horizon = max(1, int(round(duration / sampling_period)))
        return MpcParameters(sampling_period=sampling_period, horizon=horizon, **kwargs)
