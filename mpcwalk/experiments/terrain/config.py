"""The terrain experiment's configuration: robots, controllers, timings and the terrains'
sizes, read from the ``config.toml`` beside this package (:func:`load_terrain_config`).

Every size is relative to the robot that walks: rises, gaps and blocks as shares of its
leg length (:attr:`~mpcwalk.robot.Robot.leg_length`, the hip height above the soles), runs,
stones and blocks in sole lengths.
"""

from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.experiments.protocol import config_path, mode_name, read_config, unknown_keys

DEFAULT_CONFIG = config_path("mpcwalk.experiments.terrain")

#: The terrains a robot walks, in the order of the report.
TERRAINS = ("stairs", "slope", "stones", "rough")


@dataclass(frozen=True)
class RobotTerrain:
    """One robot's part of the experiment.

    Attributes:
        robot: The robot's name.
        controllers: Its controllers (named controllers: ``mpcwalk controllers``).
        step_durations: Step durations T [s] tried on every terrain (the report keeps, per
            controller, the one that climbs higher); controllers with a timing of their own
            (paper A's static gait, 12 s) walk at theirs.
    """

    robot: str
    controllers: tuple[str, ...]
    step_durations: tuple[float, ...]


@dataclass(frozen=True)
class TerrainConfig:
    """The experiment (see its ``config.toml`` for each entry).

    Attributes:
        robots: Each robot's controllers and timings.
        terrains: The terrains walked (of :data:`TERRAINS`).
        own_timing: Controllers that keep their generator's own timing [names].
        climb_error_cm: A walk climbs when its largest 3D landing error is below this [cm].
        goal_rise_share: The goal's rise [share of the leg length].
        bisection_iterations: Most walks of the bisection on the rise.
        tolerance_share: The bisection stops at a bracket this narrow [share of the leg].
        stride_shares: The command's nominal strides tried, as shares of the stair run
            (within the legs' flat reach) [-]; the planner moves each landing onto the
            treads (the report keeps, per controller, the stride and step duration that
            climb higher).
        approach: Level ground before the first feature [m].
        nb_stairs: Steps up, and as many down.
        run_soles: Stair run [sole lengths] (never under the sole with its margins).
        landing_soles: Landing between up and down [sole lengths].
        slope_deg: Slope up, then down [deg].
        slope_length_legs: Each slope's horizontal length [leg lengths].
        stones_gap_share: Gap between stones [share of the leg length].
        stones_length_soles: Stone length [sole lengths].
        stones_count: Stones.
        stones_depth_share: Depth of the pit under the stones [share of the leg length].
        rough_height_share: Highest block of the rough patch [share of the leg length].
        rough_block_soles: Block side [sole lengths].
        rough_length_blocks: Patch length [blocks].
        rough_width_blocks: Patch width [blocks].
        seed: Seed of the rough patch and of the walks.
        control_period: Controller tick [s].
        timeout: Hard limit of one case [s] (a bisection is one case).
        mode: ``"full"`` or ``"quick"``.
    """

    robots: tuple[RobotTerrain, ...]
    terrains: tuple[str, ...] = TERRAINS
    own_timing: tuple[str, ...] = ("paper-a",)
    climb_error_cm: float = 5.0
    goal_rise_share: float = 0.25
    bisection_iterations: int = 5
    tolerance_share: float = 0.01
    stride_shares: tuple[float, ...] = (1.0,)
    approach: float = 0.5
    nb_stairs: int = 5
    run_soles: float = 1.5
    landing_soles: float = 3.0
    slope_deg: float = 15.0
    slope_length_legs: float = 2.0
    stones_gap_share: float = 0.4
    stones_length_soles: float = 1.5
    stones_count: int = 4
    stones_depth_share: float = 0.5
    rough_height_share: float = 0.1
    rough_block_soles: float = 1.5
    rough_length_blocks: int = 6
    rough_width_blocks: int = 4
    seed: int = 0
    control_period: float = 0.01
    timeout: float = 5400.0
    mode: str = "full"

    def settings(self) -> dict[str, Any]:
        """The configuration as JSON (the sweep's fingerprint)."""
        return asdict(self)


#: Keys of the [quick] table besides the fields: the robots kept, their controllers, how
#: many of their step durations.
_QUICK_KEYS = ("robots", "controllers", "nb_step_durations")


def load_terrain_config(path: str | Path = DEFAULT_CONFIG, *, quick: bool = False) -> TerrainConfig:
    """Read the experiment from TOML; ``quick`` applies its ``[quick]`` table (``robots``:
    the robots kept, ``controllers``: theirs, ``nb_step_durations``: the first ones kept,
    and any field).

    Raises:
        ConfigurationError: An unknown key, an unknown terrain, or no robot.
    """
    data, small = read_config(path, quick=quick)
    names = [f.name for f in fields(TerrainConfig)]
    unknown_keys(data, [n for n in names if n != "mode"], "terrain")
    unknown_keys(small, [*names, *_QUICK_KEYS], "quick")
    robots = []
    for table in data.get("robots", []):
        unknown_keys(table, [f.name for f in fields(RobotTerrain)], "robots")
        if table["robot"] not in small.get("robots", [table["robot"]]):
            continue
        durations = [float(t) for t in table["step_durations"]]
        robots.append(
            RobotTerrain(
                str(table["robot"]),
                tuple(small.get("controllers", table["controllers"])),
                tuple(durations[: small.get("nb_step_durations", len(durations))]),
            )
        )
    if not robots:
        raise ConfigurationError(
            f"The terrain experiment in {path} has no [[robots]] table left; give at least one."
        )
    values = {k: v for k, v in {**data, **small}.items() if k in names and k != "robots"}
    values = {k: tuple(v) if isinstance(v, list) else v for k, v in values.items()}
    config = TerrainConfig(robots=tuple(robots), mode=mode_name(quick), **values)
    wrong = sorted(set(config.terrains) - set(TERRAINS))
    if wrong:
        raise ConfigurationError(
            f"Unknown terrain(s) {wrong} in {path}; the terrains are {list(TERRAINS)}."
        )
    return config


__all__ = ["DEFAULT_CONFIG", "TERRAINS", "RobotTerrain", "TerrainConfig", "load_terrain_config"]
