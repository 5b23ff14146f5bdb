"""Heading hold: the walk turns as much as it was told to, whatever its feet slip.

A position-controlled robot realises its kinematic reference relative to the foot it stands
on: each step lands where it was planned *relative to the support foot*. When the support
foot twists on the ground during single support (the swing leg's yaw reaction, soft
contacts), the error is carried into every later step, and a long turning walk ends tens of
degrees short of, or beyond, its command (bioloid-like: 2011 deg instead of 2063 deg after
120 s of ``mpc`` at 0.3 rad/s, 2.5 % short, landings up to 33 cm off the plan) while every
step is within millimetres of its support foot. With the hold: 2062 deg, landings within
3.6 cm.

The hold measures, once per step, in the double support before the swing foot lifts, the
yaw of the support foot (the estimate: IMU heading and leg kinematics) against the yaw it
has in the *original* plan, and turns the footsteps that are not yet lifted about the support
foot by that error (clamped to ``max_correction`` per step). The next landing is then where
the original plan has it in heading: the yaw error stays within one step's slip instead of
growing with the walk. The generator follows the turned footsteps from that tick on (only
generators that read the schedule at every tick: :attr:`PatternGenerator.follows_new_footsteps`).
"""

import math

import numpy as np

from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, wrap_angle
from mpcwalk.gait.contact_schedule import ContactSchedule

#: Below this yaw error [rad] the footsteps are left alone (no schedule rebuilt).
YAW_DEADBAND = math.radians(0.05)


class HeadingHold:
    """Turns the footsteps still to come by the measured heading error of the support foot.

    Args:
        plan: The walk's original footstep plan (the headings to hold).
        max_correction: Largest turn of the remaining footsteps per step [rad], > 0.

    Raises:
        ConfigurationError: ``max_correction`` not a positive number.
    """

    def __init__(self, plan: FootstepPlan, *, max_correction: float = 0.1) -> None:
        if not (math.isfinite(max_correction) and max_correction > 0.0):
            raise ConfigurationError(
                f"max_correction must be a positive angle [rad], got {max_correction!r}."
            )
        self.plan = plan
        self.max_correction = float(max_correction)
        self._checked_step = -1
        self.corrections: list[tuple[int, float]] = []
        """(step, turn [rad]) of every correction made."""

    @classmethod
    def maybe(
        cls, plan: FootstepPlan, enabled: bool | None, feedback: bool, generator, stabilizer
    ) -> "HeadingHold | None":
        """The hold of a controller, or None: ``enabled``, or when None, on with ``feedback``
        for generators that follow new footsteps unless the stabilizer re-aims the steps."""
        if enabled is None:
            enabled = bool(feedback) and bool(getattr(generator, "follows_new_footsteps", False))
            enabled = enabled and not getattr(stabilizer, "holds_heading", False)
        return cls(plan) if enabled else None

    @property
    def total_correction(self) -> float:
        """Sum of the turns made so far [rad]."""
        return float(sum(turn for _, turn in self.corrections))

    def update(
        self, t: float, schedule: ContactSchedule, estimate: EstimatedState | None
    ) -> ContactSchedule | None:
        """The schedule with its remaining footsteps turned, or None (nothing to do now).

        Checked once per step ``k``, between the start of its double support and the lift of
        its swing foot, with both feet in contact in the estimate.
        """
        if estimate is None or t < schedule.walk_start:
            return None
        k = int(math.floor((t - schedule.walk_start) / schedule.step_duration + 1e-9))
        if k <= self._checked_step or k >= schedule.plan.nb_steps:
            return None
        phase = t - schedule.walk_start - k * schedule.step_duration
        if phase > schedule.t_b or not all(foot.in_contact for foot in estimate.feet):
            return None  # the swing foot lifts (or lifted): wait for the next step
        self._checked_step = k
        support = schedule.plan.support_foot(k)
        index = 0 if support.side is Side.LEFT else 1
        measured = float(estimate.sole_yaws[index])
        error = float(wrap_angle(measured - self.plan.support_foot(k).yaw))
        if abs(error) < YAW_DEADBAND:
            return None
        turn = float(np.clip(-error, -self.max_correction, self.max_correction))
        self.corrections.append((k, turn))
        steps = list(schedule.plan.steps)
        steps[k:] = [_turned(step, support, turn) for step in steps[k:]]
        return schedule.with_steps(steps)


def _turned(step: Footstep, pivot: Footstep, angle: float) -> Footstep:
    """``step`` turned by ``angle`` [rad] about the vertical through ``pivot``'s sole centre
    (its height, roll and pitch kept)."""
    c, s = math.cos(angle), math.sin(angle)
    d = step.xy - pivot.xy
    xy = pivot.xy + np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])
    return step.moved(position=np.array([xy[0], xy[1], step.position[2]]), yaw=step.yaw + angle)
