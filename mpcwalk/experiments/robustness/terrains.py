"""The terrain factors of the robustness matrix: stairs, a slope, stepping stones, each built
to the robot's size so that every robot meets comparable terrain.

A terrain factor's level is what is drawn (:data:`LEVEL_KEYS`, the ``[factors]`` ranges of
the matrix's ``config.toml``): the rise of the stairs and the gap between the stones as a
share of the robot's leg length (:attr:`~mpcwalk.robot.robot.Robot.leg_length`, the hip's
height above the soles), the ramps' angle in degrees. The rest of each terrain is the
``[terrain]`` table (:class:`TerrainLayout`), in the robot's leg and sole lengths:

- ``stairs``: ``stair_count`` steps up, a landing, as many down; treads of ``stair_run``
  sole lengths (at least :attr:`~mpcwalk.terrain.TerrainReach.min_tread`);
- ``slope``: a ramp up ``ramp_length`` leg lengths long, a landing, a ramp down;
- ``stones``: ``stone_count`` stones ``stone_length`` sole lengths deep, as wide as the
  stance plus a sole width each side, over a pit ``pit_depth`` leg lengths deep.

Each starts ``start`` m ahead of the robot (its initial stance stays on the level ground).
A walk on a terrain takes the steps that cross it and a few more (:func:`terrain_steps`).
A terrain factor goes with neither the ground's tilt nor its bumps (the simulator refuses a
terrain on a rough floor), nor the random command (which would walk the robot away from the
terrain or across it), nor another terrain factor (:func:`compatible`).
"""

import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, fields
from typing import Any

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.terrain import (
    Slope,
    Stairs,
    SteppingStones,
    Terrain,
    TerrainReach,
    terrain_from_dict,
    terrain_to_dict,
)

#: The terrain factors, in table order.
TERRAIN_FACTORS = ("stairs", "slope", "stones")
#: The ``[factors]`` range each terrain factor's level is drawn from.
LEVEL_KEYS = {"stairs": "stair_rise", "slope": "slope_angle", "stones": "stone_gap"}
#: The factors a terrain factor does not go with (besides the other terrain factors).
TERRAIN_APART = ("command", "tilt", "roughness")
#: The label of a terrain walk holding its terrain (the tables of a terrain file, as JSON).
LAYOUT_LABEL = "layout"
#: The label of a terrain walk holding its milestones, (steps that put a foot beyond the
#: terrain's first edge, steps that carry both beyond its far end), at the nominal stride.
MILESTONES_LABEL = "terrain_steps"


@dataclass(frozen=True)
class TerrainLayout:
    """The shape of the terrain factors' terrains (``[terrain]`` of the matrix's file).

    Attributes:
        start: Distance [m] from the robot's start to the first riser, ramp or stone.
        stair_count: Steps up, then as many down.
        stair_run: Tread depth [sole lengths] (at least the reach's ``min_tread``).
        landing: Level ground between the way up and the way down [sole lengths].
        ramp_length: Horizontal length of each ramp [leg lengths].
        stone_count: Stones.
        stone_length: Depth of a stone along the heading [sole lengths].
        pit_depth: Depth of the pit under the stones [leg lengths].
        exit_steps: Steps walked beyond the terrain's far end (at the nominal stride).
    """

    start: float = 0.5
    stair_count: int = 3
    stair_run: float = 1.5
    landing: float = 3.0
    ramp_length: float = 2.0
    stone_count: int = 4
    stone_length: float = 1.5
    pit_depth: float = 0.2
    exit_steps: int = 4

    @classmethod
    def from_table(cls, table: Mapping[str, Any]) -> "TerrainLayout":
        """The layout of a ``[terrain]`` table (missing keys: the defaults).

        Raises:
            ConfigurationError: An unknown key or a value that is not a positive number.
        """
        names = [f.name for f in fields(cls)]
        unknown = sorted(set(table) - set(names))
        if unknown:
            raise ConfigurationError(
                f"Unknown key(s) {unknown} in [terrain]; the keys are {sorted(names)}."
            )
        values: dict[str, Any] = {}
        for name, value in table.items():
            integer = name in ("stair_count", "stone_count", "exit_steps")
            if isinstance(value, bool) or not isinstance(value, (int, float)) or value < 0:
                raise ConfigurationError(f"[terrain] {name} must be a number >= 0, got {value!r}.")
            values[name] = int(value) if integer else float(value)
        return cls(**values)


def compatible(factors: Iterable[str]) -> bool:
    """Whether the factors go together in one world: at most one terrain factor, and none
    with the factors of :data:`TERRAIN_APART`."""
    factors = set(factors)
    terrain = factors & set(TERRAIN_FACTORS)
    return not terrain or (len(terrain) == 1 and not factors & set(TERRAIN_APART))


def _mm(value: float) -> float:
    """A length [m] rounded to a tenth of a millimetre (a terrain file's digits)."""
    return round(float(value), 4)


def terrain_of(factor: str, level: float, robot: Any, layout: TerrainLayout) -> Terrain:
    """The terrain of the terrain factor ``factor`` at ``level`` (:data:`LEVEL_KEYS`),
    scaled to ``robot`` (its leg length, sole size and initial stance); lengths rounded to
    a tenth of a millimetre."""
    leg = float(robot.leg_length)
    sole_length, sole_width = (float(v) for v in robot.sole_size)
    start = layout.start
    landing = _mm(layout.landing * sole_length)
    if factor == "stairs":
        reach = TerrainReach.for_leg(sole_length, sole_width, leg)
        run = _mm(max(layout.stair_run * sole_length, reach.min_tread))
        rise, count = _mm(level * leg), layout.stair_count
        up = Stairs(start, rise=rise, run=run, count=count)
        down = Stairs(up.end + landing, rise=-rise, run=run, count=count)
        return Terrain([up, down])
    if factor == "slope":
        length = _mm(layout.ramp_length * leg)
        ramp = Slope(start, length=length, angle=level)
        return Terrain([ramp, Slope(ramp.end + landing, length=length, angle=-level)])
    if factor == "stones":
        left, right = robot.initial_feet()
        stance = abs(float(left.xy[1]) - float(right.xy[1]))
        stones = SteppingStones(
            start,
            count=layout.stone_count,
            length=_mm(layout.stone_length * sole_length),
            gap=_mm(level * leg),
            width=_mm(stance + 2.0 * sole_width),
            depth=_mm(layout.pit_depth * leg),
        )
        return Terrain([stones])
    raise ConfigurationError(
        f"Unknown terrain factor {factor!r}; the terrain factors are {', '.join(TERRAIN_FACTORS)}."
    )


def far_end(terrain: Terrain) -> float:
    """Distance [m] from the start to the terrain's last edge (its last feature's end)."""
    return max(feature.end for feature in terrain.features)


def _stride(robot: Any, command: Sequence[float], timing: Any) -> float:
    """The nominal stride [m] (vx times the step duration).

    Raises:
        ConfigurationError: A command that does not walk forward.
    """
    stride = float(command[0]) * float(timing.step_duration)
    if stride <= 0.0:
        raise ConfigurationError(
            f"A terrain world needs a forward command to carry {robot.name} over the terrain, "
            f"got vx = {command[0]!r} m/s; give the robot a positive vx in [robots.{robot.name}]."
        )
    return stride


def terrain_steps(
    terrain: Terrain, robot: Any, command: Sequence[float], timing: Any, exit_steps: int
) -> int:
    """Steps that carry ``robot`` over ``terrain`` at ``command`` (vx [m/s], vy [m/s],
    vyaw [rad/s]) and ``timing`` (a :class:`~mpcwalk.footsteps.footstep.StepTiming`): the
    distance to the terrain's far end and a sole length more, over the nominal stride (vx
    times the step duration), and ``exit_steps`` more. The footsteps placed on a terrain go
    at least as far as the nominal strides (a landing moved forward onto a tread or a stone
    keeps the stride it gained), so that the walk's own footsteps cross the terrain (the
    tests plan them on every terrain world of the matrix's terrain part).

    Raises:
        ConfigurationError: A command that does not walk forward.
    """
    distance = far_end(terrain) + float(robot.sole_size[0])
    return int(math.ceil(distance / _stride(robot, command, timing) - 1e-9)) + exit_steps


def milestones(
    terrain: Terrain, robot: Any, command: Sequence[float], timing: Any, exit_steps: int
) -> tuple[int, int]:
    """(Steps after which a foot has landed beyond the terrain's first edge, steps after
    which both have crossed its far end), at the nominal stride (:func:`terrain_steps`; the
    n-th step of a walk lands n strides ahead of the start): a walk that completed the
    first reached the terrain, one that completed the second crossed it.

    Raises:
        ConfigurationError: A command that does not walk forward.
    """
    first = min(feature.start for feature in terrain.features)
    approach = int(math.ceil(first / _stride(robot, command, timing) - 1e-9))
    return approach, terrain_steps(terrain, robot, command, timing, exit_steps) - exit_steps


def layout_text(terrain: Terrain) -> str:
    """The terrain as the label of its walks (:data:`LAYOUT_LABEL`): compact JSON."""
    return json.dumps(terrain_to_dict(terrain), separators=(",", ":"))


def terrain_of_text(text: str | Mapping[str, Any]) -> Terrain:
    """The terrain of :func:`layout_text` (or of its JSON read back, as a results table's
    cell is)."""
    data = json.loads(text) if isinstance(text, str) else dict(text)
    return terrain_from_dict(data, source=f"[{LAYOUT_LABEL}]")


def describe(terrain: Terrain) -> str:
    """The terrain in words (a report's line)."""
    parts = []
    for feature in terrain.features:
        if isinstance(feature, Stairs):
            way = "up" if feature.rise > 0 else "down"
            parts.append(
                f"{feature.count} steps {way} at {feature.start:.2f} m (rise "
                f"{100 * abs(feature.rise):.1f} cm, run {100 * feature.run:.1f} cm)"
            )
        elif isinstance(feature, Slope):
            parts.append(
                f"ramp of {feature.angle:+.1f} deg at {feature.start:.2f} m, {feature.length:.2f} m"
            )
        elif isinstance(feature, SteppingStones):
            parts.append(
                f"{feature.count} stones at {feature.start:.2f} m ({100 * feature.length:.1f} x "
                f"{100 * feature.width:.1f} cm, gap {100 * feature.gap:.1f} cm, pit "
                f"{100 * feature.depth:.1f} cm)"
            )
        else:  # the matrix lays no other feature
            parts.append(f"{type(feature).__name__} at {feature.start:.2f} m")
    return ", ".join(parts)


__all__ = [
    "LAYOUT_LABEL",
    "LEVEL_KEYS",
    "MILESTONES_LABEL",
    "TERRAIN_APART",
    "TERRAIN_FACTORS",
    "TerrainLayout",
    "compatible",
    "describe",
    "far_end",
    "layout_text",
    "milestones",
    "terrain_of",
    "terrain_of_text",
    "terrain_steps",
]
