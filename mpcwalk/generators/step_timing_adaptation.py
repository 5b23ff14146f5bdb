"""Step timing adaptation of the footstep-adaptive MPC (Khadiv 2016, Griffin 2017).

:class:`StepTimingAdaptation` is the part of
:class:`~mpcwalk.generators.mpc_steps.FootstepMpcGenerator` that moves its schedule's clock
(``timing_adaptation``): a landing brought forward when the capture point at the planned
landing lies beyond the leg's reach (:meth:`~StepTimingAdaptation._landing_advance`), and a
lift-off put off while the DCM error points towards the foot about to lift
(:meth:`~StepTimingAdaptation._hold_lift_off`). The generator sets the attributes declared
here and calls these methods from its tick.
"""

import numpy as np

from mpcwalk.generators.receding_horizon import RecedingHorizonGenerator
from mpcwalk.qp.footstep_supports import FootstepSlots


class StepTimingAdaptation(RecedingHorizonGenerator):
    """The step timing of a footstep-adaptive generator (see the module's documentation)."""

    _slots: FootstepSlots | None
    _retimed_steps: set[int]
    _held: tuple[int, float]  # step whose lift-off is put off, how long
    min_swing: float
    max_hold: float
    hold_dcm_error: float
    nb_held: int

    def _lift_off(self, k: int) -> float:
        """When the swing foot of step ``k`` lifts, on the schedule's clock [s]."""
        assert self._slots is not None and self.schedule is not None  # set by reset()
        return float(self._slots.landing[k]) - (self.schedule.t_e - self.schedule.t_b)

    def _hold_lift_off(self, t: float) -> bool:
        """Whether this tick's output (at ``t + control_period``) would be the first past a
        lift-off that should be put off: the DCM error points towards the lifting foot by
        more than ``hold_dcm_error``, and that lift-off has been put off less than
        ``max_hold`` so far."""
        slots, schedule, dt = self._slots, self.schedule, self.control_period
        if not self.max_hold or slots is None or schedule is None:
            return False
        t_out = t + dt
        k = schedule.step_index(t_out)
        if not 0 <= k < slots.nb_steps:
            return False
        if not t_out - dt < self._lift_off(k) <= t_out + 1e-9:
            return False
        toward = slots.positions[slots.lift[k]] - slots.positions[slots.support[k]]
        toward = toward / max(float(np.linalg.norm(toward)), 1e-9)
        held = self._held[1] if self._held[0] == k else 0.0
        if float(self.dcm_error @ toward) <= self.hold_dcm_error or held >= self.max_hold - 1e-9:
            return False
        self._held = (k, held + dt)
        self.nb_held += 1
        return True

    def _landing_advance(self, t: float, x0: np.ndarray, k: int) -> float:
        """How much earlier [s] step ``k`` should land (once per step): 0 unless the capture
        point at its planned landing (the ZMP held at the stance sole's point nearest the
        DCM, the ankle's best) lies beyond the reach of step ``k``; then the landing time in
        ``[swing start + min_swing, planned]`` leaving it nearest the reachable region (the
        latest among equals)."""
        slots, schedule = self._slots, self.schedule
        if slots is None or schedule is None or k in self._retimed_steps:
            return 0.0
        landing, swing_start = float(slots.landing[k]), self._lift_off(k)
        earliest = max(t + self.control_period, swing_start + self.min_swing)
        if t < swing_start or earliest >= landing - 1e-9:
            return 0.0
        omega = self.lipm.omega
        stance = slots.positions[slots.support[k]]
        yaw = float(slots.yaws[slots.support[k]])
        rotation = np.array([[np.cos(yaw), np.sin(yaw)], [-np.sin(yaw), np.cos(yaw)]])
        lower, upper = (np.asarray(bound)[:2] for bound in slots.bounds[k])
        half_sole = 0.5 * np.array([schedule.foot.length, schedule.foot.width])
        dcm = rotation @ (x0[0] + x0[1] / omega + self.dcm_error - stance)  # stance frame
        zmp = np.clip(dcm, -half_sole, half_sole)
        times = np.linspace(earliest, landing, 9)
        local = zmp + (dcm - zmp) * np.exp(omega * (times - t))[:, None]  # capture points
        beyond = np.linalg.norm(local - np.clip(local, lower, upper), axis=1)
        if beyond[-1] <= half_sole[1]:  # within reach (give or take the sole)
            return 0.0
        best = int(np.flatnonzero(beyond <= beyond.min() + 1e-6)[-1])
        if best == len(times) - 1:
            return 0.0
        self._retimed_steps.add(k)
        return float(landing - times[best])
