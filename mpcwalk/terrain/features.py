"""The features a terrain is made of, laid along the robot's initial heading.

Every feature starts ``start`` [m] ahead of the robot's start (the midpoint of its initial
soles, on its initial heading: the world's x axis) and is laid on the ground *level* the
features before it left: the walk starts on a level of 0 m, stairs and slopes change the
level for everything after them, platforms, stepping stones and rough patches leave it as
they found it. :meth:`Feature.surfaces` turns a feature into the blocks' tops
(:class:`~mpcwalk.terrain.surface.Surface`) and the level after it.
"""

import math
from dataclasses import dataclass, fields
from typing import Any, ClassVar

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import TerrainError
from mpcwalk.terrain.surface import Surface

#: Steepest slope [deg] a terrain may hold.
MAX_SLOPE_DEG = 30.0
#: Largest distance [m] of a feature from the start.
MAX_DISTANCE = 50.0


def _number(feature: str, name: str, value: Any, low: float, high: float, unit: str) -> float:
    def refuse(expected: str) -> TerrainError:
        return TerrainError(f"{feature}.{name} must be {expected}, got {value!r}.")

    return checked_number(name, value, low=low, high=high, unit=unit, error=refuse)


def _integer(feature: str, name: str, value: Any, low: int, high: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise TerrainError(
            f"{feature}.{name} must be an integer in [{low}, {high}], got {value!r}."
        )


@dataclass(frozen=True)
class Feature:
    """Base of the terrain features (``start`` [m]: distance ahead of the robot's start)."""

    start: float

    #: Table name in a terrain file.
    key: ClassVar[str] = ""
    #: Whether the feature changes the level of what follows.
    changes_level: ClassVar[bool] = False

    def __post_init__(self) -> None:
        name = type(self).__name__
        object.__setattr__(
            self, "start", _number(name, "start", self.start, 0.0, MAX_DISTANCE, "m")
        )

    @property
    def extent(self) -> float:
        """Extent of the feature along the heading [m]."""
        raise NotImplementedError

    @property
    def end(self) -> float:
        """Distance [m] of the feature's far end from the start."""
        return self.start + self.extent

    def level_change(self) -> float:
        """Change of level [m] from before the feature to after it."""
        return 0.0

    def surfaces(self, level: float, half_width: float) -> list[Surface]:
        """Tops of the feature's blocks laid on ``level`` [m], ``half_width`` [m] each side
        of the heading."""
        raise NotImplementedError

    def to_dict(self) -> dict[str, float | int]:
        """The feature's fields, as a terrain file holds them."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True)
class Stairs(Feature):
    """A flight of ``count`` steps: risers ``run`` [m] apart, each ``rise`` [m] high
    (negative: down); the last riser leads to the new level."""

    rise: float = 0.15
    run: float = 0.30
    count: int = 5

    key: ClassVar[str] = "stairs"
    changes_level: ClassVar[bool] = True

    def __post_init__(self) -> None:
        super().__post_init__()
        set_ = object.__setattr__
        set_(self, "rise", _number("Stairs", "rise", self.rise, -1.0, 1.0, "m"))
        if self.rise == 0.0:
            raise TerrainError(
                "Stairs.rise must not be 0 m: use a positive rise up, negative down."
            )
        set_(self, "run", _number("Stairs", "run", self.run, 0.02, 5.0, "m"))
        _integer("Stairs", "count", self.count, 1, 100)

    @property
    def extent(self) -> float:
        return (self.count - 1) * self.run

    def level_change(self) -> float:
        return self.count * self.rise

    def surfaces(self, level: float, half_width: float) -> list[Surface]:
        return [
            Surface(
                self.start + k * self.run,
                self.start + (k + 1) * self.run,
                -half_width,
                half_width,
                level + (k + 1) * self.rise,
                kind="tread",
            )
            for k in range(self.count - 1)
        ]


@dataclass(frozen=True)
class Slope(Feature):
    """A ramp ``length`` [m] long (horizontally) at ``angle`` [deg] (negative: down)."""

    length: float = 1.0
    angle: float = 10.0

    key: ClassVar[str] = "slope"
    changes_level: ClassVar[bool] = True

    def __post_init__(self) -> None:
        super().__post_init__()
        set_ = object.__setattr__
        set_(self, "length", _number("Slope", "length", self.length, 0.05, 20.0, "m"))
        set_(
            self,
            "angle",
            _number("Slope", "angle", self.angle, -MAX_SLOPE_DEG, MAX_SLOPE_DEG, "deg"),
        )

    @property
    def extent(self) -> float:
        return self.length

    def level_change(self) -> float:
        return self.length * math.tan(math.radians(self.angle))

    def surfaces(self, level: float, half_width: float) -> list[Surface]:
        return [
            Surface(
                self.start,
                self.end,
                -half_width,
                half_width,
                level,
                math.radians(self.angle),
                "ramp",
            )
        ]


@dataclass(frozen=True)
class Platform(Feature):
    """A block ``length`` [m] long whose top is ``height`` [m] above the level (negative: a
    trench); the level goes on after it."""

    length: float = 0.5
    height: float = 0.05

    key: ClassVar[str] = "platform"

    def __post_init__(self) -> None:
        super().__post_init__()
        set_ = object.__setattr__
        set_(self, "length", _number("Platform", "length", self.length, 0.02, 20.0, "m"))
        set_(self, "height", _number("Platform", "height", self.height, -1.0, 1.0, "m"))

    @property
    def extent(self) -> float:
        return self.length

    def surfaces(self, level: float, half_width: float) -> list[Surface]:
        return [
            Surface(
                self.start, self.end, -half_width, half_width, level + self.height, kind="landing"
            )
        ]


@dataclass(frozen=True)
class SteppingStones(Feature):
    """``count`` stones ``length`` [m] deep and ``width`` [m] wide, ``gap`` [m] apart, their
    tops ``height`` [m] above the level, over a pit ``depth`` [m] below the level."""

    count: int = 4
    length: float = 0.2
    gap: float = 0.1
    width: float = 0.4
    height: float = 0.0
    depth: float = 0.2

    key: ClassVar[str] = "stones"

    def __post_init__(self) -> None:
        super().__post_init__()
        set_ = object.__setattr__
        _integer("SteppingStones", "count", self.count, 1, 100)
        set_(self, "length", _number("SteppingStones", "length", self.length, 0.02, 5.0, "m"))
        set_(self, "gap", _number("SteppingStones", "gap", self.gap, 0.0, 2.0, "m"))
        set_(self, "width", _number("SteppingStones", "width", self.width, 0.02, 5.0, "m"))
        set_(self, "height", _number("SteppingStones", "height", self.height, -1.0, 1.0, "m"))
        set_(self, "depth", _number("SteppingStones", "depth", self.depth, 0.01, 2.0, "m"))

    @property
    def pitch(self) -> float:
        """Distance [m] from one stone's back edge to the next one's."""
        return self.length + self.gap

    @property
    def extent(self) -> float:
        return self.count * self.pitch  # the last gap leads off the stones

    def surfaces(self, level: float, half_width: float) -> list[Surface]:
        stones = [
            Surface(
                self.start + k * self.pitch,
                self.start + k * self.pitch + self.length,
                -0.5 * self.width,
                0.5 * self.width,
                level + self.height,
                kind="stone",
            )
            for k in range(self.count)
        ]
        # the pit's bottom: below the stones, all across the terrain
        pit = Surface(self.start, self.end, -half_width, half_width, level - self.depth, kind="pit")
        return [pit, *stones]


@dataclass(frozen=True)
class RoughPatch(Feature):
    """A patch ``length`` [m] long and ``width`` [m] wide of square blocks of side ``block``
    [m] whose tops lie uniformly in ``[0, height]`` [m] above the level (drawn with
    ``seed``; the planner knows them)."""

    length: float = 1.0
    width: float = 1.0
    block: float = 0.1
    height: float = 0.02
    seed: int = 0

    key: ClassVar[str] = "rough"

    def __post_init__(self) -> None:
        super().__post_init__()
        set_ = object.__setattr__
        set_(self, "length", _number("RoughPatch", "length", self.length, 0.02, 20.0, "m"))
        set_(self, "width", _number("RoughPatch", "width", self.width, 0.02, 10.0, "m"))
        set_(self, "block", _number("RoughPatch", "block", self.block, 0.01, 2.0, "m"))
        set_(self, "height", _number("RoughPatch", "height", self.height, 0.0, 0.5, "m"))
        _integer("RoughPatch", "seed", self.seed, 0, 2**63 - 1)

    @property
    def extent(self) -> float:
        return self.length

    def block_heights(self) -> np.ndarray:
        """Heights [m] of the blocks above the level, shape (along x, along y)."""
        nx = max(1, int(round(self.length / self.block)))
        ny = max(1, int(round(self.width / self.block)))
        return np.random.default_rng(self.seed).uniform(0.0, self.height, (nx, ny))

    def surfaces(self, level: float, half_width: float) -> list[Surface]:
        heights = self.block_heights()
        nx, ny = heights.shape
        dx, dy = self.length / nx, self.width / ny
        y0 = -0.5 * self.width
        out = [Surface(self.start, self.end, -half_width, half_width, level, kind="landing")]
        for i in range(nx):
            for j in range(ny):
                if heights[i, j] > 0.0:
                    out.append(
                        Surface(
                            self.start + i * dx,
                            self.start + (i + 1) * dx,
                            y0 + j * dy,
                            y0 + (j + 1) * dy,
                            level + float(heights[i, j]),
                            kind="block",
                        )
                    )
        return out


#: Feature classes by their table name in a terrain file.
FEATURES: dict[str, type[Feature]] = {
    cls.key: cls for cls in (Stairs, Slope, Platform, SteppingStones, RoughPatch)
}


__all__ = ["FEATURES", "Feature", "Platform", "RoughPatch", "Slope", "Stairs", "SteppingStones"]
