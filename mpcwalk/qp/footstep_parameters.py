"""Parameters of the footstep-adaptive MPC, and the double-support rectangles it uses."""

import dataclasses
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError


@dataclass(frozen=True)
class FootstepMpcParameters:
    """Horizon and weights of the footstep-adaptive MPC (all weights per sample and axis).

    Attributes:
        sampling_period: Time between two samples, in [s].
        horizon: Number of samples N.
        velocity_weight: CoM velocity error to the reference walking velocity, in [s^2/m^2].
        zmp_weight: ZMP distance to the centre of its (variable) support, in [1/m^2].
        jerk_weight: CoM jerk, in [s^6/m^2]; positive.
        footstep_weight: Footstep distance to its nominal position (or displacement), in
            [1/m^2] per footstep; positive (it also keeps the QP strictly convex).
        zmp_margin: Distance kept between the ZMP and the support edges, in [m].
        constraint_points: Points of each sampling interval where the ZMP is constrained,
            evenly spaced, the last at the sample: 1 constrains the samples only; 2 (the
            default) also the middle of each interval. The ZMP is cubic between samples
            and, at the samples only, was measured 9 mm outside the foot after a push (the
            ZMP crossing to a footstep moved 6 cm away within the 0.1 s double support).
        capturability: Require the DCM at the end of the horizon inside the support of the
            last sample (the robot could stop there: every plan returned is capturable
            within the horizon, as the terminal constraint of Scianca et al. 2020 keeps the
            DCM bounded). When no plan meets it the generator solves without it and says so.
    """

    sampling_period: float = 0.05  # [s]
    horizon: int = 32  # [] 1.6 s
    velocity_weight: float = 1.0  # [s^2/m^2]
    zmp_weight: float = 100.0  # [1/m^2]
    jerk_weight: float = 1e-6  # [s^6/m^2]
    footstep_weight: float = 100.0  # [1/m^2]
    zmp_margin: float = 0.0  # [m]
    constraint_points: int = 2  # [] per sampling interval
    capturability: bool = False

    def __post_init__(self) -> None:
        if not np.isfinite(self.sampling_period) or self.sampling_period <= 0.0:
            raise ConfigurationError(
                f"FootstepMpcParameters.sampling_period must be a positive number of seconds, "
                f"got {self.sampling_period!r}; 0.05 s is the default."
            )
        if isinstance(self.horizon, bool) or int(self.horizon) != self.horizon or self.horizon < 2:
            raise ConfigurationError(
                f"FootstepMpcParameters.horizon is a number of samples and must be an integer "
                f">= 2, got {self.horizon!r}."
            )
        object.__setattr__(self, "horizon", int(self.horizon))
        for name in ("velocity_weight", "zmp_weight", "jerk_weight", "footstep_weight"):
            value = getattr(self, name)
            strict = name in ("jerk_weight", "footstep_weight")
            if not np.isfinite(value) or value < 0.0 or (strict and value == 0.0):
                raise ConfigurationError(
                    f"FootstepMpcParameters.{name} must be a "
                    f"{'positive' if strict else 'non-negative'} number, got {value!r}."
                )
        if (
            isinstance(self.constraint_points, bool)
            or int(self.constraint_points) != self.constraint_points
            or self.constraint_points < 1
        ):
            raise ConfigurationError(
                "FootstepMpcParameters.constraint_points must be an integer >= 1 (points per "
                f"sampling interval), got {self.constraint_points!r}."
            )
        object.__setattr__(self, "constraint_points", int(self.constraint_points))
        if not isinstance(self.capturability, bool):
            raise ConfigurationError(
                "FootstepMpcParameters.capturability must be True or False, got "
                f"{self.capturability!r}."
            )
        if not np.isfinite(self.zmp_margin) or self.zmp_margin < 0.0:
            raise ConfigurationError(
                f"FootstepMpcParameters.zmp_margin must be a non-negative distance in metres, "
                f"got {self.zmp_margin!r}."
            )

    @property
    def duration(self) -> float:
        """Horizon duration, in [s]."""
        return self.horizon * self.sampling_period

    def replace(self, **changes) -> "FootstepMpcParameters":
        """Copy with some fields changed; unknown names raise ConfigurationError."""
        names = [f.name for f in dataclasses.fields(self)]
        unknown = sorted(set(changes) - set(names))
        if unknown:
            raise ConfigurationError(
                f"Unknown footstep MPC parameter(s) {', '.join(unknown)}; the parameters are "
                f"{', '.join(names)}."
            )
        return dataclasses.replace(self, **changes)


def blended_rectangles(yaw_a: np.ndarray, yaw_b: np.ndarray, lam: np.ndarray, foot):
    """Sole-sized rectangles between two feet A and B, for double support.

    The rectangle centred at ``(1 - lam) A + lam B`` with the yaw of
    ``w = (1 - lam) e^{i yaw_A} + lam e^{i yaw_B}`` and half sizes scaled by ``|w| <= 1``
    lies inside the convex hull of the two soles whatever their positions: each of its
    points is the same convex combination of a point of each sole. Linear in A and B.

    Args:
        yaw_a, yaw_b: Yaws of the feet, shape (k,), in [rad].
        lam: Share of B, shape (k,), in [0, 1].
        foot: Sole (``length``, ``width`` in [m]).

    Returns:
        ``(normals, half)``: outward unit normals (k, 4, 2) (front, back, left, right) and
        the distances of the edges from the centre (k, 4), in [m].
    """
    lam = np.asarray(lam, dtype=float)
    w = (1.0 - lam) * np.exp(1j * np.asarray(yaw_a)) + lam * np.exp(1j * np.asarray(yaw_b))
    scale, yaw = np.abs(w), np.angle(w)
    c, s = np.cos(yaw), np.sin(yaw)
    normals = np.empty((*w.shape, 4, 2))  # rows: (c, s), (-c, -s), (-s, c), (s, -c)
    normals[..., 0, 0], normals[..., 0, 1] = c, s
    normals[..., 1, 0], normals[..., 1, 1] = -c, -s
    normals[..., 2, 0], normals[..., 2, 1] = -s, c
    normals[..., 3, 0], normals[..., 3, 1] = s, -c
    half = scale[..., None] * (0.5 * np.array([foot.length, foot.length, foot.width, foot.width]))
    return normals, half
