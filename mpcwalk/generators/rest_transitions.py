"""Start and stop of paper M's closed form from and to rest, where the robot cannot follow
the paper's velocity jump.

Each step of paper M's closed form (:mod:`~mpcwalk.generators.analytic`) imposes only the CoM
positions at its ends, so the CoM reference of the first step starts with a velocity (the
lateral one about 0.2 to 0.3 m/s) while the robot stands still, and the last step ends with
one. The robot's divergent component of motion (DCM, ``xi = c + c_dot / omega``) then lags
the reference's by ``c_dot(0) / omega``, which the first double support must make up.

The rule (a capturability bound): in the first double support, of duration ``t_b``, the CoP
can at most be at the far edge of the other sole, at ``d + w / 2`` from the torso waypoint
(``d``: distance from the waypoint to the first support sole's centre, ``w``: sole width),
which carries a DCM starting at rest on the waypoint by at most
``(d + w / 2) (exp(omega t_b) - 1)``. When this reaches the support sole's inner edge,
``d - w / 2``, the robot can take the paper's first step as it is (the paper's robot,
bioloid-like: 0.027 m for 0.010 m). Where the ankle roll motors cannot hold the robot's weight
``m g`` on a sole's edge, the CoP reaches only ``r = tau_max / (m g)`` sideways from a sole's
centre, and ``r`` takes the place of ``w / 2`` (the drafted ``human`` of example-robot-data:
20 N m ankle rolls for 74.7 kg, ``r`` = 2.7 cm on a sole 12.1 cm wide; 0.027 m for 0.055 m,
where the sole's width alone gave 0.036 m for 0.022 m). When it cannot (g1: 0.039 m for
0.084 m; romeo: 0.037 m for 0.046 m), the step is started at rest instead: the first step's
torso waypoint is moved to the point from which the closed form starts with zero velocity
(the same boundary value problem, eq. 6-18, one more condition), and the CoM is shifted there
during the standing time before the walk along a quintic (zero velocity and acceleration at
both ends). The stop mirrors it: the last step's final waypoint is moved to where it ends
at rest, and the CoM goes back above the feet's midpoint during the standing time after the
walk.
"""

import math

import numpy as np


def start_is_capturable(
    waypoint: np.ndarray,
    support: np.ndarray,
    sole_width: float,
    omega: float,
    duration: float,
    *,
    cop_reach: float | None = None,
) -> bool:
    """Whether a DCM at rest on ``waypoint`` can reach the support sole centred at ``support``
    (both (2,), in [m]) within a double support of ``duration`` [s] (see the module
    docstring); ``sole_width`` in [m], ``omega`` the LIPM's ``sqrt(g / z_c)`` in [1/s].
    ``cop_reach`` [m]: how far sideways from a sole's centre the ankles can carry the CoP,
    where it is less than half the sole's width (None: half the sole's width)."""
    d = float(np.linalg.norm(np.asarray(support, dtype=float) - np.asarray(waypoint, dtype=float)))
    half = 0.5 * float(sole_width)
    if cop_reach is not None:
        half = min(half, float(cop_reach))
    return (d + half) * math.expm1(omega * duration) >= d - half


def quintic_shift(start: np.ndarray, end: np.ndarray, t: float, duration: float) -> np.ndarray:
    """Position, velocity and acceleration, shape (3, 2), at time ``t`` [s] of a quintic from
    ``start`` to ``end`` (in [m]) over ``duration`` [s], at rest at both ends."""
    state = np.zeros((3, 2))
    if duration <= 0.0:
        state[0] = end if t > 0.0 else start
        return state
    s = min(max(t / duration, 0.0), 1.0)
    delta = np.asarray(end, dtype=float) - np.asarray(start, dtype=float)
    state[0] = start + s**3 * (10.0 - 15.0 * s + 6.0 * s * s) * delta
    state[1] = 30.0 * s * s * (1.0 - s) ** 2 / duration * delta
    state[2] = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / duration**2 * delta
    return state


def standing_state(
    t: float,
    times: tuple[float, float, float],
    waypoints: tuple[np.ndarray, np.ndarray],
    rest: tuple[np.ndarray | None, np.ndarray | None],
) -> np.ndarray:
    """CoM state, shape (3, 2), at ``t`` [s] outside the steps: at rest on the first (before
    the walk) or last (after) torso waypoint, or on the quintic from it to the rest waypoint
    of the first step (from that of the last step to it).

    Args:
        t: Time since the start of the schedule [s].
        times: Start of the first step, end of the last one, end of the schedule [s].
        waypoints: The torso waypoints ``x_t[0]`` and ``x_t[N]`` (paper M), each (2,) [m].
        rest: Where the first step starts and the last one ends at rest, (2,) [m] each, or
            None where the walk keeps the paper's waypoint.
    """
    walk_start, walk_end, duration = times
    before = t < walk_start
    point = rest[0] if before else rest[1]
    if point is None:
        state = np.zeros((3, 2))
        state[0] = waypoints[0] if before else waypoints[1]
        return state
    if before:
        return quintic_shift(waypoints[0], point, t, walk_start)
    return quintic_shift(point, waypoints[1], t - walk_end, duration - walk_end)
