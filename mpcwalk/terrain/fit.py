"""Whether a terrain fits a robot: every tread holds its sole, every rise is within its
legs' reach (:func:`check_terrain`), checked before a walk starts."""

import math
from dataclasses import dataclass

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import TerrainError
from mpcwalk.terrain.features import Platform, RoughPatch, Slope, Stairs, SteppingStones
from mpcwalk.terrain.terrain import Terrain

#: Largest rise of one step as a share of the leg length (the hip's height above the sole
#: in the nominal posture): half a leg lifts the swing sole above the nose with the knee
#: bent to about 90 deg.
MAX_RISE_RATIO = 0.5
#: Largest height a swing foot climbs or drops from its lift-off to its landing, as a share
#: of the leg length: stepping over a tread (one foot per tread) lifts the foot by two rises,
#: so above half this share the feet meet on every tread (two feet per tread).
MAX_SWING_RISE_RATIO = 0.25
#: Longest stride (sole centre to sole centre) on a terrain as a share of the leg length.
MAX_STRIDE_RATIO = 0.8
#: Steepest slope [deg] a flat sole stands on (with the friction of the scene, 1.0).
MAX_WALKABLE_SLOPE_DEG = 20.0
#: Largest angle [deg] between two tops meeting without a step (a ramp's foot or brow) that a
#: sole may straddle. The sole then rests on the ground's upper hull under it: on both tops
#: at a hollow, on the brow and one top at a crest, at most the sole's half length times the
#: angle's tangent (9 mm for a 0.2 m sole) off the other top. Without it a sole must land
#: wholly on one side, so every ramp's foot and brow asks a stride of a sole length and two
#: margins, longer than a small humanoid's or g1's longest flat step.
MAX_STRADDLED_KINK_DEG = 5.0


@dataclass(frozen=True)
class TerrainReach:
    """What a robot's legs and soles can cross.

    Attributes:
        sole_length: Sole length [m].
        sole_width: Sole width [m].
        leg_length: Hip height above the soles in the nominal posture [m].
        max_stride: Farthest landing ahead of the support foot [m] (centre to centre).
        tread_margin: Distance [m] a sole keeps from a tread's edges (default: a tenth of
            its length).
        max_slope_deg: Steepest slope [deg].
        max_kink_deg: Largest angle [deg] between two tops meeting without a step that a
            sole may straddle (:data:`MAX_STRADDLED_KINK_DEG`; 0: none).
    """

    sole_length: float
    sole_width: float
    leg_length: float
    max_stride: float
    tread_margin: float | None = None
    max_slope_deg: float = MAX_WALKABLE_SLOPE_DEG
    max_kink_deg: float = MAX_STRADDLED_KINK_DEG

    def __post_init__(self) -> None:
        for name in ("sole_length", "sole_width", "leg_length", "max_stride"):
            value = checked_number(
                f"TerrainReach.{name}",
                getattr(self, name),
                low=0.0,
                low_inclusive=False,
                unit="m",
                error=TerrainError,
            )
            object.__setattr__(self, name, value)
        if self.tread_margin is None:
            object.__setattr__(self, "tread_margin", 0.1 * self.sole_length)
        kink = checked_number(
            "TerrainReach.max_kink_deg", self.max_kink_deg, low=0.0, unit="deg", error=TerrainError
        )
        object.__setattr__(self, "max_kink_deg", kink)

    @property
    def max_kink(self) -> float:
        """:attr:`max_kink_deg` in [rad]."""
        return math.radians(self.max_kink_deg)

    @classmethod
    def for_leg(cls, sole_length: float, sole_width: float, leg_length: float) -> "TerrainReach":
        """The reach of a leg ``leg_length`` [m] long: strides of :data:`MAX_STRIDE_RATIO`
        and rises of :data:`MAX_RISE_RATIO` of it."""
        return cls(sole_length, sole_width, leg_length, MAX_STRIDE_RATIO * leg_length)

    @property
    def max_rise(self) -> float:
        """Largest rise of one step [m]."""
        return MAX_RISE_RATIO * self.leg_length

    @property
    def max_swing_rise(self) -> float:
        """Largest height [m] a swing foot climbs or drops from lift-off to landing."""
        return MAX_SWING_RISE_RATIO * self.leg_length

    @property
    def min_tread(self) -> float:
        """Shortest tread [m] that holds the sole with its margins."""
        return self.sole_length + 2.0 * float(self.tread_margin or 0.0)


def check_terrain(terrain: Terrain, reach: TerrainReach, robot: str = "the robot") -> None:
    """Refuse a terrain that does not fit a robot.

    Raises:
        TerrainError: A rise beyond ``reach.max_rise``, a tread shorter than
            ``reach.min_tread``, a gap wider than a stride, a slope steeper than
            ``reach.max_slope_deg``; the message gives the limit.
    """
    margin = float(reach.tread_margin or 0.0)

    def refuse(what: str, fix: str) -> None:
        raise TerrainError(f"The terrain does not fit {robot}: {what}; {fix}.")

    def rise(name: str, value: float) -> None:
        if abs(value) > reach.max_rise + 1e-12:
            refuse(
                f"{name} of {abs(value) * 100:.1f} cm is beyond the {reach.max_rise * 100:.1f} cm "
                f"its legs reach ({MAX_RISE_RATIO:g} x its leg length of {reach.leg_length * 100:.1f} cm)",
                f"use a rise of at most {reach.max_rise:.3f} m",
            )

    def tread(name: str, value: float) -> None:
        if value < reach.min_tread - 1e-12:
            refuse(
                f"{name} of {value * 100:.1f} cm is shorter than its sole with margins "
                f"({reach.sole_length * 100:.1f} cm + 2 x {margin * 100:.1f} cm = {reach.min_tread * 100:.1f} cm)",
                f"use at least {reach.min_tread:.3f} m",
            )

    for feature in terrain.features:
        if isinstance(feature, Stairs):
            rise("a stair rise", feature.rise)
            tread("a tread", feature.run)
            if feature.run > reach.max_stride + 1e-12 and feature.run < 2.0 * reach.min_tread:
                refuse(
                    f"a tread of {feature.run * 100:.1f} cm holds one sole but is longer than its "
                    f"{reach.max_stride * 100:.1f} cm stride",
                    "use a run within its stride or long enough for two soles",
                )
        elif isinstance(feature, Slope):
            if abs(feature.angle) > reach.max_slope_deg:
                refuse(
                    f"a slope of {abs(feature.angle):g} deg is steeper than the {reach.max_slope_deg:g} "
                    "deg its soles stand on",
                    f"use at most {reach.max_slope_deg:g} deg",
                )
        elif isinstance(feature, Platform):
            rise("a platform's height", feature.height)
            tread("a platform", feature.length)
        elif isinstance(feature, SteppingStones):
            rise("the stones' height", feature.height)
            tread("a stone", feature.length)
            if feature.width < reach.sole_width + 2.0 * margin:
                refuse(
                    f"stones {feature.width * 100:.1f} cm wide are narrower than its sole with "
                    f"margins ({(reach.sole_width + 2.0 * margin) * 100:.1f} cm)",
                    "use wider stones",
                )
            needed = feature.gap + reach.min_tread
            if needed > reach.max_stride + 1e-12:
                refuse(
                    f"a gap of {feature.gap * 100:.1f} cm needs a stride of {needed * 100:.1f} cm "
                    f"(gap + sole + margins), beyond its {reach.max_stride * 100:.1f} cm",
                    f"use a gap of at most {max(reach.max_stride - reach.min_tread, 0.0):.3f} m",
                )
        elif isinstance(feature, RoughPatch):
            rise("a block height", feature.height)
        if math.isinf(feature.start):  # pragma: no cover - features check their start
            refuse("a feature at infinity", "give a finite start")


__all__ = [
    "MAX_RISE_RATIO",
    "MAX_STRADDLED_KINK_DEG",
    "MAX_STRIDE_RATIO",
    "MAX_SWING_RISE_RATIO",
    "TerrainReach",
    "check_terrain",
]
