"""Paper A's path follower: re-aim every step at the file's global target.

Paper A (sec. 3.3) walks a path of global footstep poses read from a file.
Before each step it takes the swing foot's target into the frame of the
actual support foot, moves it into the reachability rectangle if needed and
corrects the difference in the following steps, comparing the actual global
pose with the file so that the drift does not accumulate.

The re-aiming moves a landing horizontally (x, y, yaw): its height, roll and pitch are
the file's (a foot on a tilted tread stays tilted), or the ground's where it lands when a
height map is given.
"""

from collections.abc import Sequence

import numpy as np

from mpcwalk.exceptions import ConfigurationError, InfeasibleStep
from mpcwalk.footsteps.footstep import (
    Footstep,
    FootstepPlan,
    HeightMap,
    Side,
    StepTiming,
    wrap_angle,
)
from mpcwalk.footsteps.reachability import (
    ATLAS_REACHABILITY,
    CLAMP_TOLERANCE,
    ClampedStep,
    ReachabilityRectangle,
)


def _same_pose(a: Footstep, b: Footstep) -> bool:
    """True when the poses agree: position (height too), yaw, roll and pitch."""
    return bool(
        np.max(np.abs(a.position - b.position)) <= CLAMP_TOLERANCE
        and abs(float(wrap_angle(a.yaw - b.yaw))) <= CLAMP_TOLERANCE
        and abs(a.roll - b.roll) <= CLAMP_TOLERANCE
        and abs(a.pitch - b.pitch) <= CLAMP_TOLERANCE
    )


class PathFollower:
    """Paper A's rule for walking a path of global footstep targets.

    Before each step the swing foot's target is taken into the frame of the
    *actual* support foot (planned, or measured by the caller) and clamped
    into the reachability rectangle. A clamped target stays pending: extra
    steps are inserted (the other foot re-aims at its own file pose, then the
    clamped foot at its target again) until it is reached. Every landing aims
    at the file's global pose, so neither clamping nor measured drift
    accumulates.

    The extra step of the other foot aims at where the file puts that foot
    while the pending target is reached. In forward walking that pose lies
    behind the rectangle, so the foot lands at the nearest safe point, i.e.
    it is drawn forward, and the next attempt of the clamped foot starts
    closer to its target. A target still out of reach after
    ``max_extra_steps`` extra steps is an error of the path, not of the
    walk: :class:`~mpcwalk.exceptions.InfeasibleStep` names it.

    Args:
        initial_left: Left foot before the first step.
        initial_right: Right foot before the first step.
        targets: Global landings in walking order (usually alternating sides).
        rectangle: Safe landings around the support foot.
        labels: Names of the targets for error messages (e.g. ``"line 7"``).
        max_extra_steps: Extra steps allowed per target before giving up.
        height_map: Ground at a point, ``(x, y) -> (z [m], roll [rad], pitch [rad])`` (world
            roll and pitch of the ground), where a clamped landing takes its height and tilt;
            None (default): a clamped landing keeps its target's height, roll and pitch.
    """

    def __init__(
        self,
        initial_left: Footstep,
        initial_right: Footstep,
        targets: Sequence[Footstep],
        rectangle: ReachabilityRectangle = ATLAS_REACHABILITY,
        *,
        labels: Sequence[str] | None = None,
        max_extra_steps: int = 10,
        height_map: HeightMap | None = None,
    ) -> None:
        if initial_left.side is not Side.LEFT or initial_right.side is not Side.RIGHT:
            raise ConfigurationError(
                "PathFollower needs initial_left on the left and initial_right on the right."
            )
        if (
            isinstance(max_extra_steps, bool)
            or not isinstance(max_extra_steps, (int, np.integer))
            or max_extra_steps < 0
        ):
            raise ConfigurationError(
                f"max_extra_steps must be a non-negative integer, got {max_extra_steps!r}."
            )
        self.targets: tuple[Footstep, ...] = tuple(targets)
        if labels is None:
            labels = [f"target {j}" for j in range(len(self.targets))]
        self.labels: tuple[str, ...] = tuple(labels)
        if len(self.labels) != len(self.targets):
            raise ConfigurationError(
                f"Got {len(self.labels)} labels for {len(self.targets)} targets; give one each."
            )
        self.rectangle = rectangle
        self.max_extra_steps = int(max_extra_steps)
        self.height_map = height_map
        self.initial = {Side.LEFT: initial_left, Side.RIGHT: initial_right}
        poses = dict(self.initial)
        self._file_before = []  # file pose of each foot before target j
        for target in self.targets:
            self._file_before.append(dict(poses))
            poses[target.side] = target
        self._file_final = poses
        self._next = 0
        self._extra = 0
        self._commanded = dict(self.initial)
        self._last_swing: Side | None = None
        self.steps_taken: list[Footstep] = []
        """Landings returned so far, in order (world frame)."""
        self.nb_clamped_steps = 0
        """Steps whose target was moved into the rectangle."""
        self.nb_extra_steps = 0
        """Steps that did not complete a target (clamped or inserted)."""

    @property
    def finished(self) -> bool:
        """True once every target is reached and both feet stand on the file's last poses."""
        return self._next == len(self.targets) and all(
            _same_pose(self._commanded[s], self._file_final[s]) for s in Side
        )

    @property
    def next_swing_side(self) -> Side:
        """Foot expected to swing next (sides alternate)."""
        if self._last_swing is not None:
            return self._last_swing.other
        return self.targets[0].side if self.targets else Side.RIGHT

    def next_step(self, actual_support: Footstep, actual_swing: Footstep) -> Footstep:
        """Landing of the next step, re-aimed from the actual feet.

        Args:
            actual_support: Support foot now (measured pose, or the planned
                one in open loop); its yaw may come from the IMU.
            actual_swing: Foot about to swing; only its side is used, since
                the landing aims at the absolute file pose.

        Returns:
            The (possibly clamped) world landing of ``actual_swing.side``.

        Raises:
            InfeasibleStep: The pending target is still out of reach after
                ``max_extra_steps`` extra steps.
        """
        if actual_support.side is actual_swing.side:
            raise ConfigurationError(
                f"actual_support and actual_swing must be different feet, both are {actual_swing.side.value}."
            )
        if self.finished:
            raise ConfigurationError(
                "The path is finished (PathFollower.finished is True); no step is left."
            )
        side = actual_swing.side
        pending = self._next < len(self.targets)
        regular = pending and self.targets[self._next].side is side
        if regular:
            goal = self.targets[self._next]
        else:  # extra step: this foot re-aims at its own file pose
            goal = self._file_before[self._next][side] if pending else self._file_final[side]
        label = self.labels[self._next] if pending else "final stance"
        result = self.rectangle.clamp_footstep(actual_support, goal, self.height_map)
        self.nb_clamped_steps += int(result.local.was_clamped)
        if regular and not result.local.was_clamped:
            self._next += 1
            self._extra = 0
        else:
            self._extra += 1
            self.nb_extra_steps += 1
            if self._extra > self.max_extra_steps:
                raise InfeasibleStep(self._message(label, goal, actual_support, result.local))
        self._commanded[side] = result.footstep
        self._last_swing = side
        self.steps_taken.append(result.footstep)
        return result.footstep

    def _message(self, label: str, goal: Footstep, support: Footstep, local: ClampedStep) -> str:
        target = np.array([*(local.xy + local.remainder[:2]), local.yaw + local.remainder[2]])
        lower, upper = self.rectangle.bounds(goal.side)
        names, units = ("x", "y", "yaw"), ("m", "m", "rad")
        broken = [
            f"{n} = {v:.4g} {u} {'above' if v > hi else 'below'} its limit {hi if v > hi else lo:g} {u}"
            for n, v, lo, hi, u in zip(names, target, lower, upper, units)
            if v > hi + CLAMP_TOLERANCE or v < lo - CLAMP_TOLERANCE
        ]
        return (
            f"{label}: the {goal.side.value} foot target (x={goal.xy[0]:.4g}, y={goal.xy[1]:.4g} m, "
            f"yaw={goal.yaw:.4g} rad) is still out of reach after {self.max_extra_steps} extra steps; "
            f"in the {support.side.value} support-foot frame {'; '.join(broken) or 'it lies on the border'} "
            f"(reachability rectangle for the {goal.side.value} foot: {self.rectangle.describe()}"
            f"{', mirrored in y and yaw' if goal.side is Side.RIGHT else ''}). "
            "Shorten that step in the path or widen the rectangle."
        )

    def plan(self, timing: StepTiming | None = None) -> FootstepPlan:
        """Finish the path in open loop (actual = commanded) and return the whole plan.

        Steps already taken through :meth:`next_step` are kept; the rest
        assumes every landing lands where it was commanded.

        Args:
            timing: Timing of the plan (default ``StepTiming()``).

        Raises:
            InfeasibleStep: A target stays out of reach.
        """
        feet = self._commanded
        while not self.finished:
            side = self.next_swing_side
            self.next_step(feet[side.other], feet[side])
        return FootstepPlan(
            self.initial[Side.LEFT],
            self.initial[Side.RIGHT],
            tuple(self.steps_taken),
            timing if timing is not None else StepTiming(),
        )
