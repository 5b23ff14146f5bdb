"""The worlds of the robustness matrix: its factors and how each world of a robot is drawn.

Each robot walks a list of *worlds* (:func:`robot_worlds`): the nominal one (over a few
seeds), each factor alone at random levels stratified over its range, and random
combinations of 2 to 4 factors. The factors (:data:`FACTORS`): a random omnidirectional
command within the robot's limits; a push on the torso (direction, phase of the step,
impulse as a fraction of the LIPM's no-step capture bound in that direction); torso mass;
torso CoM offset; friction; sensor noise; latency; servo strength; ground tilt (towards a
random azimuth); rough ground (a height field); and the terrain factors, stairs, a slope and
stepping stones built to the robot's size (:mod:`~mpcwalk.experiments.robustness.terrains`;
a combination holds at most one, never with the tilt, the bumps or the random command). A
configuration may select some factors (``factors``, e.g. the ``[terrain_only]`` table): it
keeps the worlds of the same draws whose factors it holds.
"""

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.robustness.config import MatrixConfig
from mpcwalk.experiments.robustness.terrains import LEVEL_KEYS, TERRAIN_FACTORS, compatible

#: The factors, in table order.
FACTORS = (
    "command",
    "push",
    "mass",
    "com",
    "friction",
    "noise",
    "latency",
    "servo",
    "tilt",
    "roughness",
    *TERRAIN_FACTORS,
)

#: What the level of each factor is, for the tables.
LEVEL_UNITS = {
    "command": "largest share of a limit",
    "push": "impulse / no-step capture bound",
    "mass": "torso mass factor",
    "com": "CoM offset [m]",
    "friction": "friction coefficient",
    "noise": "noise factor",
    "latency": "latency [control periods]",
    "servo": "servo strength factor",
    "tilt": "slope [deg]",
    "roughness": "largest bump [m]",
    "stairs": "rise / leg length",
    "slope": "ramp angle [deg]",
    "stones": "gap / leg length",
}


@dataclass(frozen=True)
class World:
    """How one world of the matrix differs from the nominal walk.

    Attributes:
        group: ``"nominal"``, ``"single"`` or ``"combination"``.
        factors: The factors changed.
        level: The single factor's level (:data:`LEVEL_UNITS`), None otherwise.
        seed: Seed of the walk (sensor noise, bumps).
        changes: Fields of a :class:`~mpcwalk.walking.specification.WalkSpec` (the latency in control
            periods, ``latency_periods``), the command as a fraction of
            the robot's limits (``command_share``), the push as ``push`` = (direction
            [deg], phase [share of the step], impulse share) and the terrain as
            ``terrain`` = (terrain factor, level).
    """

    group: str
    factors: tuple[str, ...]
    level: float | None
    seed: int
    changes: Mapping[str, Any]


def _draw(factor: str, u: float, rng: np.random.Generator, ranges) -> tuple[dict, float]:
    """The changes of ``factor`` at the stratified draw ``u`` in [0, 1), and its level."""

    def span(key: str) -> float:
        low, high = ranges[key]
        return round(float(low + u * (high - low)), 4)

    if factor == "command":
        share = np.round(rng.uniform(-1.0, 1.0, 3) * float(ranges["command_fraction"]), 3)
        return {"command_share": tuple(float(s) for s in share)}, float(np.abs(share).max())
    if factor == "push":
        direction = round(float(rng.uniform(0.0, 360.0)), 1)
        phase = round(float(rng.uniform(0.0, 1.0)), 3)
        fraction = span("push_fraction")
        return {"push": (direction, phase, fraction)}, fraction
    if factor == "com":
        low, high = ranges["com_offset"]
        angle = rng.uniform(0.0, 2.0 * math.pi)
        radius = u * max(abs(low), abs(high))
        offset = (round(radius * math.cos(angle), 4), round(radius * math.sin(angle), 4))
        return {"com_offset": offset}, round(math.hypot(*offset), 4)
    if factor == "latency":
        low, high = ranges["latency_periods"]
        periods = int(low + min(int(u * (high - low + 1)), high - low))
        return {"latency_periods": periods}, float(periods)
    if factor in TERRAIN_FACTORS:
        level = span(LEVEL_KEYS[factor])
        return {"terrain": (factor, level)}, level
    if factor == "tilt":
        slope = span("ground_tilt")
        azimuth = round(float(rng.uniform(0.0, 360.0)), 1)
        return {"ground_tilt": slope, "ground_tilt_direction": azimuth}, slope
    key = {
        "mass": "mass_scale",
        "friction": "friction",
        "noise": "noise_scale",
        "servo": "servo_strength",
        "roughness": "ground_roughness",
    }[factor]
    value = span(key)
    return {key: value}, value


def selected_factors(config: MatrixConfig) -> tuple[str, ...]:
    """The factors of the configuration's worlds, in table order (None: every factor).

    Raises:
        ConfigurationError: An unknown factor.
    """
    if config.factors is None:
        return FACTORS
    unknown = sorted(set(config.factors) - set(FACTORS))
    if unknown:
        raise ConfigurationError(
            f"Unknown factor(s) {unknown} in the matrix's factors; the factors are "
            f"{', '.join(FACTORS)}."
        )
    return tuple(f for f in FACTORS if f in config.factors)


def robot_worlds(config: MatrixConfig, robot_index: int) -> list[World]:
    """The worlds of one robot (the ``robot_index``-th of the config: its own draws). A
    combination draws its factors one by one, keeping those that go with the ones before
    (:func:`~mpcwalk.experiments.robustness.terrains.compatible`). A selection of factors
    (``config.factors``) keeps the worlds whose factors it holds, of the same draws: the same
    worlds as every factor's matrix."""
    rng = np.random.default_rng([config.seed, robot_index])
    keep = set(selected_factors(config))
    worlds = [World("nominal", (), None, int(seed), {}) for seed in config.nominal_seeds]
    next_seed = 100
    for factor in FACTORS:
        for i in range(config.levels):
            changes, level = _draw(factor, (i + rng.uniform()) / config.levels, rng, config.ranges)
            worlds.append(World("single", (factor,), level, next_seed, changes))
            next_seed += 1
    low, high = config.combination_size
    for _ in range(config.combinations):
        size = int(rng.integers(low, high + 1))
        chosen: list[str] = []
        for factor in rng.permutation(np.array(FACTORS)):
            if len(chosen) < size and compatible([*chosen, str(factor)]):
                chosen.append(str(factor))
        chosen.sort(key=FACTORS.index)
        changes = {}
        for factor in chosen:
            changes.update(_draw(factor, float(rng.uniform()), rng, config.ranges)[0])
        worlds.append(World("combination", tuple(chosen), None, next_seed, changes))
        next_seed += 1
    return [world for world in worlds if keep.issuperset(world.factors)]


__all__ = ["FACTORS", "LEVEL_UNITS", "World", "robot_worlds", "selected_factors"]
