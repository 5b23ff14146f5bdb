"""Late step adjustment of a swing in progress: its limits, the quintic that retargets it, and
how far a landing may still move.

A landing moved during the swing is reached by re-planning what is left of the swing as a
quintic of time, from the swing foot's current position, velocity and acceleration to the new
landing at rest (zero velocity and acceleration), over the time left to touch-down ``tau``:
position and velocity are continuous at the re-plan (the acceleration too, as far as the
caller gives it). The quintic is linear in its end point: moving the landing by ``delta``
adds ``delta * s(u)`` with ``s(u) = 10 u^3 - 15 u^4 + 6 u^5``, ``u = (t - t0) / tau``, whose
peaks are ``1.875 |delta| / tau`` in velocity and ``10/sqrt(3) |delta| / tau^2`` in
acceleration. Requiring them within the swing limits gives the largest landing change the
time left allows, per axis::

    |delta| <= min(v_max tau / 1.875, a_max tau^2 / 5.774)

which the footstep-adaptive MPC puts into its QP as a box on the next landing
(:mod:`mpcwalk.generators.mpc_steps`, ``late_adjustment``).

The limits (:class:`SwingLimits`) are the swing foot's own headroom for such changes. Unless
given, they come from the gait (:meth:`SwingLimits.for_gait`): **the leg can swing its longest
step in half the nominal single support on the quintic law**, so ``v_max = 1.875 D /
(T_ss / 2)`` and ``a_max = 5.774 D / (T_ss / 2)^2`` with ``D`` the longest swing the leg
limits allow (twice the longest step) and ``T_ss`` the single support. On ``bioloid-like``
(``D`` = 0.16 m, ``T_ss`` = 0.4 s): 1.5 m/s and 23 m/s^2, within what its 1.5 N m servos give
its 0.4 kg leg (about 50 m/s^2 at the foot, in the air); a landing may still move 40 mm
0.1 s before touch-down, 22 mm 75 ms before, 6 mm 40 ms before.
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.reachability import ReachabilityRectangle
from mpcwalk.gait.contact_schedule import ContactSchedule

#: Peak of ``ds/du`` for ``s(u) = 10 u^3 - 15 u^4 + 6 u^5`` (at u = 1/2).
PEAK_VELOCITY = 1.875
#: Peak of ``|d^2 s / du^2|`` (at u = (3 -+ sqrt(3)) / 6).
PEAK_ACCELERATION = 10.0 / math.sqrt(3.0)


@dataclass(frozen=True)
class SwingLimits:
    """Speed and acceleration a landing change may add to the swing foot, per axis.

    Attributes:
        velocity: Largest added speed, in [m/s].
        acceleration: Largest added acceleration, in [m/s^2].
    """

    velocity: float  # [m/s]
    acceleration: float  # [m/s^2]

    def __post_init__(self) -> None:
        for name in ("velocity", "acceleration"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise ConfigurationError(
                    f"SwingLimits.{name} must be a positive number, got {value!r}; e.g. "
                    "SwingLimits.for_gait(single_support=0.4, longest_swing=0.16)."
                )

    @classmethod
    def for_gait(cls, *, single_support: float, longest_swing: float) -> "SwingLimits":
        """The limits of a leg that swings ``longest_swing`` [m] in half of
        ``single_support`` [s] on the quintic law (see the module's rule)."""
        if not (math.isfinite(single_support) and single_support > 0.0):
            raise ConfigurationError(
                f"single_support must be a positive duration [s], got {single_support!r}."
            )
        if not (math.isfinite(longest_swing) and longest_swing > 0.0):
            raise ConfigurationError(
                f"longest_swing must be a positive distance [m], got {longest_swing!r}."
            )
        half = 0.5 * single_support
        return cls(
            PEAK_VELOCITY * longest_swing / half, PEAK_ACCELERATION * longest_swing / half**2
        )

    @classmethod
    def for_walk(cls, schedule: ContactSchedule, reach: ReachabilityRectangle) -> "SwingLimits":
        """:meth:`for_gait` of the schedule's single support and the longest swing of the
        reach: twice its longest step forward or backward."""
        longest = 2.0 * max(reach.x_max, -reach.x_min)
        return cls.for_gait(single_support=schedule.t_e - schedule.t_b, longest_swing=longest)

    def landing_change_bound(self, remaining):
        """Largest move [m] of the landing, per axis, a re-plan ``remaining`` [s] before
        touch-down may make within the limits (0 when no time is left); a float for a float,
        an array for an array."""
        tau = np.maximum(np.asarray(remaining, dtype=float), 0.0)
        bound = np.minimum(
            self.velocity * tau / PEAK_VELOCITY, self.acceleration * tau**2 / PEAK_ACCELERATION
        )
        return float(bound) if bound.ndim == 0 else bound


class QuinticRetarget:
    """The rest of a swing as a quintic of time, per axis, from a state to a landing at rest.

    Args:
        start: Time of the re-plan ``t0``, in [s].
        duration: Time left to touch-down ``tau``, in [s]; positive.
        position, velocity, acceleration: The foot's state at ``t0``, shape (d,), in [m],
            [m/s], [m/s^2].
        landing: Where the foot lands, shape (d,), in [m] (with zero velocity and
            acceleration).
    """

    def __init__(
        self,
        start: float,
        duration: float,
        position: np.ndarray,
        velocity: np.ndarray,
        acceleration: np.ndarray,
        landing: np.ndarray,
    ) -> None:
        if not (math.isfinite(duration) and duration > 0.0):
            raise ConfigurationError(f"duration must be a positive time [s], got {duration!r}.")
        self.start, self.duration = float(start), float(duration)
        T = self.duration
        p0, v0, a0 = (np.asarray(x, dtype=float) for x in (position, velocity, acceleration))
        p1 = np.asarray(landing, dtype=float)
        # p(s) = c0 + c1 s + c2 s^2 + c3 s^3 + c4 s^4 + c5 s^5, s = t - t0 in [0, T]
        d = p1 - p0 - v0 * T - 0.5 * a0 * T**2  # what the end conditions add
        e, f = -v0 - a0 * T, -a0  # end velocity and acceleration to cancel
        c3 = (10.0 * d - 4.0 * e * T + 0.5 * f * T**2) / T**3
        c4 = (-15.0 * d + 7.0 * e * T - f * T**2) / T**4
        c5 = (6.0 * d - 3.0 * e * T + 0.5 * f * T**2) / T**5
        self.coefficients = np.stack([p0, v0, 0.5 * a0, c3, c4, c5])
        """Shape (6, d): the powers 0..5 of ``t - t0``."""

    def evaluate(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position [m], velocity [m/s] and acceleration [m/s^2] at ``t`` [s] (held at the
        landing after touch-down)."""
        s = min(max(float(t) - self.start, 0.0), self.duration)
        c = self.coefficients
        powers = s ** np.arange(6)
        position = powers @ c
        velocity = (np.arange(1, 6) * powers[:5]) @ c[1:]
        acceleration = (np.array([2.0, 6.0, 12.0, 20.0]) * powers[:4]) @ c[2:]
        return position, velocity, acceleration
