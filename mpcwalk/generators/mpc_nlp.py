"""Footstep-adaptive MPC whose next landings and step durations come from a nonlinear program.

:class:`TimingNlpGenerator` is the footstep-adaptive MPC (:mod:`mpcwalk.generators.mpc_steps`)
with its heuristic step timing (the landing brought forward when the capture point leaves the
reach) replaced by the step-timing program of :mod:`mpcwalk.generators.timing_nlp` (Khadiv
et al. 2016/2020 over two steps, with the ankle's CoP), solved every tick by IPOPT through
CasADi, warm-started: its first landing becomes the target of the QP's footsteps (in place of
the capture-point offset), and its time left in the step, when shorter than the schedule's
by a tick or more during the swing, brings the landing forward (the schedule's clock jumps,
as with ``timing_adaptation``; the swing is re-planned as a quintic, ``late_adjustment``).
The landing changes stay boxed by the swing's time left (late step adjustment).
"""

from typing import ClassVar

import numpy as np

from mpcwalk.generators.mpc_steps import FootstepMpcGenerator
from mpcwalk.generators.timing_nlp import (
    TimingNLP,
    TimingProblem,
    TimingSolution,
    TimingWeights,
    nominal_offsets,
)


class TimingNlpGenerator(FootstepMpcGenerator):
    """The footstep-adaptive MPC with optimal step timing (a CasADi program).

    Args:
        timing_weights: Weights of the program, as a table (``footstep``, ``duration``,
            ``offset``, ``cop``; :class:`~mpcwalk.generators.timing_nlp.TimingWeights`).
        **options: Those of :class:`~mpcwalk.generators.mpc_steps.FootstepMpcGenerator`;
            ``timing_adaptation`` and ``late_adjustment`` default to True.
    """

    name: ClassVar[str] = "mpc-nlp"

    def __init__(self, *, timing_weights: dict | None = None, **options) -> None:
        options.setdefault("timing_adaptation", True)
        options.setdefault("late_adjustment", True)
        super().__init__(**options)
        self.nlp = TimingNLP(self.lipm.omega, TimingWeights(**(timing_weights or {})))
        self.last_timing: TimingSolution | None = None
        """The program's last solution (None before the first)."""
        self.nb_nlp_failures = 0
        """Ticks since the last reset where the program did not converge (the capture-point
        offset was used)."""
        self._nlp_offset: np.ndarray | None = None

    def _reset(self, schedule, initial_state):
        self.nlp.reset()
        self.last_timing, self.nb_nlp_failures, self._nlp_offset = None, 0, None
        return super()._reset(schedule, initial_state)

    def _landing_advance(self, t: float, x0: np.ndarray, k: int) -> float:
        """Solve the program for the next landing; how much earlier [s] step ``k`` lands."""
        slots, schedule = self._slots, self.schedule
        assert slots is not None and schedule is not None  # set by reset()
        self._nlp_offset = None
        j = k if t < slots.landing[k] - 1e-9 else k + 1  # the next landing
        if j >= slots.nb_steps:
            return 0.0
        problem = self._problem(t, x0, j)
        solution = self.last_timing = self.nlp.solve(problem)
        if not solution.success:
            self.nb_nlp_failures += 1
            self.nlp.reset()
            return 0.0
        self._nlp_offset = solution.landings[0] - slots.nominal[2 + j]
        advance = float(problem.durations[0] - solution.durations[0])
        if j != k or t < self._lift_off(k) or advance < self.control_period:
            return 0.0
        return advance

    def _capture_offset(self, t: float, first_landing: float) -> np.ndarray:
        """The program's move of the next landing from the plan (the QP's footstep targets),
        or the capture-point offset when it did not converge."""
        if self._nlp_offset is not None:
            return self._nlp_offset
        return super()._capture_offset(t, first_landing)

    def _problem(self, t: float, x0: np.ndarray, j: int) -> TimingProblem:
        """The program of the landing of step ``j`` at ``t`` [s] from the CoM state ``x0``."""
        slots, schedule = self._slots, self.schedule
        assert slots is not None and schedule is not None
        T, omega = schedule.step_duration, self.lipm.omega
        nb = slots.nb_steps
        support, lift = slots.support[j], 2 + j
        following = min(j + 1, nb - 1)
        nominal = slots.nominal[[lift, 2 + following]].copy()
        if following == j:  # the last step: the second landing beside the first
            nominal[1] = slots.positions[support]
        final = 0.5 * (slots.nominal[-1] + slots.nominal[slots.support[nb - 1]])
        offsets = nominal_offsets(slots.nominal[2 + j :], final, omega, T)
        offsets = np.vstack([offsets, np.zeros((2, 2))])[:2]
        remaining = float(slots.landing[j]) - t
        swing_start = self._lift_off(j)
        earliest = max(self.control_period, swing_start + self.min_swing - t)
        durations = np.array([[min(earliest, remaining), remaining], [0.0, T]])
        durations[1, 0] = schedule.t_b + self.min_swing + (T - schedule.t_e)
        reach = np.array([np.asarray(b)[:, :2] for b in slots.bounds[j : j + 2]])
        if following == j:
            reach = np.array([reach[0], [[-np.inf, -np.inf], [np.inf, np.inf]]])
        box = np.array([[-np.inf, -np.inf], [np.inf, np.inf]])
        if slots.late is not None:
            half = slots.late.landing_change_bound(remaining - self.control_period)
            box = slots.positions[lift] + np.array([[-half], [half]])
        yaws = slots.yaws
        return TimingProblem(
            dcm=x0[0] + x0[1] / omega + self.dcm_error,
            stance=slots.positions[support],
            stance_yaw=float(yaws[support]),
            nominal=nominal,
            offsets=offsets,
            durations=np.array([remaining, T]),
            duration_bounds=durations,
            reach=reach,
            landing_yaw=float(yaws[lift]),
            half_sole=0.5 * np.array([schedule.foot.length, schedule.foot.width]),
            box=box,
        )
