"""Joint-space point-to-point trajectories (paper A's ``jtraj``).

The time is normalised: ``s`` goes from 0 to 1 in ``n`` evenly spaced
samples. Velocities and accelerations are derivatives with respect to ``s``;
for a motion of duration ``D`` seconds divide them by ``D`` and ``D**2`` to
get [rad/s] and [rad/s^2].

Two time laws:

- ``"quintic"`` (default): fifth-order polynomial with the given boundary
  velocities (zero by default) and zero boundary accelerations.
- ``"trapezoidal"``: constant acceleration over the first
  ``acceleration_fraction`` of the time, constant velocity, then constant
  deceleration over the last ``acceleration_fraction``; zero boundary
  velocities. The peak velocity is ``(q1 - q0) / (1 - acceleration_fraction)``.
"""

import numbers
from dataclasses import dataclass

import numpy as np

from mpcwalk._checks import as_float
from mpcwalk.exceptions import ConfigurationError

PROFILES = ("quintic", "trapezoidal")


@dataclass(frozen=True)
class JointTrajectory:
    """Sampled joint trajectory, one row per sample.

    Attributes:
        q: Positions, shape (n, N), in the joints' units ([rad] or [m]).
        qd: Derivatives of ``q`` with respect to ``s``, shape (n, N).
        qdd: Second derivatives of ``q`` with respect to ``s``, shape (n, N).
        s: Normalised time of each sample, shape (n,), from 0 to 1.
    """

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    s: np.ndarray

    @property
    def nb_samples(self) -> int:
        """Number of samples ``n``."""
        return len(self.s)


def check_nb_samples(n, name: str = "n") -> int:
    """Validated number of samples (an integer >= 2)."""
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 2:
        raise ConfigurationError(
            f"{name} must be an integer >= 2 (number of samples including both ends), got {n!r}."
        )
    return int(n)


def _joint_vector(value, name: str, shape: tuple[int, ...] | None = None) -> np.ndarray:
    try:
        vector = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise ConfigurationError(
            f"{name} must be a number or a 1-D array of numbers, got {value!r}."
        ) from None
    if vector.ndim != 1:
        raise ConfigurationError(
            f"{name} must be a 1-D joint vector, got an array of shape {vector.shape}; "
            "pass one configuration, e.g. q[i], not a whole trajectory."
        )
    if shape is not None and vector.shape != shape:
        raise ConfigurationError(f"{name} must have the shape of q0, {shape}, got {vector.shape}.")
    if not np.all(np.isfinite(vector)):
        raise ConfigurationError(f"{name} must be finite, got {vector}.")
    return vector


def _quintic(s: np.ndarray, q0, q1, qd0, qd1):
    """Quintic with boundary positions/velocities and zero boundary accelerations."""
    delta = q1 - q0
    a5 = 6.0 * delta - 3.0 * (qd0 + qd1)
    a4 = -15.0 * delta + 8.0 * qd0 + 7.0 * qd1
    a3 = 10.0 * delta - 6.0 * qd0 - 4.0 * qd1
    S = s[:, None]
    q = q0 + S * (qd0 + S**2 * (a3 + S * (a4 + S * a5)))
    qd = qd0 + S**2 * (3.0 * a3 + S * (4.0 * a4 + S * 5.0 * a5))
    qdd = S * (6.0 * a3 + S * (12.0 * a4 + S * 20.0 * a5))
    return q, qd, qdd


def _trapezoidal(s: np.ndarray, q0, q1, fraction: float):
    """Trapezoidal velocity profile (linear segments with parabolic blends)."""
    delta = q1 - q0
    peak = delta / (1.0 - fraction)
    accel = peak / fraction
    S = s[:, None]
    rising, falling = S < fraction, S > 1.0 - fraction
    q = np.where(
        rising,
        q0 + 0.5 * accel * S**2,
        np.where(falling, q1 - 0.5 * accel * (1.0 - S) ** 2, q0 + peak * (S - 0.5 * fraction)),
    )
    qd = np.where(rising, accel * S, np.where(falling, accel * (1.0 - S), peak))
    qdd = np.where(rising, accel, np.where(falling, -accel, 0.0 * accel))
    return q, qd, qdd


def jtraj(
    q0,
    q1,
    n: int,
    *,
    profile: str = "quintic",
    qd0=None,
    qd1=None,
    acceleration_fraction: float = 1.0 / 3.0,
) -> JointTrajectory:
    """Point-to-point joint trajectory in ``n`` samples of normalised time.

    Args:
        q0: Start configuration, shape (N,) (a scalar is one joint).
        q1: End configuration, shape (N,).
        n: Number of samples, including both ends (>= 2).
        profile: ``"quintic"`` or ``"trapezoidal"``.
        qd0: Start velocity with respect to ``s``, shape (N,); quintic only,
            default zero.
        qd1: End velocity with respect to ``s``, shape (N,); quintic only,
            default zero.
        acceleration_fraction: Trapezoidal only: fraction of the time spent
            accelerating (and again decelerating), in (0, 0.5].

    Returns:
        The sampled trajectory; ``q[0] == q0`` and ``q[-1] == q1`` exactly.

    Raises:
        ConfigurationError: On a bad ``n``, mismatched or non-finite
            configurations, an unknown profile, boundary velocities with the
            trapezoidal profile or an acceleration fraction outside (0, 0.5].
    """
    n = check_nb_samples(n)
    start = _joint_vector(q0, "q0")
    end = _joint_vector(q1, "q1", start.shape)
    if profile not in PROFILES:
        raise ConfigurationError(f"profile must be one of {', '.join(PROFILES)}, got {profile!r}.")
    zeros = np.zeros_like(start)
    v0 = zeros if qd0 is None else _joint_vector(qd0, "qd0", start.shape)
    v1 = zeros if qd1 is None else _joint_vector(qd1, "qd1", start.shape)
    s = np.linspace(0.0, 1.0, n)
    if profile == "quintic":
        q, qd, qdd = _quintic(s, start, end, v0, v1)
    else:
        if np.any(v0 != 0.0) or np.any(v1 != 0.0):
            raise ConfigurationError(
                "The trapezoidal profile starts and ends at rest; drop qd0/qd1 or "
                "use profile='quintic' for non-zero boundary velocities."
            )
        fraction = as_float(acceleration_fraction)
        if not 0.0 < fraction <= 0.5:
            raise ConfigurationError(
                f"acceleration_fraction must lie in (0, 0.5], got "
                f"{acceleration_fraction!r}; 1/3 gives a peak velocity of 1.5 times "
                "the mean velocity."
            )
        q, qd, qdd = _trapezoidal(s, start, end, fraction)
    q[0], q[-1] = start, end
    for array in (q, qd, qdd, s):
        array.setflags(write=False)
    return JointTrajectory(q=q, qd=qd, qdd=qdd, s=s)
