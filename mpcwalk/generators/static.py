"""Paper A's static gait as a CoM generator.

The CoM is kept above the support foot centre during every single support and
moves only while both feet are on the ground: in each double support it
travels from its previous target (the feet midpoint at the start, or the
previous support foot centre) to above the centre of the next support foot,
with a quintic time law (zero velocity and acceleration at both ends, as
paper A's ``jtraj``/``ctraj``). After the last single support it returns to
the midpoint of the feet.

The first shift uses the whole initial double support (standing phase plus
the opening double support of step 0); the last one uses the closing double
support of the last step plus the final standing phase.

This is quasi-static only when the double support is long: the ZMP is
``c - c_ddot / omega^2`` and the quintic's peak acceleration grows as
``1 / T_ds^2``, so with short double supports (paper M's ``r_ds = 0.2`` at
``T = 0.5 s``) the ZMP leaves the support polygon. That is the static gait's
limit at speed (paper A walks with 12 s steps), reproduced here on purpose.
"""

from typing import ClassVar

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.closed_form import ClosedFormGenerator
from mpcwalk.generators.pattern_generator import GeneratorOutput
from mpcwalk.generators.static_timing import check_static_timing
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM


def quintic(tau) -> np.ndarray:
    """Quintic time law and its derivatives on normalised time.

    Args:
        tau: Normalised time, clipped to [0, 1].

    Returns:
        Shape ``(3,) + shape(tau)``: ``s``, ``ds/dtau``, ``d2s/dtau2`` with
        ``s(0) = 0``, ``s(1) = 1`` and zero first and second derivatives at
        both ends.
    """
    x = np.clip(np.asarray(tau, dtype=float), 0.0, 1.0)
    return np.stack(
        [
            x**3 * (10.0 - 15.0 * x + 6.0 * x**2),
            30.0 * x**2 * (1.0 - x) ** 2,
            60.0 * x * (1.0 - x) * (1.0 - 2.0 * x),
        ]
    )


class StaticGenerator(ClosedFormGenerator):
    """CoM above the support foot in single support, quintic shifts in double support.

    Open loop: ``initial_state`` and the measured state are ignored; the CoM
    starts at rest above the midpoint of the initial feet.

    Args:
        lipm: Pendulum model (CoM height, gravity), used for the ZMP output.
        control_period: Output period, in [s].
        horizon_time: Length of the output horizon, in [s]; None: the rest of
            the current step (no horizon while standing); 0: no horizon.

    Raises:
        ConfigurationError: at reset, when a double support has zero length
            (``r_ds = 0``): the CoM would have to jump.
    """

    name = "static"
    #: Paper A's timing: 12 s per step (r_ds 0.2: 2.4 s to move the CoM between the feet).
    default_timing: ClassVar[tuple[float, float] | None] = (12.0, 0.2)
    holds_com_over_support: ClassVar[bool] = True

    @classmethod
    def check_timing(cls, schedule: ContactSchedule, lipm: LIPM) -> None:
        """Refuse a double support too short for the CoM shifts (see
        :mod:`mpcwalk.generators.static_timing`)."""
        check_static_timing(schedule, lipm, cls.name)

    def __init__(
        self,
        *,
        lipm: LIPM = LIPM(),
        control_period: float = 0.01,
        horizon_time: float | None = None,
    ) -> None:
        super().__init__(lipm=lipm, control_period=control_period, horizon_time=horizon_time)
        self.segment_starts = np.zeros(1)
        self.segment_ends = np.zeros(1)
        self.segment_from = np.zeros((1, 2))
        self.segment_to = np.zeros((1, 2))

    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        self._build_segments(schedule)
        return self._make_output(0.0)

    def _step(self, measured: ComState | None) -> GeneratorOutput:
        return self._make_output((self.tick + 1) * self.control_period)

    def _build_segments(self, sched: ContactSchedule) -> None:
        """Alternate shifts (double support) and holds (single support)."""
        N, T, t0 = sched.plan.nb_steps, sched.step_duration, sched.walk_start
        xt, xs = sched.torso_waypoints, sched.support_positions
        if N > 0 and sched.t_b <= 0.0:
            raise ConfigurationError(
                "The static generator moves the CoM only in double support, but the "
                f"schedule has none (t_b={sched.t_b:g} s, t_e={sched.t_e:g} s, T={T:g} s); "
                "use a double_support_ratio > 0 (paper A's static gait needs long ones)."
            )
        segments = []  # (start, end, from, to)
        start, here = 0.0, xt[0]
        for k in range(N):
            ss_begin, ss_end = t0 + k * T + sched.t_b, t0 + k * T + sched.t_e
            segments.append((start, ss_begin, here, xs[k]))
            segments.append((ss_begin, ss_end, xs[k], xs[k]))
            start, here = ss_end, xs[k]
        end = max(sched.duration, start)
        if end <= start:
            raise ConfigurationError(
                "The static generator needs time after the last single support to return "
                "the CoM between the feet; use final_duration > 0 or double_support_ratio > 0."
            )
        segments.append((start, end, here, xt[N]))
        starts, ends, froms, tos = zip(*segments)
        self.segment_starts = np.array(starts)
        self.segment_ends = np.array(ends)
        self.segment_from = np.array(froms)
        self.segment_to = np.array(tos)

    def evaluate(self, times) -> np.ndarray:
        """CoM state at any times of the schedule.

        Args:
            times: Shape (n,), in [s] (clamped to the schedule).

        Returns:
            Shape (n, 3, 2): position [m], velocity [m]/[s] and acceleration
            [m]/[s]^2 of the CoM (x, y).
        """
        t = np.atleast_1d(np.asarray(times, dtype=float))
        i = np.clip(
            np.searchsorted(self.segment_starts, t, side="right") - 1,
            0,
            len(self.segment_starts) - 1,
        )
        length = self.segment_ends[i] - self.segment_starts[i]
        s, ds, dds = quintic((t - self.segment_starts[i]) / length)
        delta = self.segment_to[i] - self.segment_from[i]
        out = np.empty((len(t), 3, 2))
        out[:, 0] = self.segment_from[i] + s[:, None] * delta
        out[:, 1] = (ds / length)[:, None] * delta
        out[:, 2] = (dds / length**2)[:, None] * delta
        return out

    def _make_output(self, t: float) -> GeneratorOutput:
        return self._output(t, self.evaluate([t])[0], horizon=self._horizon(t))
