"""Integral action on the DCM error: the part of the balance stabilizer that removes a bias.

The proportional DCM feedback (:mod:`mpcwalk.control.dcm_feedback`) asks for the ZMP
``z = z_ref + k_p e`` with ``e = xi - xi_ref`` the error of the divergent component of
motion. On the LIPM the error obeys ``de/dt = omega (e - (z - z_ref))``; if the ZMP the robot
realises is the commanded one plus a constant bias ``b`` (a model that is wrong, servos that
sag, a sensor offset), the error settles at ``e = -b / (k_p - 1)``: the robot walks off its
plan by that much, and a larger bias pushes the ZMP to the edge of the feet.

:class:`DcmIntegrator` adds ``k_i I`` to the desired ZMP, where ``I`` integrates the error
(Caron et al. 2019, the DCM feedback of the LIPM walking controller of HRP-4, eq. 4):

    dI/dt = e - I / T_leak,        z = z_ref + k_p e + k_i I.

Without leak the error then goes to zero for any constant bias (the integral ends at
``-b / k_i``); the closed loop is ``s^2 + omega (k_p - 1) s + omega k_i``, whose slow pole is
about ``k_i / (k_p - 1)`` [1/s] for small ``k_i``. Anti-windup: the integral's ZMP shift is
clamped to ``limit`` per axis (the integral itself is held at the bound, so that it comes
back as soon as the error changes sign), and the leak (time constant ``T_leak``) slowly
forgets what a transient (a push, a landing) left in it; with a leak the error of a constant
bias is ``-b / (k_p - 1 + k_i T_leak)`` instead of zero.
"""

import math

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError


def _non_negative(name: str, value: float) -> float:
    return checked_number(f"DcmIntegrator {name}", value, low=0.0)


class DcmIntegrator:
    """Leaky, bounded integral of the DCM error and the ZMP shift it asks for.

    Args:
        gain: Integral gain ``k_i`` [1/s]: ZMP shift [m] per metre-second of integrated
            DCM error.
        leak_time: Time constant ``T_leak`` [s] of the leak (inf: no leak).
        limit: Bound of the ZMP shift of each axis [m] (anti-windup).

    Raises:
        ConfigurationError: A negative or non-finite gain or limit, a non-positive leak time.
    """

    def __init__(self, *, gain: float, leak_time: float = math.inf, limit: float) -> None:
        self.gain = _non_negative("gain", gain)
        self.limit = _non_negative("limit", limit)
        if isinstance(leak_time, bool) or not (
            isinstance(leak_time, (int, float)) and leak_time > 0.0 and not math.isnan(leak_time)
        ):
            raise ConfigurationError(
                f"DcmIntegrator leak_time must be a positive number of seconds (inf: no leak), "
                f"got {leak_time!r}."
            )
        self.leak_time = float(leak_time)
        self.integral = np.zeros(2)
        """Integrated DCM error ``I`` [m s], shape (2,)."""

    def reset(self) -> None:
        """Forget the integral (a new walk)."""
        self.integral = np.zeros(2)

    @property
    def shift(self) -> np.ndarray:
        """ZMP shift of the integral action ``k_i I`` [m], shape (2,)."""
        return self.gain * self.integral

    def update(self, dcm_error: np.ndarray, dt: float) -> np.ndarray:
        """Integrate the DCM error [m], shape (2,), over ``dt`` [s]; return the new ZMP shift
        [m], shape (2,), clamped to ``limit`` per axis."""
        decay = math.exp(-dt / self.leak_time)  # 1 without leak
        bound = self.limit / self.gain if self.gain > 0.0 else math.inf
        self.integral = np.array(
            [
                min(bound, max(-bound, (self.integral[i] + dt * float(dcm_error[i])) * decay))
                for i in (0, 1)
            ]
        )
        return self.gain * self.integral
