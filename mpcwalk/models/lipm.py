"""Linear inverted pendulum (3D-LIPM) in continuous time.

The CoM moves at constant height ``com_height`` and its horizontal motion
obeys, per axis,

    p = c - (z_c / g) * c_ddot,        i.e.   c_ddot = omega^2 (c - p),

with ``omega = sqrt(g / z_c)`` (paper M eq. 1-3 and 14).
"""

from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError

GRAVITY = 9.81  # [m] / [s]^2


@dataclass(frozen=True)
class LIPM:
    """Linear inverted pendulum parameters.

    Attributes:
        com_height: Constant CoM height z_c above the ground, in [m].
        gravity: Gravity acceleration g, in [m] / [s]^2.
    """

    com_height: float = 0.23  # [m] (paper M, Table 1)
    gravity: float = GRAVITY  # [m] / [s]^2

    def __post_init__(self) -> None:
        if not np.isfinite(self.com_height) or self.com_height <= 0.0:
            raise ConfigurationError(
                f"LIPM com_height must be a positive number of metres, got "
                f"{self.com_height!r}; pass the CoM height of the walking posture."
            )
        if not np.isfinite(self.gravity) or self.gravity <= 0.0:
            raise ConfigurationError(f"LIPM gravity must be positive, got {self.gravity!r}.")

    @property
    def omega(self) -> float:
        """Natural frequency sqrt(g / z_c), in [1/s]."""
        return float(np.sqrt(self.gravity / self.com_height))

    def zmp(self, com: np.ndarray, com_acceleration: np.ndarray) -> np.ndarray:
        """ZMP implied by a CoM position and acceleration (same shapes), in [m]."""
        return np.asarray(com) - np.asarray(com_acceleration) / self.omega**2

    def dcm(self, com: np.ndarray, com_velocity: np.ndarray) -> np.ndarray:
        """Divergent component of motion ``c + c_dot / omega``, in [m]."""
        return np.asarray(com) + np.asarray(com_velocity) / self.omega

    def propagate(
        self,
        com: np.ndarray,
        com_velocity: np.ndarray,
        zmp: np.ndarray,
        duration: float,
        zmp_velocity: np.ndarray | float = 0.0,
    ):
        """Exact LIPM propagation under a ZMP that is affine in time.

        With ``p(t) = zmp + zmp_velocity * t`` the solution is
        ``c(t) = p(t) + (c0 - p0) cosh(w t) + (v0 - pdot) / w sinh(w t)``.

        Args:
            com: Initial CoM position (any shape), in [m].
            com_velocity: Initial CoM velocity (same shape), in [m]/[s].
            zmp: ZMP at the start of the interval (same shape), in [m].
            duration: Interval length, in [s].
            zmp_velocity: ZMP rate over the interval, in [m]/[s].

        Returns:
            Tuple ``(com, com_velocity, com_acceleration)`` at the end of the
            interval.
        """
        w = self.omega
        c0 = np.asarray(com, dtype=float)
        v0 = np.asarray(com_velocity, dtype=float)
        p0 = np.asarray(zmp, dtype=float)
        m = np.asarray(zmp_velocity, dtype=float)
        ch, sh = np.cosh(w * duration), np.sinh(w * duration)
        a, b = c0 - p0, (v0 - m) / w
        c = p0 + m * duration + a * ch + b * sh
        v = m + a * w * sh + b * w * ch
        acc = w**2 * (a * ch + b * sh)
        return c, v, acc
