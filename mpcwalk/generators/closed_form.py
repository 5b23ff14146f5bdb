"""The generators whose CoM is a known function of time: :class:`ClosedFormGenerator`.

Paper M's closed-form LIPM (:mod:`~mpcwalk.generators.analytic`) and paper A's static gait
(:mod:`~mpcwalk.generators.static`) compute the CoM of the whole walk at reset; each tick
reads it (:meth:`ClosedFormGenerator.evaluate`) and ignores the measured state (open loop).
Their horizon is the same function sampled every control period ahead.
"""

from abc import abstractmethod

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.generators.pattern_generator import Horizon, PatternGenerator
from mpcwalk.models.lipm import LIPM


class ClosedFormGenerator(PatternGenerator):
    """A pattern generator whose CoM is a function of time, known for the whole walk.

    Args:
        lipm: Pendulum model (CoM height, gravity), for the ZMP of the horizon.
        control_period: Output period, in [s].
        horizon_time: Length of :attr:`GeneratorOutput.horizon`, in [s]; None: the rest of
            the current step (no horizon while standing); 0: no horizon.

    Raises:
        ConfigurationError: A negative or non-finite ``horizon_time``.
    """

    def __init__(self, *, lipm: LIPM, control_period: float, horizon_time: float | None) -> None:
        super().__init__(lipm=lipm, control_period=control_period)
        self.horizon_time = (
            None
            if horizon_time is None
            else checked_number(
                "horizon_time",
                horizon_time,
                low=0.0,
                unit="s",
                fix="or None for the rest of the current step",
            )
        )

    @abstractmethod
    def evaluate(self, times) -> np.ndarray:
        """CoM states at ``times`` (shape (n,), in [s]): shape (n, 3, 2), position [m],
        velocity [m/s] and acceleration [m/s^2] of the CoM (x, y)."""

    def _horizon(self, t: float) -> Horizon | None:
        """The CoM and ZMP every control period after ``t`` until the horizon's end."""
        sched = self.current_schedule
        if self.horizon_time is None:
            k = sched.step_index(t)
            if not 0 <= k < sched.plan.nb_steps:
                return None
            end = sched.walk_start + (k + 1) * sched.step_duration
        else:
            end = t + self.horizon_time
        n = int(np.floor((end - t) / self.control_period + 1e-9))
        if n < 1:
            return None
        times = t + self.control_period * np.arange(1, n + 1)
        states = self.evaluate(times)
        zmp = states[:, 0] - states[:, 2] / self.lipm.omega**2
        return Horizon(times=times, com=states[:, 0], zmp=zmp)
