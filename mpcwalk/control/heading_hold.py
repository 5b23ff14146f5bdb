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

**Position too** (``position=True``, the controller's ``hold_position``; off by default): the
same error is carried in position as well.
The swing foot lands where the model puts it relative to its support foot, so a support
foot that landed, slid or twisted off its footstep moves every later landing by as much,
and the errors of all the steps add up (`g1` up and down five 16.5 cm stairs with the
heading alone: landings 5.3 cm off the plan on average, 10 cm at worst, every one short of
its tread and to its side). With the position held, the hold measures the support foot's
whole horizontal pose (the estimate: leg kinematics anchored at its contact, IMU heading)
against the pose the model holds it at (its footstep in the schedule the controller
follows), and moves the footsteps still to come to the original plan's footholds carried
by that difference (the turn and the shift that take the measured support foot onto the
model's): the next landing is then where the original plan has it in the world, up to the
estimate's own drift. Their heights, roll and pitch stay the plan's (the terrain's). The
turn is clamped to ``max_correction`` and the shift to ``max_shift`` per step.
"""

import math

import numpy as np

from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, rotation_2d, wrap_angle
from mpcwalk.gait.contact_schedule import ContactSchedule

#: Below this yaw error [rad] the footsteps are left alone (no schedule rebuilt).
YAW_DEADBAND = math.radians(0.05)
#: Below this position error [m] (holding the position too) the footsteps are left alone.
POSITION_DEADBAND = 5e-4
#: Largest shift of the footsteps per step [sole lengths] of the hold of a controller
#: (:meth:`HeadingHold.maybe`) holding the position too.
MAX_SHIFT_SOLES = 0.5


class HeadingHold:
    """Turns the footsteps still to come by the measured heading error of the support foot.

    Args:
        plan: The walk's original footstep plan (the headings, and footholds, to hold).
        max_correction: Largest turn of the remaining footsteps per step [rad], > 0.
        position: Hold the footholds' positions too (see the module's documentation).
        max_shift: Largest shift of the remaining footsteps per step [m], > 0 (holding the
            position).

    Raises:
        ConfigurationError: ``max_correction`` or ``max_shift`` not a positive number.
    """

    def __init__(
        self,
        plan: FootstepPlan,
        *,
        max_correction: float = 0.1,
        position: bool = False,
        max_shift: float = 0.05,
    ) -> None:
        for name, value, unit in (
            ("max_correction", max_correction, "angle [rad]"),
            ("max_shift", max_shift, "distance [m]"),
        ):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
                raise ConfigurationError(f"{name} must be a positive {unit}, got {value!r}.")
        self.plan = plan
        self.max_correction = float(max_correction)
        self.position = bool(position)
        self.max_shift = float(max_shift)
        self._checked_step = -1
        self.corrections: list[tuple[int, float]] = []
        """(step, turn [rad]) of every correction made."""
        self.shifts: list[tuple[int, float]] = []
        """(step, shift [m]) of every correction made holding the position (the change of
        the hold's shift at that step)."""
        self._held_motion: tuple[float, np.ndarray] = (0.0, np.zeros(2))

    def restarted(self) -> "HeadingHold":
        """A hold of the same plan and settings with nothing checked (a new walk)."""
        return HeadingHold(
            self.plan,
            max_correction=self.max_correction,
            position=self.position,
            max_shift=self.max_shift,
        )

    @classmethod
    def maybe(
        cls,
        schedule: ContactSchedule,
        enabled: bool | None,
        feedback: bool,
        generator,
        stabilizer,
        *,
        position: bool = False,
    ) -> "HeadingHold | None":
        """The hold of a controller walking ``schedule``, or None: ``enabled``, or when None,
        on with ``feedback`` for generators that follow new footsteps unless the stabilizer
        re-aims the steps; ``position``: see the class (its shifts bounded by
        :data:`MAX_SHIFT_SOLES` of the schedule's sole length)."""
        if enabled is None:
            enabled = bool(feedback) and bool(getattr(generator, "follows_new_footsteps", False))
            enabled = enabled and not getattr(stabilizer, "holds_heading", False)
        if not enabled:
            return None
        max_shift = MAX_SHIFT_SOLES * schedule.foot.length
        return cls(schedule.plan, position=bool(position), max_shift=max_shift)

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
        if self.position:
            return self._held(k, schedule, support, estimate, index)
        measured = float(estimate.sole_yaws[index])
        error = float(wrap_angle(measured - self.plan.support_foot(k).yaw))
        if abs(error) < YAW_DEADBAND:
            return None
        turn = float(np.clip(-error, -self.max_correction, self.max_correction))
        self.corrections.append((k, turn))
        steps = list(schedule.plan.steps)
        steps[k:] = [_turned(step, support, turn) for step in steps[k:]]
        return schedule.with_steps(steps)

    def _held(
        self,
        k: int,
        schedule: ContactSchedule,
        support: Footstep,
        estimate: EstimatedState,
        index: int,
    ) -> ContactSchedule | None:
        """The footsteps from ``k`` on: the original plan's, carried by the motion that
        takes the measured support foot onto ``support`` (the model's), or None when they
        are there already."""
        measured_xy = np.asarray(estimate.sole_positions[index][:2], dtype=float)
        measured_yaw = float(estimate.sole_yaws[index])
        turn = float(wrap_angle(support.yaw - measured_yaw))
        shift = support.xy - measured_xy
        # the hold's own motion changes by at most max_correction and max_shift per step
        last_turn, last_shift = self._held_motion
        turn = last_turn + float(
            np.clip(turn - last_turn, -self.max_correction, self.max_correction)
        )
        change = shift - last_shift
        norm = float(np.linalg.norm(change))
        if norm > self.max_shift:
            shift = last_shift + change * (self.max_shift / norm)
        self._held_motion = (turn, shift)
        rotation = rotation_2d(turn)
        steps = list(schedule.plan.steps)
        moved = False
        for j in range(k, len(steps)):
            original = self.plan.steps[j]
            xy = rotation @ (original.xy - measured_xy) + measured_xy + shift
            yaw = float(wrap_angle(original.yaw + turn))
            current = steps[j]
            if (
                float(np.max(np.abs(xy - current.xy))) < POSITION_DEADBAND
                and abs(float(wrap_angle(yaw - current.yaw))) < YAW_DEADBAND
            ):
                continue
            position = np.array([xy[0], xy[1], original.position[2]])
            steps[j] = original.moved(position=position, yaw=yaw)
            moved = True
        if not moved:
            return None
        self.corrections.append((k, turn - last_turn))  # what this step added
        self.shifts.append((k, float(np.linalg.norm(shift - last_shift))))
        return schedule.with_steps(steps)


def _turned(step: Footstep, pivot: Footstep, angle: float) -> Footstep:
    """``step`` turned by ``angle`` [rad] about the vertical through ``pivot``'s sole centre
    (its height, roll and pitch kept)."""
    c, s = math.cos(angle), math.sin(angle)
    d = step.xy - pivot.xy
    xy = pivot.xy + np.array([c * d[0] - s * d[1], s * d[0] + c * d[1]])
    return step.moved(position=np.array([xy[0], xy[1], step.position[2]]), yaw=step.yaw + angle)
