"""The CoM's height and the ZMP's plane along a contact schedule, off the flat floor.

On a level floor the CoM walks at a constant height ``h`` above the soles and the ZMP lives
on the soles' plane. When the footsteps climb (stairs, slopes, stones), both follow them:

- **the ground reference** ``z_g(t)`` under the CoM (:meth:`HeightProfile.ground`): at the
  middle of every single support, the support sole's height (less :data:`DESCENT_LEAN` of
  the drop when the swing foot steps down: the stance knee bends early so that the swing
  leg reaches the lower tread); at the middle of every double
  support, the lower sole's height plus :attr:`HeightProfile.lean` times the difference (the
  CoM keeps the lower leg near its nominal bend and folds the upper one); between these
  knots a quintic with zero velocity and acceleration at both ends, so that the CoM height
  ``z_c = z_g + h`` is twice continuously differentiable and known over any horizon;
- **the ZMP's plane** ``z_p(t)`` (:meth:`HeightProfile.zmp_plane`): the support sole's
  height in single support, moving linearly in time from one support's height to the next
  through each double support, as the ZMP moves from one sole to the other.

The LIPM then reads, with the known vertical motion (Kajita's ZMP equation with ``z_c``
given): ``p = c - (z_c - z_p) / (g + z_c'') c''``, linear in the horizontal CoM state with a
coefficient :meth:`HeightProfile.eta` that changes with time but not with the decision
variables, so the walking MPC stays a QP.
"""

import numpy as np

from mpcwalk.exceptions import ConfigurationError

#: Share of the drop of a step down the CoM's ground reference takes in the single support
#: before it (the stance knee bends so that the swing leg reaches the lower tread).
DESCENT_LEAN = 0.5
#: Share of the height difference of two soles the CoM's ground reference rises above the
#: lower one in double support.
DEFAULT_LEAN = 0.3


def _quintic(times: np.ndarray, knot_times: np.ndarray, knot_values: np.ndarray):
    """Value, first and second derivative of the rest-to-rest quintics through the knots."""
    t = np.clip(np.asarray(times, dtype=float), knot_times[0], knot_times[-1])
    k = np.clip(np.searchsorted(knot_times, t, side="right") - 1, 0, len(knot_times) - 2)
    t0, t1 = knot_times[k], knot_times[k + 1]
    v0, v1 = knot_values[k], knot_values[k + 1]
    tau = np.maximum(t1 - t0, 1e-12)
    s = (t - t0) / tau
    delta = v1 - v0
    value = v0 + delta * s**3 * (10.0 - 15.0 * s + 6.0 * s**2)
    rate = delta / tau * 30.0 * s**2 * (1.0 - s) ** 2
    acceleration = delta / tau**2 * 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s)
    return value, rate, acceleration


class HeightProfile:
    """CoM height and ZMP plane of a contact schedule (see the module's documentation).

    Args:
        schedule: The contact schedule (its phases and their feet).
        com_height: CoM height ``h`` [m] above the ground reference.
        lean: Share of a double support's height difference the ground reference takes above
            the lower sole, in [0, 1].

    Raises:
        ConfigurationError: ``lean`` outside [0, 1] or ``com_height`` not positive.
    """

    def __init__(self, schedule, com_height: float, lean: float = DEFAULT_LEAN) -> None:
        if not np.isfinite(lean) or not 0.0 <= lean <= 1.0:
            raise ConfigurationError(f"lean must lie in [0, 1], got {lean!r}.")
        if not np.isfinite(com_height) or com_height <= 0.0:
            raise ConfigurationError(
                f"com_height must be a positive height [m], got {com_height!r}."
            )
        self.com_height = float(com_height)
        self.lean = float(lean)
        plan = schedule.plan  # the phases' feet are the plan's footsteps
        feet = (plan.initial_left, plan.initial_right, *plan.steps)
        self.is_level = len({float(f.position[2]) for f in feet}) == 1
        """Whether every sole of the schedule is at the same height (the constant LIPM)."""
        self.level = float(plan.initial_left.position[2]) if self.is_level else float("nan")
        if self.is_level:  # the constant LIPM: no knots
            return
        heights = [[float(f.position[2]) for f in phase.feet.values()] for phase in schedule.phases]
        # Ground reference: knots at the middle of each single support and of each run of
        # double supports.
        groups: list[tuple[float, float, bool, list[float], float]] = []
        steps = schedule.plan.steps
        for phase, hs in zip(schedule.phases, heights):
            if groups and not phase.single_support and not groups[-1][2]:
                start, _, _, previous, _ = groups[-1]
                pair = previous if len(previous) == 2 else hs
                groups[-1] = (start, phase.end, False, pair, 0.0)
            else:
                drop = 0.0  # how far the swing foot of a single support goes down
                if phase.single_support and 0 <= phase.step_index < len(steps):
                    drop = max(0.0, hs[0] - float(steps[phase.step_index].position[2]))
                groups.append((phase.start, phase.end, phase.single_support, hs, drop))
        times, values, plane_times, plane_values = [], [], [], []
        for start, end, single, hs, drop in groups:
            low, high = min(hs), max(hs)
            times.append(0.5 * (start + end))
            # stepping down, the CoM lowers already over the support foot so that the swing
            # leg reaches the lower tread
            values.append(hs[0] - DESCENT_LEAN * drop if single else low + self.lean * (high - low))
            if single:
                plane_times += [start, end]
                plane_values += [hs[0], hs[0]]
        times = [float(schedule.phases[0].start), *times, float(schedule.duration)]
        values = [values[0], *values, values[-1]]
        self._times, self._values = self._increasing(times, values)
        if not plane_times:  # no step: the stance's reference
            plane_times, plane_values = [0.0], [values[0]]
        self._plane_times = np.array(plane_times, dtype=float)
        self._plane_values = np.array(plane_values, dtype=float)

    @staticmethod
    def _increasing(times: list[float], values: list[float]) -> tuple[np.ndarray, np.ndarray]:
        t, v = np.array(times), np.array(values)
        keep = np.concatenate([[True], np.diff(t) > 1e-12])
        return t[keep], v[keep]

    def ground(self, times):
        """Ground reference ``z_g`` [m] under the CoM at ``times`` [s] (a float for a
        float)."""
        if self.is_level:
            return self.level if np.ndim(times) == 0 else np.full(np.shape(times), self.level)
        value = _quintic(np.atleast_1d(times), self._times, self._values)[0]
        return float(value[0]) if np.ndim(times) == 0 else value

    def com(self, times) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """CoM height [m], vertical velocity [m/s] and acceleration [m/s^2] at ``times``."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        if self.is_level:
            zeros = np.zeros(times.shape)
            return np.full(times.shape, self.level + self.com_height), zeros, zeros.copy()
        value, rate, acceleration = _quintic(times, self._times, self._values)
        return value + self.com_height, rate, acceleration

    def zmp_plane(self, times) -> np.ndarray:
        """Height [m] of the plane the ZMP lives on at ``times`` [s]."""
        times = np.atleast_1d(np.asarray(times, dtype=float))
        if self.is_level:
            return np.full(times.shape, self.level)
        return np.interp(times, self._plane_times, self._plane_values)

    def eta(self, times, gravity: float) -> np.ndarray:
        """``(z_c - z_p) / (g + z_c'')`` [s^2] at ``times``: the ZMP is ``c - eta c''``."""
        z, _, acceleration = self.com(times)
        return (z - self.zmp_plane(times)) / (gravity + acceleration)


def height_profile(schedule, com_height: float) -> HeightProfile:
    """The :class:`HeightProfile` of ``schedule`` for a CoM ``com_height`` [m] above its
    ground reference, built once per schedule and height (cached on the schedule)."""
    cache = schedule.__dict__.setdefault("_height_profiles", {})
    profile = cache.get(com_height)
    if profile is None:
        profile = cache[com_height] = HeightProfile(schedule, com_height)
    return profile


__all__ = ["DEFAULT_LEAN", "DESCENT_LEAN", "HeightProfile", "height_profile"]
