"""How fast a joint's PD may be when the state it acts on is late: a phase-margin rule.

The inverse dynamics realises the desired acceleration of the posture task, so each joint
is a double integrator closed by a critically damped PD of natural frequency ``omega``
(``kp = omega^2``, ``kd = 2 omega``) on a state ``delay`` seconds old, plus the joint's own
viscous damping (``b`` of the model, which the inverse dynamics does not cancel) that acts
at once, a rate ``beta = b / M_jj`` [1/s]:

    L(s) = (kd s + kp) e^(-s delay) / (s (s + beta))

Its phase margin is ``pi / 2 + atan(2 w / omega) - atan(w / beta) - w delay`` at the
crossover ``|L(j w)| = 1``. :func:`delay_limited_frequency` gives the largest ``omega``, up
to a bound, that keeps :data:`PHASE_MARGIN`: with no damping of its own a joint may run at
``0.139 / delay`` (4.5 rad/s on a state 31 ms old), a heavily damped servo (the small
humanoid's, ``beta`` 16 /s) at nearly 15 rad/s.
"""

import math

import numpy as np

from mpcwalk.exceptions import ConfigurationError

#: Phase margin [rad] every posture loop keeps.
PHASE_MARGIN = math.radians(60.0)

#: Phase margin [rad] the swing soles' and the torso's loops keep: their references carry
#: their own velocities (and the swing its acceleration), so the PD only corrects; capped at
#: 60 deg they are too slow for a swing to land in its time, uncapped (25 rad/s on a state
#: 31 ms old: -14 deg) the swing foot rings at 8 Hz and shakes the stance foot loose.
TASK_MARGIN = math.radians(15.0)


def phase_margin(omega: np.ndarray, beta: np.ndarray, delay: float) -> np.ndarray:
    """Phase margin [rad] of the loop of the module docstring, elementwise."""
    omega, beta = np.broadcast_arrays(np.asarray(omega, float), np.asarray(beta, float))
    low, high = np.full(omega.shape, 1e-6), np.full(omega.shape, 1e6)
    for _ in range(80):  # |L(jw)| decreases in w: bisection on a log scale
        w = np.sqrt(low * high)
        gain = omega * np.sqrt(4.0 * w**2 + omega**2) / (w * np.sqrt(w**2 + beta**2))
        above = gain > 1.0
        low, high = np.where(above, w, low), np.where(above, high, w)
    w = np.sqrt(low * high)
    return 0.5 * math.pi + np.arctan2(2.0 * w, omega) - np.arctan2(w, beta) - w * delay


def delay_limited_frequency(
    bound: float, damping_rates: np.ndarray, delay: float, *, margin: float = PHASE_MARGIN
) -> np.ndarray:
    """Largest natural frequency [rad/s] up to ``bound`` of each joint's posture PD that
    keeps the phase ``margin`` on a state ``delay`` [s] old.

    Args:
        bound: The task's own natural frequency [rad/s], > 0.
        damping_rates: Each joint's damping over its inertia ``b / M_jj`` [1/s], >= 0.
        delay: Age of the state [s], > 0.
        margin: Phase margin [rad] to keep (default :data:`PHASE_MARGIN`).

    Raises:
        ConfigurationError: A delay or bound that is not a positive number, or a negative
            damping rate.
    """
    rates = np.asarray(damping_rates, dtype=float)
    if not (isinstance(delay, (int, float)) and math.isfinite(delay) and delay > 0.0):
        raise ConfigurationError(
            f"delay must be a positive number of seconds (the age of the estimated state the "
            f"torques act on), got {delay!r}."
        )
    if not (math.isfinite(bound) and bound > 0.0) or np.any(~(rates >= 0.0)):
        raise ConfigurationError(
            f"bound must be > 0 [rad/s] and damping rates >= 0 [1/s], got {bound!r} and {rates}."
        )
    low, high = np.zeros(rates.shape), np.full(rates.shape, float(bound))
    keeps = phase_margin(high, rates, delay) >= margin
    for _ in range(40):  # the margin falls as omega grows
        middle = 0.5 * (low + high)
        ok = phase_margin(middle, rates, delay) >= margin
        low, high = np.where(ok, middle, low), np.where(ok, high, middle)
    return np.where(keeps, float(bound), low)


def delay_capped(
    frequencies: tuple[float, float, float], damping_rate: float, delay: float
) -> tuple[float, float, float]:
    """The inverse dynamics' posture, swing-sole and torso frequencies [rad/s] capped for a
    state ``delay`` [s] old: the posture's to keep :data:`PHASE_MARGIN` with the joints'
    ``damping_rate`` [1/s] (the least damped joint's), the swing soles' and the torso's to
    keep :data:`TASK_MARGIN`; a frequency <= 0 is left as it is."""
    rate = np.array([damping_rate])

    def cap(bound: float, margin: float) -> float:
        if bound <= 0.0:
            return bound
        return float(delay_limited_frequency(bound, rate, delay, margin=margin)[0])

    posture, swing, torso = frequencies
    return cap(posture, PHASE_MARGIN), cap(swing, TASK_MARGIN), cap(torso, TASK_MARGIN)
