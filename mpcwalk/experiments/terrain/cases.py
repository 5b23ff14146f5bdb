"""The terrain experiment's cases on the sweep engine.

A case (:class:`TerrainCase`) is one controller of one robot at one step duration and one
nominal stride on one terrain. Its runner (:func:`run_terrain_case`):

- ``stairs``: the largest rise climbed, by bisection between 0 and the legs' reach
  (:attr:`~mpcwalk.terrain.TerrainReach.max_rise`), its first walk at the goal's rise
  (whose measures fill the row); a walk climbs by
  :func:`~mpcwalk.experiments.terrain.walks.climbed`;
- ``slope``, ``stones``, ``rough``: one walk over the terrain, walked or not, its measures.

A terrain or controller the library refuses is a row with ``refused`` (its message), never
an exception; a walk that crashes (any other exception) leaves its row to the sweep engine,
with the error.
"""

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mpcwalk.experiments.terrain.config import TerrainConfig
from mpcwalk.experiments.terrain.walks import (
    WALK_KEYS,
    climbed,
    reach_of,
    terrain_of,
    terrain_walk,
)
from mpcwalk.sweep import Sweep

#: What the runner of a case returns.
TERRAIN_COLUMNS = (
    "refused",
    "climbed",
    *WALK_KEYS,
    "nb_steps",
    "step_duration_s",
    "rise_m",
    "leg_length_m",
    "largest_rise_m",
    "largest_rise_share",
    "smallest_failed_rise_m",
    "nb_walks",
    "trials",
    "drawn_rise_m",
)
#: Folder (in the results folder) of the climbs' side views.
SIDE_VIEWS = "side_views"


@dataclass(frozen=True)
class TerrainCase:
    """One controller of one robot at one step duration and nominal stride on one terrain.

    Attributes:
        config: The experiment.
        robot: The robot's name.
        controller: The named controller.
        terrain: ``stairs``, ``slope``, ``stones`` or ``rough``.
        step_duration: Step duration T [s]; None: the controller's own timing.
        stride_share: The command's nominal stride [share of the stair run].
        out: The results folder, where a stairs case draws its highest climb (None: none).
    """

    config: TerrainConfig
    robot: str
    controller: str
    terrain: str
    step_duration: float | None
    stride_share: float = 1.0
    out: str | None = None

    @property
    def timing(self) -> str:
        """The step duration as the tables show it (``own`` for the controller's)."""
        return "own" if self.step_duration is None else f"{self.step_duration:g}"

    @property
    def variant(self) -> str:
        """The step duration and the stride, as the tables and file names name them."""
        return f"T{self.timing}-stride{self.stride_share:g}"

    @property
    def case_id(self) -> str:
        """Robot, controller, terrain, step duration and stride."""
        return f"{self.robot}/{self.controller}/{self.terrain}/{self.variant}"

    def to_columns(self) -> dict[str, Any]:
        """Columns of the results table."""
        return {
            "case_id": self.case_id,
            "robot": self.robot,
            "controller": self.controller,
            "terrain": self.terrain,
            "timing": self.timing,
            "stride_share": self.stride_share,
            "variant": self.variant,
        }


def timing_of(row: dict[str, Any]) -> str:
    """A row's step duration as :attr:`TerrainCase.timing` spells it (the table reads it
    back as a number)."""
    value = row["timing"]
    return "own" if value == "own" else f"{float(value):g}"


def terrain_cases(config: TerrainConfig, out: str | Path | None = None) -> tuple[TerrainCase, ...]:
    """Every robot's controllers on every terrain, at each of its step durations (a
    controller with its own timing: at that one) and each nominal stride."""
    folder = None if out is None else str(out)
    cases = []
    for plan in config.robots:
        for controller in plan.controllers:
            own = controller in config.own_timing
            durations: tuple[float | None, ...] = (None,) if own else plan.step_durations
            for terrain in config.terrains:
                for duration in durations:
                    for stride in config.stride_shares:
                        cases.append(
                            TerrainCase(
                                config, plan.robot, controller, terrain, duration, stride, folder
                            )
                        )
    return tuple(cases)


def _walk(case: TerrainCase, robot: Any, rise: float | None, side_view: Any = None) -> dict:
    terrain = terrain_of(case.terrain, robot, case.config, rise)
    duration = case.step_duration or robot.gait.step_duration
    return terrain_walk(
        robot,
        case.controller,
        terrain,
        case.config,
        duration,
        case.stride_share,
        side_view=side_view,
    )


def _trial(rise: float, walk: dict[str, Any], ok: bool) -> list[Any]:
    """A bisection trial as the row keeps it: rise [m], climbed, and why not."""
    why = walk.get("refused") or walk.get("outcome")
    if walk.get("outcome") == "walked":
        error = walk["landing_error_3d_cm_max"]
        why = (
            f"walked, {walk['steps_completed']}/{walk['steps_planned']} steps, landing error "
            f"max {'-' if error is None else f'{error:.1f}'} cm"
        )
    elif walk.get("outcome"):
        why = f"{walk['outcome']} after {walk['steps_completed']}/{walk['steps_planned']} steps"
    return [round(rise, 5), ok, why]


def bisect_rise(case: TerrainCase, robot: Any) -> dict[str, Any]:
    """The stairs case: the goal's walk, then the bisection on the rise (see the module's
    documentation)."""
    config, leg = case.config, robot.leg_length
    final = draft = None
    if case.out is not None:  # the goal's walk drawn, then each higher climb over it
        folder = Path(case.out) / SIDE_VIEWS
        folder.mkdir(parents=True, exist_ok=True)
        final = folder / f"{case.robot}_{case.controller}_{case.variant}.png"
        draft = final.with_suffix(".draft.png")
    lo, hi, failed = 0.0, reach_of(robot).max_rise, None
    goal_rise = config.goal_rise_share * leg
    goal = _walk(case, robot, goal_rise, draft)
    row: dict[str, Any] = {**goal, "rise_m": goal_rise, "leg_length_m": leg}
    if goal.get("refused"):
        return {**row, "climbed": False, "nb_walks": 0, "trials": []}
    ok = climbed(goal, config)
    row["climbed"] = ok
    trials = [_trial(goal_rise, goal, ok)]
    drawn = goal_rise if _keep_view(draft, final, True) else None
    if ok:
        lo = goal_rise
    else:
        hi = failed = goal_rise
    while len(trials) < config.bisection_iterations and hi - lo > config.tolerance_share * leg:
        rise = 0.5 * (lo + hi)
        walk = _walk(case, robot, rise, draft)
        ok = climbed(walk, config)
        trials.append(_trial(rise, walk, ok))
        if ok:
            lo = rise
        else:
            hi = failed = rise
        if _keep_view(draft, final, ok):
            drawn = rise
    return {
        **row,
        "largest_rise_m": lo,
        "largest_rise_share": lo / leg,
        "smallest_failed_rise_m": failed,
        "nb_walks": len(trials),
        "trials": trials,
        "drawn_rise_m": drawn,
    }


def _keep_view(draft: Path | None, final: Path | None, keep: bool) -> bool:
    """The draft side view over the final one when ``keep``, else dropped; whether kept."""
    if draft is None or final is None or not draft.exists():
        return False
    if keep:
        draft.replace(final)
        return True
    draft.unlink()
    return False


def run_terrain_case(case: TerrainCase) -> dict[str, Any]:
    """The row of ``case`` (in a worker; see the module's documentation)."""
    from mpcwalk.walking.sweep_cases import worker_robot

    robot = worker_robot(case.robot)
    if case.terrain == "stairs":
        return bisect_rise(case, robot)
    walk = _walk(case, robot, None)
    return {
        **walk,
        "climbed": climbed(walk, case.config),
        "leg_length_m": robot.leg_length,
        "nb_walks": 0 if walk.get("refused") else 1,
    }


def terrain_sweep(config: TerrainConfig, out: str | Path | None = None) -> Sweep:
    """The experiment as a sweep of the engine."""
    return Sweep(
        name="terrain",
        cases=terrain_cases(config, out),
        runner=run_terrain_case,
        columns=TERRAIN_COLUMNS,
        settings=config.settings(),
        timeout=config.timeout,
    )


__all__ = [
    "SIDE_VIEWS",
    "TERRAIN_COLUMNS",
    "TerrainCase",
    "bisect_rise",
    "run_terrain_case",
    "terrain_cases",
    "terrain_sweep",
    "timing_of",
]
