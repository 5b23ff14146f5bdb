"""Paper M's closed-form CoM: a boundary value problem per step (eq. 6-18).

For each step ``k`` of duration ``T`` the ZMP follows the polygonal reference
of eq. 6-8 (from the torso waypoint ``x_t[k]`` to the support foot ``x_s[k]``
during ``[0, t_b)``, held until ``t_e``, then on to ``x_t[k+1]``), and the CoM
is the LIPM solution that meets ``c(0) = x_t[k]`` and ``c(T) = x_t[k+1]``
(eq. 9). The x and y axes are solved independently.

Only positions are imposed at the step boundaries, so the CoM *velocity*
may jump from one step to the next: each step is a separate boundary value
problem, as in the paper. Position and acceleration stay continuous (at a
boundary ``c = p`` so ``c_ddot = 0``). In steady walking consecutive steps
mirror each other and the jump vanishes; it is large where the gait changes:
from rest into the first step and from the last step to rest (about 0.2 m/s
lateral with paper M's Table 1 parameters), and when the command changes. This
generator is the paper's baseline and keeps that behaviour on purpose, except at the start
and the stop of a robot that cannot follow the jump there (a capturability rule on its
stance, soles, CoM height and double support,
:mod:`~mpcwalk.generators.rest_transitions`): there the first step starts, and the last
ends, at rest.
"""

import math
from typing import Any

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.closed_form import ClosedFormGenerator
from mpcwalk.generators.closed_form_step import ClosedFormStep, closed_form_step
from mpcwalk.generators.pattern_generator import GeneratorOutput
from mpcwalk.generators.rest_transitions import standing_state, start_is_capturable
from mpcwalk.generators.robot_traits import RobotTraits
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM


class AnalyticGenerator(ClosedFormGenerator):
    """Paper M's closed-form CoM, step by step, open loop.

    Before the first step and after the last one the CoM rests above the
    midpoint of the feet (``x_t[0]``, ``x_t[N]``); ``initial_state`` and the
    measured state are ignored (the boundary conditions are the paper's).
    Where the robot cannot follow the CoM velocity jump into the first step
    (out of the last), the walk starts (stops) at rest instead, the CoM shifted
    in the standing time (:mod:`~mpcwalk.generators.rest_transitions`).

    Args:
        lipm: Pendulum model (CoM height, gravity).
        control_period: Output period, in [s].
        horizon_time: Length of :attr:`GeneratorOutput.horizon`, in [s];
            None: the rest of the current step (what the paper plans at once;
            no horizon while standing); 0 (default): no horizon, the cheap
            per-tick path (:meth:`evaluate` gives the CoM at any times).
        start_at_rest: Start the first step and end the last one at rest; None
            (default): where the capturability rule says the robot cannot follow
            the paper's velocity jump; False: always the paper's jumps.
        lateral_cop_reach: How far sideways from a sole's centre the robot's ankles can
            carry the CoP, in [m], which the rule takes where it is less than half the
            sole's width; None (default): half the sole's width. :meth:`for_robot` takes
            the robot's (its ankle roll motors' torque limit over its weight).
    """

    name = "analytic"

    def __init__(
        self,
        *,
        lipm: LIPM = LIPM(),
        control_period: float = 0.01,
        horizon_time: float | None = 0.0,
        start_at_rest: bool | None = None,
        lateral_cop_reach: float | None = None,
    ) -> None:
        super().__init__(lipm=lipm, control_period=control_period, horizon_time=horizon_time)
        if start_at_rest is not None and not isinstance(start_at_rest, bool):
            raise ConfigurationError(
                f"start_at_rest must be true, false or None (the capturability rule), got "
                f"{start_at_rest!r}."
            )
        self.start_at_rest = start_at_rest
        self.lateral_cop_reach = (
            None
            if lateral_cop_reach is None
            else checked_number(
                "lateral_cop_reach", lateral_cop_reach, low=0.0, unit="m", fix="e.g. 0.03"
            )
        )
        self.steps: list[ClosedFormStep] = []
        self.rest_waypoints: tuple[np.ndarray | None, np.ndarray | None] = (None, None)
        """CoM where the first step starts and the last one ends at rest (None: the paper's
        waypoints, with its velocity jumps)."""

    @classmethod
    def robot_options(cls, robot: RobotTraits) -> dict[str, Any]:
        """How far sideways the robot's ankles carry the CoP (``lateral_cop_reach``)."""
        return {"lateral_cop_reach": robot.lateral_cop_reach}

    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        xt, xs = schedule.torso_waypoints, schedule.support_positions
        self.steps = [
            closed_form_step(
                xt[k],
                xs[k],
                xt[k + 1],
                schedule.step_duration,
                schedule.t_b,
                schedule.t_e,
                self.lipm.omega,
            )
            for k in range(schedule.plan.nb_steps)
        ]
        self.rest_waypoints = (None, None)
        if self.steps:
            self._rest_transitions(schedule)
        return self._make_output(0.0)

    def _at_rest(self, waypoint, support, duration: float) -> bool:
        if self.start_at_rest is not None:
            return self.start_at_rest
        width, omega = self.current_schedule.foot.width, self.lipm.omega
        reach = self.lateral_cop_reach
        return not start_is_capturable(waypoint, support, width, omega, duration, cop_reach=reach)

    def _rest_transitions(self, schedule: ContactSchedule) -> None:
        """Move the first (last) torso waypoint to where the closed form starts (ends) at
        rest, where the rule asks for it (the boundary value problem is linear in its
        waypoints: one more solve gives the velocity per metre of waypoint)."""
        xt, xs = schedule.torso_waypoints, schedule.support_positions
        T, t_b, t_e, w = schedule.step_duration, schedule.t_b, schedule.t_e, self.lipm.omega
        first: np.ndarray | None = None
        last: np.ndarray | None = None
        if schedule.walk_start > 0.0 and self._at_rest(xt[0], xs[0], t_b):
            per_metre = closed_form_step(1.0, 0.0, 0.0, T, t_b, t_e, w).com_velocity(0.0)
            first = xt[0] - self.steps[0].com_velocity(0.0) / per_metre
            self.steps[0] = closed_form_step(first, xs[0], xt[1], T, t_b, t_e, w)
        n = len(self.steps) - 1
        if schedule.duration > schedule.walk_end and self._at_rest(xt[n + 1], xs[n], T - t_e):
            per_metre = closed_form_step(0.0, 0.0, 1.0, T, t_b, t_e, w).com_velocity(T)
            last = xt[n + 1] - self.steps[n].com_velocity(T) / per_metre
            self.steps[n] = closed_form_step(self.steps[n].x_t0, xs[n], last, T, t_b, t_e, w)
        self.rest_waypoints = (first, last)

    def _standing(self, t: float) -> np.ndarray:
        """CoM state (3, 2) before the first step or after the last one."""
        sched = self.current_schedule
        return standing_state(
            t,
            (sched.walk_start, sched.walk_end, sched.duration),
            (sched.torso_waypoints[0], sched.torso_waypoints[len(self.steps)]),
            self.rest_waypoints,
        )

    def _step(self, measured: ComState | None) -> GeneratorOutput:
        return self._make_output((self.tick + 1) * self.control_period)

    def evaluate(self, times) -> np.ndarray:
        """CoM state of the whole walk at any times.

        Args:
            times: Shape (n,), in [s] since the start of the schedule.

        Returns:
            Shape (n, 3, 2): position [m], velocity [m]/[s] and acceleration
            [m]/[s]^2 of the CoM (x, y) at each time.
        """
        sched = self.current_schedule
        t = np.atleast_1d(np.asarray(times, dtype=float))
        out = np.zeros((len(t), 3, 2))
        N, T = len(self.steps), sched.step_duration
        k = np.floor((t - sched.walk_start) / T).astype(int)
        out[:, 0] = sched.torso_waypoints[np.clip(k, 0, N)]  # standing before / after
        if any(point is not None for point in self.rest_waypoints):
            for j in np.flatnonzero((k < 0) | (k >= N)):
                out[j] = self._standing(float(t[j]))
        for i in np.unique(k[(k >= 0) & (k < N)]):
            sel = k == i
            out[sel] = self.steps[i].state(t[sel] - sched.walk_start - i * T)
        return out

    def state_at(self, t: float) -> np.ndarray:
        """CoM state at one time, shape (3, 2) (fast path of :meth:`evaluate`)."""
        sched = self.current_schedule
        k = int(math.floor((t - sched.walk_start) / sched.step_duration))
        if not 0 <= k < len(self.steps):
            return self._standing(t)
        return self.steps[k].state_at(t - sched.walk_start - k * sched.step_duration)

    def _make_output(self, t: float) -> GeneratorOutput:
        state = self.state_at(t)
        return self._output(t, state, horizon=self._horizon(t))
