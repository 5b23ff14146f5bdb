"""The push map on the sweep engine: the largest push each controller survives, per direction,
phase of the step and walking speed, and its ratio to ``paper-m``'s in the same cell.

A case (:class:`PushCase`) is one controller pushed in one direction (of ``nb_directions``
around the robot, 0 deg forward, 90 deg left) at one phase of the pushed step (of
``nb_phases``, from the step's start) while walking forward at one speed (a share of the
robot's nominal speed; 0: stepping in place). Its runner (:func:`run_push_case`) brackets and
bisects the impulse of a 0.1 s torso push
(:func:`~mpcwalk.experiments.survival.find_largest_survived`), in units of the LIPM's no-step capture bound in that direction, and
returns the largest impulse survived; a walk survives by
:func:`~mpcwalk.experiments.survival.survived` (neither fallen nor stopped).
:mod:`mpcwalk.experiments.push_map.report` writes the report: the ratios to ``paper-m`` and
the shares of the LIPM's capture bounds.
"""

import json
import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from mpcwalk.experiments.survival import find_largest_survived, survived
from mpcwalk.footsteps.capturability import capture_impulse_bound
from mpcwalk.sim.actuation import check_actuation
from mpcwalk.sweep import Sweep
from mpcwalk.walking.sweep_cases import worker_robot

REFERENCE = "paper-m"

#: What the runner of a push case returns.
PUSH_COLUMNS = (
    "capture_bound_Ns",
    "largest_survived_Ns",
    "smallest_fallen_Ns",
    "largest_share",
    "censored",
    "nb_walks",
    "trials",
)


@dataclass(frozen=True)
class PushMapConfig:
    """The grid and the bisection (impulses as shares of the no-step capture bound)."""

    robot: str = "bioloid-like"
    controllers: tuple[str, ...] = (REFERENCE, "mpc", "mpc-steps", "mpc-timing", "mpc-hip")
    nb_directions: int = 16
    nb_phases: int = 6
    speed_shares: tuple[float, ...] = (0.0, 1.0)
    nb_steps: int = 5
    push_step: int = 2
    push_duration: float = 0.1
    initial_share: float = 0.5
    max_share: float = 3.0
    tolerance_share: float = 0.05
    relative_tolerance: float = 0.1
    control_period: float = 0.01
    seed: int = 0
    actuation: str = "position"

    def __post_init__(self) -> None:
        check_actuation(self.actuation)

    @property
    def folder_name(self) -> str:
        """The map's sub-folder: the robot's name, with the actuation unless position."""
        return self.robot if self.actuation == "position" else f"{self.robot}-{self.actuation}"

    def settings(self) -> dict[str, Any]:
        """The configuration as JSON (position servos, the default, unsaid: the maps run
        before torque control keep their fingerprint)."""
        values = asdict(self)
        if self.actuation == "position":
            del values["actuation"]
        return values


@dataclass(frozen=True)
class PushCase:
    """One cell of the push map for one controller."""

    config: PushMapConfig
    controller: str
    direction_deg: float
    phase: float
    speed_share: float

    @property
    def case_id(self) -> str:
        """The cell and the controller (the rest is the sweep's settings)."""
        return f"{self.controller}/{self.direction_deg:g}/{self.phase:.4f}/{self.speed_share:g}"

    def to_columns(self) -> dict[str, Any]:
        """Columns of the results table."""
        return {
            "case_id": self.case_id,
            "robot": self.config.robot,
            "controller": self.controller,
            "direction_deg": self.direction_deg,
            "phase": self.phase,
            "speed_share": self.speed_share,
        }


def push_map_cases(config: PushMapConfig) -> tuple[PushCase, ...]:
    """Every cell for every controller (controller by controller)."""
    return tuple(
        PushCase(
            config,
            controller,
            round(360.0 * i / config.nb_directions, 4),
            round((j + 0.5) / config.nb_phases, 4),
            speed,
        )
        for controller in config.controllers
        for speed in config.speed_shares
        for j in range(config.nb_phases)
        for i in range(config.nb_directions)
    )


def run_push_case(case: PushCase) -> dict[str, Any]:
    """The largest impulse ``case.controller`` survives in its cell (walks by bisection)."""
    from mpcwalk.footsteps.velocity_planner import VelocityPlanner
    from mpcwalk.walking.controller_builder import walk_timing
    from mpcwalk.walking.runner import run_walk
    from mpcwalk.walking.specification import ControllerSpec, PlanSpec, WalkSpec

    config = case.config
    robot = worker_robot(config.robot)
    generator = ControllerSpec.named(case.controller).generator
    timing = walk_timing(generator, robot.gait, PlanSpec())
    nominal = VelocityPlanner(robot.leg_limits, timing).default_command().vx
    start = 1.0 + (config.push_step + case.phase) * timing.step_duration
    angle = math.radians(case.direction_deg)
    bound = capture_impulse_bound(
        angle,
        mass=robot.total_mass,
        com_height=robot.com_height,
        half_length=0.5 * robot.sole_size[0],
        half_width=0.5 * robot.sole_size[1],
    )

    def survives(impulse: float) -> bool:
        magnitude = impulse / config.push_duration
        fx, fy = magnitude * math.cos(angle), magnitude * math.sin(angle)
        spec = WalkSpec.build(
            config.robot,
            controller=case.controller,
            command=(case.speed_share * nominal, 0.0, 0.0),
            nb_steps=config.nb_steps,
            control_period=config.control_period,
            pushes=((start, config.push_duration, fx, fy, 0.0),),
            seed=config.seed,
            **({} if config.actuation == "position" else {"actuation": config.actuation}),
        )
        return survived(run_walk(spec, robot=robot))

    found = find_largest_survived(
        survives,
        initial=config.initial_share * bound,
        upper_limit=config.max_share * bound,
        tolerance=config.tolerance_share * bound,
        relative_tolerance=config.relative_tolerance,
    )
    return {
        "capture_bound_Ns": bound,
        "largest_survived_Ns": found.largest_survived,
        "smallest_fallen_Ns": found.smallest_fallen,
        "largest_share": found.largest_survived / bound,
        "censored": found.censored,
        "nb_walks": len(found.trials),
        "trials": [[round(value, 6), ok] for value, ok in found.trials],
    }


def push_map_sweep(config: PushMapConfig) -> Sweep:
    """The push map as a sweep of the engine."""
    return Sweep(
        name="push-map",
        cases=push_map_cases(config),
        runner=run_push_case,
        columns=PUSH_COLUMNS,
        settings=config.settings(),
        timeout=1800.0,
    )


Cell = tuple[float, float, float]  # direction [deg], phase, speed share


def cell_of(row: dict) -> Cell:
    """The cell of a row (or of a capture cell with its speed), rounded as both grids are."""
    return (
        round(float(row["direction_deg"]), 3),
        round(float(row["phase"]), 4),
        float(row["speed_share"]),
    )


def by_cell(rows: list[dict], column: str) -> dict[str, dict[Cell, float]]:
    """Per controller, ``column`` of every cell without error where it has a value."""
    out: dict[str, dict[Cell, float]] = {}
    for row in rows:
        value = row.get(column)
        if not row.get("error") and value is not None:
            out.setdefault(row["controller"], {})[cell_of(row)] = float(value)
    return out


def impulses(rows: list[dict]) -> dict[str, dict[Cell, float]]:
    """Per controller, the largest impulse survived [N s] of every cell without error."""
    return by_cell(rows, "largest_survived_Ns")


def ratios(rows: list[dict]) -> dict[str, list[tuple[Cell, float | None]]]:
    """Per controller, ``(cell, ratio to paper-m)`` of every cell (None: paper-m survived
    nothing there, or a row has an error)."""
    reference = impulses(rows).get(REFERENCE, {})
    out: dict[str, list[tuple[Cell, float | None]]] = {}
    for row in rows:
        ref, value = reference.get(cell_of(row)), row.get("largest_survived_Ns")
        ratio = value / ref if ref and value is not None and not row.get("error") else None
        out.setdefault(row["controller"], []).append((cell_of(row), ratio))
    return out


#: Settings two push maps must share to be joined in one report.
_GRID = ("robot", "nb_directions", "nb_phases", "speed_shares", "nb_steps", "push_step")


def joined_push_rows(config: PushMapConfig, folders) -> list[dict]:
    """The rows of the finished push maps in ``folders`` (other controllers run apart, on
    the grid of ``config``), to join to its report.

    Raises:
        ConfigurationError: A folder without a finished push map, on another robot or
            grid, or with a controller ``config`` runs too.
    """
    from mpcwalk.exceptions import ConfigurationError
    from mpcwalk.sweep import read_rows

    mine, rows = dict(config.settings()), []
    for folder in map(Path, folders):
        manifest, table = folder / "sweep.json", folder / "results.csv"
        if not (manifest.exists() and table.exists()):
            raise ConfigurationError(
                f"Joined push map {folder}: expected the folder of a push map (sweep.json and "
                "results.csv), found none; give the folder of a robot's push map."
            )
        settings = json.loads(manifest.read_text()).get("settings", {})
        differs = [k for k in _GRID if _jsonable(settings.get(k)) != _jsonable(mine[k])]
        if differs:
            raise ConfigurationError(
                f"Joined push map {folder}: expected a push map on the same robot and grid, but "
                + ", ".join(f"{k} is {settings.get(k)!r} there, {mine[k]!r} here" for k in differs)
                + "; run both with the same robot and grid."
            )
        theirs = read_rows(table)
        expected = len(json.loads(manifest.read_text()).get("cases", []))
        if len(theirs) < expected:
            raise ConfigurationError(
                f"Joined push map {folder}: expected a finished push map ({expected} cells), found "
                f"{len(theirs)}; run its command again to finish it."
            )
        twice = {r["controller"] for r in theirs} & set(config.controllers)
        if twice:
            raise ConfigurationError(
                f"Joined push map {folder}: expected other controllers, but {', '.join(sorted(twice))} "
                "run here too; leave them out of this map's controllers or of the joined folder."
            )
        rows.extend(theirs)
    return rows


def _jsonable(value: Any) -> Any:
    return json.loads(json.dumps(value))


__all__ = [
    "PUSH_COLUMNS",
    "Cell",
    "PushCase",
    "PushMapConfig",
    "by_cell",
    "cell_of",
    "impulses",
    "joined_push_rows",
    "push_map_cases",
    "push_map_sweep",
    "ratios",
    "run_push_case",
]
