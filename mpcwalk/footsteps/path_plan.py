"""Paths of paper A: stances of both feet, the single-foot steps that walk through them and
the footstep plan that follows them (the file format is :mod:`~mpcwalk.footsteps.mdat`)."""

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import (
    Footstep,
    FootstepPlan,
    HeightMap,
    Side,
    StepTiming,
    wrap_angle,
)
from mpcwalk.footsteps.path_follower import PathFollower
from mpcwalk.footsteps.reachability import (
    ATLAS_REACHABILITY,
    CLAMP_TOLERANCE,
    ReachabilityRectangle,
    opening_side,
)


@dataclass(frozen=True)
class PathWaypoint:
    """Both feet of one line of a path file.

    Attributes:
        left: Left foot pose, world frame.
        right: Right foot pose, world frame.
        line: One-based line number in its file, if read from one.
    """

    left: Footstep
    right: Footstep
    line: int | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if self.left.side is not Side.LEFT or self.right.side is not Side.RIGHT:
            raise ConfigurationError("PathWaypoint needs a left Footstep then a right Footstep.")

    def foot(self, side) -> Footstep:
        """Pose of one foot."""
        return self.left if Side.parse(side) is Side.LEFT else self.right


class PathTarget(NamedTuple):
    """One single-foot step of a path, before any clamping.

    Attributes:
        footstep: Global landing.
        waypoint_index: Index of the waypoint it reaches.
        label: Where it comes from, for messages (``"waypoint 3 (line 5)"``).
    """

    footstep: Footstep
    waypoint_index: int
    label: str


def _changed(a: Footstep, b: Footstep) -> bool:
    """True when the pose changed: position (height too), yaw, roll or pitch."""
    return bool(
        np.max(np.abs(a.position - b.position)) > CLAMP_TOLERANCE
        or abs(float(wrap_angle(a.yaw - b.yaw))) > CLAMP_TOLERANCE
        or abs(a.roll - b.roll) > CLAMP_TOLERANCE
        or abs(a.pitch - b.pitch) > CLAMP_TOLERANCE
    )


def _mid_frame(waypoint: PathWaypoint) -> Footstep:
    """Frame between the feet: midpoint position, mean yaw."""
    left, right = waypoint.left, waypoint.right
    yaw = right.yaw + 0.5 * float(wrap_angle(left.yaw - right.yaw))
    return Footstep(Side.LEFT, 0.5 * (left.position + right.position), yaw)


def path_targets(
    waypoints: Sequence[PathWaypoint], *, first_swing=None, steps_in_place: bool = False
) -> list[PathTarget]:
    """Alternating single-foot steps that walk through the waypoints.

    From waypoint ``i`` to ``i + 1`` the foot whose pose changed steps; if
    both changed, both step, the first being the foot that keeps the sides
    alternating (for the very first step: ``first_swing``, else the foot on
    the side of the motion, else the right one). An unchanged waypoint is
    skipped, or with ``steps_in_place`` becomes a step in place of the next
    foot in turn (paper A starts with two). When the same foot would move
    twice in a row, or ``first_swing`` is not the first foot to move, a step
    in place of the other foot is inserted.
    """
    if not waypoints:
        raise ConfigurationError("A path needs at least one waypoint (the initial stance).")
    moves = []  # (sides that move, waypoint index); () = step in place
    for i in range(1, len(waypoints)):
        prev, cur = waypoints[i - 1], waypoints[i]
        sides = tuple(s for s in (Side.LEFT, Side.RIGHT) if _changed(prev.foot(s), cur.foot(s)))
        if sides or steps_in_place:
            moves.append((sides, i))
    first = next((m for m in moves if m[0]), None)
    if first_swing is not None:
        last = Side.parse(first_swing).other
    elif first is None:
        last = Side.LEFT  # only steps in place: start with the right foot
    else:
        before, after = waypoints[first[1] - 1], waypoints[first[1]]
        frame = _mid_frame(before)
        one = (
            first[0][0]
            if len(first[0]) == 1
            else opening_side(
                frame.to_local(_mid_frame(after).xy)[1],
                float(wrap_angle(_mid_frame(after).yaw - frame.yaw)),
            )
        )
        in_place_before = moves.index(first)
        last = one.other if in_place_before % 2 == 0 else one
    targets: list[PathTarget] = []
    feet = {Side.LEFT: waypoints[0].left, Side.RIGHT: waypoints[0].right}
    for sides, i in moves:
        line = waypoints[i].line
        label = f"waypoint {i}" + (f" (line {line})" if line is not None else "")
        order = [last.other] if not sides else sorted(sides, key=lambda s: s is last)
        if len(sides) == 1 and sides[0] is last:
            order = [last.other, last]  # keep alternation with a step in place
        for side in order:
            pose = waypoints[i].foot(side) if side in sides else feet[side]
            targets.append(PathTarget(pose, i, label))
            feet[side] = pose
            last = side
    return targets


def plan_from_path(
    waypoints: Sequence[PathWaypoint],
    *,
    rectangle: ReachabilityRectangle = ATLAS_REACHABILITY,
    timing: StepTiming = StepTiming(),
    first_swing=None,
    steps_in_place: bool = False,
    max_extra_steps: int = 10,
    height_map: HeightMap | None = None,
) -> FootstepPlan:
    """Footstep plan of a path, walked with paper A's clamping rule in open loop.

    The first waypoint is the initial stance. Targets come from
    :func:`path_targets`; each is clamped into ``rectangle`` around the
    planned support foot and extra steps are inserted until it is reached
    (see :class:`~.path_follower.PathFollower`). A clamped landing keeps its
    target's height, roll and pitch, or takes the ground's from ``height_map``
    (``(x, y) -> (z, roll, pitch)``) when one is given.

    Raises:
        InfeasibleStep: A target stays out of reach after ``max_extra_steps``.
    """
    targets = path_targets(waypoints, first_swing=first_swing, steps_in_place=steps_in_place)
    follower = PathFollower(
        waypoints[0].left,
        waypoints[0].right,
        [t.footstep for t in targets],
        rectangle,
        labels=[t.label for t in targets],
        max_extra_steps=max_extra_steps,
        height_map=height_map,
    )
    return follower.plan(timing)
