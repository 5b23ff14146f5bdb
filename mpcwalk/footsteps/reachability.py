"""Reachability rectangle and the path follower of paper A (sec. 3.3).

Before each step, paper A expresses the swing foot's global target in the
frame of the current support foot (origin at the sole centre, axes turned
with it). A precomputed rectangle of that frame holds the safe landings (leg
workspace plus stability). A target outside it is moved to the nearest safe
point and the difference is made up later; because every step re-aims at the
file's global target from the *actual* support pose, errors never accumulate.

The rectangle bounds the horizontal pose ``(x, y, yaw)`` of the landing in the support
foot's horizontal frame (its heading): footsteps on tilted treads keep their height, roll
and pitch when moved into it, or take them from a height map when one is given.

Conventions (one rectangle serves both feet):
    The rectangle is written for a LEFT swing foot over a RIGHT support foot:
    ``y`` is the lateral distance to the left (outward, positive) and ``yaw``
    is positive when the toes turn outward (left). For a RIGHT swing foot the
    rectangle is mirrored about the support foot's x axis: ``y`` lies in
    ``[-y_max, -y_min]`` and ``yaw`` in ``[-yaw_max, -yaw_min]``.
"""

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Footstep, HeightMap, Side, wrap_angle

#: Below this a remainder counts as zero ([m] and [rad]).
CLAMP_TOLERANCE = 1e-9


class ClampedStep(NamedTuple):
    """A swing-foot landing clamped into the reachability rectangle.

    Attributes:
        xy: Clamped landing in the support-foot frame, shape (2,), in [m].
        yaw: Clamped yaw relative to the support foot, in [rad].
        remainder: ``target - clamped`` as ``(dx [m], dy [m], dyaw [rad])`` in
            the support-foot frame, shape (3,); zeros when the target was safe.
    """

    xy: np.ndarray
    yaw: float
    remainder: np.ndarray

    @property
    def was_clamped(self) -> bool:
        """True when the target lay outside the rectangle."""
        return bool(np.max(np.abs(self.remainder)) > CLAMP_TOLERANCE)


class ClampedFootstep(NamedTuple):
    """World landing after clamping, with the local details.

    Attributes:
        footstep: Landing pose in the world frame.
        local: Clamping in the support-foot frame.
    """

    footstep: Footstep
    local: ClampedStep


@dataclass(frozen=True)
class ReachabilityRectangle:
    """Safe swing-foot landings in the support-foot frame (LEFT swing, RIGHT support).

    Attributes:
        x_min: Furthest landing behind the support foot (negative), in [m].
        x_max: Furthest landing ahead of the support foot, in [m].
        y_min: Smallest outward lateral distance between the sole centres
            (self-collision), in [m]; must be positive.
        y_max: Largest outward lateral distance (leg reach), in [m].
        yaw_min: Most inward toe turn (negative), in [rad].
        yaw_max: Most outward toe turn, in [rad].
    """

    x_min: float
    x_max: float
    y_min: float
    y_max: float
    yaw_min: float
    yaw_max: float

    def __post_init__(self) -> None:
        values = np.array(
            [self.x_min, self.x_max, self.y_min, self.y_max, self.yaw_min, self.yaw_max]
        )
        if not np.all(np.isfinite(values)):
            raise ConfigurationError(
                f"ReachabilityRectangle bounds must be finite numbers, got {self!r}."
            )
        for lo, hi, unit in (
            ("x_min", "x_max", "m"),
            ("y_min", "y_max", "m"),
            ("yaw_min", "yaw_max", "rad"),
        ):
            if getattr(self, lo) > getattr(self, hi):
                raise ConfigurationError(
                    f"ReachabilityRectangle needs {lo} <= {hi}, got {getattr(self, lo):g} > "
                    f"{getattr(self, hi):g} {unit}; swap them."
                )
        if self.y_min <= 0.0:
            raise ConfigurationError(
                f"ReachabilityRectangle.y_min must be positive (the swing foot stays on its own "
                f"side of the support foot), got {self.y_min:g} m."
            )
        if self.yaw_min <= -np.pi / 2 or self.yaw_max >= np.pi / 2:
            raise ConfigurationError(
                f"ReachabilityRectangle yaw bounds must lie in (-pi/2, pi/2), got "
                f"[{self.yaw_min:g}, {self.yaw_max:g}] rad."
            )

    def bounds(self, side) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds of ``(x, y, yaw)`` for a swing foot of ``side``.

        Returns:
            ``(lower, upper)``, each of shape (3,), in [m, m, rad]; mirrored
            (y and yaw negated and swapped) for a RIGHT swing foot.
        """
        if Side.parse(side) is Side.LEFT:
            return (
                np.array([self.x_min, self.y_min, self.yaw_min]),
                np.array([self.x_max, self.y_max, self.yaw_max]),
            )
        return (
            np.array([self.x_min, -self.y_max, -self.yaw_max]),
            np.array([self.x_max, -self.y_min, -self.yaw_min]),
        )

    def clamp(self, target_local_xy, yaw: float, side) -> ClampedStep:
        """Nearest safe landing to a target given in the support-foot frame.

        The rectangle is a box in ``(x, y, yaw)``, so the nearest point (in
        each coordinate) is the coordinate-wise clip.

        Args:
            target_local_xy: Target position in the support-foot frame, (2,), [m].
            yaw: Target yaw relative to the support foot, in [rad] (wrapped).
            side: Side of the swing foot.

        Returns:
            The clamped landing and the remainder ``target - clamped``.
        """
        yaw = float(yaw)
        if not -np.pi <= yaw < np.pi:  # wrap only when needed: no round-off on in-range angles
            yaw = float(wrap_angle(yaw))
        target = np.array([*np.asarray(target_local_xy, dtype=float)[:2], yaw])
        if not np.all(np.isfinite(target)):
            raise ConfigurationError(
                f"Footstep target must be finite, got {target_local_xy!r}, yaw {yaw!r}."
            )
        lower, upper = self.bounds(side)
        clamped = np.clip(target, lower, upper)
        return ClampedStep(clamped[:2], float(clamped[2]), target - clamped)

    def contains(
        self, target_local_xy, yaw: float, side, tolerance: float = CLAMP_TOLERANCE
    ) -> bool:
        """True when the target (support-foot frame) is a safe landing."""
        return not (np.max(np.abs(self.clamp(target_local_xy, yaw, side).remainder)) > tolerance)

    def clamp_footstep(
        self, support: Footstep, target: Footstep, height_map: HeightMap | None = None
    ) -> ClampedFootstep:
        """Clamp a world target into this rectangle around ``support``.

        The rectangle bounds the horizontal pose (x, y, yaw); a clamped landing keeps the
        target's height, roll and pitch, never flattened, unless ``height_map`` gives the
        ground where it lands (:meth:`~mpcwalk.footsteps.footstep.Footstep.on_height_map`).

        Args:
            support: Actual (or planned) support foot; its horizontal pose alone counts.
            target: Desired landing of the other foot, world frame.
            height_map: Ground at a point, ``(x, y) -> (z, roll, pitch)`` (world roll and
                pitch of the ground), for the landings moved by the clamping; None keeps
                the target's. A target inside the rectangle is returned as it is.

        Returns:
            The safe landing in the world and the local clamping details.
        """
        if target.side is support.side:
            raise ConfigurationError(
                f"The swing foot and the support foot must differ, both are {target.side.value}."
            )
        local = self.clamp(support.to_local(target.xy), target.yaw - support.yaw, target.side)
        if not local.was_clamped:
            # keep the exact target (no round-off from the frame changes)
            return ClampedFootstep(target, local)
        xy = support.to_world(local.xy)
        landing = target.moved(
            position=np.array([xy[0], xy[1], target.position[2]]),
            yaw=float(wrap_angle(support.yaw + local.yaw)),
        )
        return ClampedFootstep(landing.on_height_map(height_map), local)

    def describe(self) -> str:
        """Human-readable bounds, for error messages."""
        return (
            f"x in [{self.x_min:g}, {self.x_max:g}] m, outward y in [{self.y_min:g}, {self.y_max:g}] m, "
            f"outward yaw in [{self.yaw_min:g}, {self.yaw_max:g}] rad"
        )


#: Atlas-like robot (paper A). Assumed sole 0.25 m x 0.13 m, hip width about
#: 0.22 m. Forward reach 0.30 m and backward 0.15 m keep the static CoM over
#: the support foot in slow walking; sole centres at least 0.18 m apart leave
#: 0.05 m between the inner edges; 0.40 m is the widest stance of the leg. An
#: inward toe turn of 0.4 rad moves the inner toe corner 0.044 m towards the
#: other foot, which still clears it (by 6 mm) at the minimum separation.
ATLAS_REACHABILITY = ReachabilityRectangle(
    x_min=-0.15, x_max=0.30, y_min=0.18, y_max=0.40, yaw_min=-0.4, yaw_max=0.4
)

#: Small servo humanoid (paper M): the rectangle of the default LegLimits of
#: the velocity planner (x in [-0.04, 0.08] m, sole centres 0.08-0.14 m
#: apart, toes 0.2 rad inward to 0.35 rad outward).
SMALL_HUMANOID_REACHABILITY = ReachabilityRectangle(
    x_min=-0.04, x_max=0.08, y_min=0.08, y_max=0.14, yaw_min=-0.2, yaw_max=0.35
)


def opening_side(lateral: float, yaw_rate: float, default: Side = Side.RIGHT) -> Side:
    """Which foot should step first so that the first step opens the stance.

    Stepping first with the foot on the side of the motion moves it outward
    (away from the other foot); the other foot then closes in. The opposite
    order would start with an inward step against the self-collision limit.
    A lateral motion decides first (it hits the separation limit), then the
    turning direction, else ``default``.

    Args:
        lateral: Lateral velocity or displacement (positive to the left).
        yaw_rate: Yaw rate or yaw change (positive counter-clockwise).
        default: Side when both are zero.
    """
    if lateral > CLAMP_TOLERANCE or lateral < -CLAMP_TOLERANCE:
        return Side.LEFT if lateral > 0.0 else Side.RIGHT
    if yaw_rate > CLAMP_TOLERANCE or yaw_rate < -CLAMP_TOLERANCE:
        return Side.LEFT if yaw_rate > 0.0 else Side.RIGHT
    return Side.parse(default)
