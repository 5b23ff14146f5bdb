"""Paper M's push sweep: the grid of pushes, one cell's result, the summary per controller.

A push is a horizontal force on the torso for ``push_duration`` (0.1 s), of impulse ``J``
[N s] (force = J / duration), in one of several directions of the world frame (0 deg:
forward, 90 deg: left), applied at a gait phase of one step of a straight walk. For each
(controller, direction, phase) :func:`~mpcwalk.experiments.survival.find_largest_survived`
brackets and bisects the impulse; a walk survives by
:func:`~mpcwalk.experiments.survival.survived` (neither fallen nor stopped). The LIPM's
bounds drawn beside it are :func:`~mpcwalk.footsteps.capturability.capture_impulse_bound`.
"""

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError

#: Gait phases of the pushed step: offset of the push start from the step start, as a
#: function of (t_b, t_e, T) [s].
PHASES = {
    "ss-start": lambda t_b, t_e, T: t_b,  # single support begins
    "ss-mid": lambda t_b, t_e, T: 0.5 * (t_b + t_e),  # middle of single support
    "ds": lambda t_b, t_e, T: t_e,  # double support (end of this step, start of the next)
}


@dataclass(frozen=True)
class PushSweepConfig:
    """The push-recovery grid and the walks it runs.

    Attributes:
        command: Walking command ``(vx [m/s], vy [m/s], vyaw [rad/s])``.
        nb_steps: Commanded steps (the planner adds a closing step).
        push_step: Index of the pushed step (0: first step).
        push_duration: Duration of each push [s].
        directions_deg: Push directions [deg] in the world frame (0: forward, 90: left).
        phases: Names of :data:`PHASES`.
        initial_impulse: First impulse tried [N s].
        max_impulse: Largest impulse tried [N s].
        tolerance: Absolute bracket width at which the bisection stops [N s].
        relative_tolerance: Relative bracket width at which it stops.
        impulse_grid: Impulses [N s] of the success rate.
    """

    command: tuple[float, float, float] = (0.1, 0.0, 0.0)
    nb_steps: int = 5
    push_step: int = 2
    push_duration: float = 0.1
    directions_deg: tuple[float, ...] = (0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0)
    phases: tuple[str, ...] = ("ss-start", "ss-mid", "ds")
    initial_impulse: float = 0.4
    max_impulse: float = 4.0
    tolerance: float = 0.02
    relative_tolerance: float = 0.1
    impulse_grid: tuple[float, ...] = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0)

    def __post_init__(self) -> None:
        unknown = [p for p in self.phases if p not in PHASES]
        if unknown:
            raise ConfigurationError(
                f"Unknown push phase(s) {unknown}; use some of {sorted(PHASES)}."
            )
        if not 0 <= self.push_step < self.nb_steps:
            raise ConfigurationError(
                f"push_step must lie in [0, nb_steps) = [0, {self.nb_steps}), got "
                f"{self.push_step!r}."
            )

    def push_start(
        self,
        phase: str,
        *,
        step_duration: float,
        double_support_ratio: float,
        initial_duration: float = 1.0,
    ) -> float:
        """Start time [s] of a push at ``phase`` of the pushed step."""
        t_b = 0.5 * double_support_ratio * step_duration
        offset = PHASES[phase](t_b, step_duration - t_b, step_duration)
        return initial_duration + self.push_step * step_duration + offset

    def push_force(self, direction_deg: float, impulse: float) -> np.ndarray:
        """Force [N] of a push of ``impulse`` [N s] in ``direction_deg``."""
        angle = math.radians(direction_deg)
        magnitude = impulse / self.push_duration
        return np.array([magnitude * math.cos(angle), magnitude * math.sin(angle), 0.0])


@dataclass(frozen=True)
class SweepCase:
    """One cell of the grid: a controller pushed in one direction at one phase."""

    controller: str
    direction_deg: float
    phase: str


@dataclass(frozen=True)
class CaseResult:
    """Largest impulse survived in one :class:`SweepCase`.

    Attributes:
        case: The cell.
        largest_survived: [N s] (0: fell at the smallest impulse tried, or without a push).
        smallest_fallen: [N s], None when the largest impulse tried survived.
        trials: ``(impulse [N s], survived)`` in the order tried.
        wall_time: Wall time of the case [s] (one process).
    """

    case: SweepCase
    largest_survived: float
    smallest_fallen: float | None
    trials: tuple[tuple[float, bool], ...]
    wall_time: float

    def to_dict(self) -> dict:
        """JSON-ready record (impulses in [N s], time in [s])."""
        return {
            **asdict(self.case),
            "largest_survived_Ns": self.largest_survived,
            "smallest_fallen_Ns": self.smallest_fallen,
            "trials": [[round(value, 6), ok] for value, ok in self.trials],
            "wall_time_s": self.wall_time,
        }


def summarize_sweep(results: Sequence[CaseResult], config: PushSweepConfig) -> dict:
    """Per controller: largest impulse per direction (median over phases), median over the
    grid, success rate over :attr:`PushSweepConfig.impulse_grid` (a grid impulse counts as
    survived in a cell when it is at most the cell's largest impulse survived: the oracle is
    taken as monotone) and over the walks actually run."""
    summary = {}
    for name in dict.fromkeys(r.case.controller for r in results):
        rows = [r for r in results if r.case.controller == name]
        largest = np.array([r.largest_survived for r in rows])
        per_direction = {}
        for direction in config.directions_deg:
            values = [r.largest_survived for r in rows if r.case.direction_deg == direction]
            if values:
                per_direction[f"{direction:g}"] = float(np.median(values))
        grid = np.asarray(config.impulse_grid)
        survived_grid = (grid[None, :] <= largest[:, None] + 1e-12).mean() if grid.size else None
        trials = [ok for r in rows for _, ok in r.trials]
        summary[name] = {
            "median_impulse_Ns": float(np.median(largest)),
            "min_impulse_Ns": float(largest.min()),
            "max_impulse_Ns": float(largest.max()),
            "per_direction_Ns": per_direction,
            "success_rate_grid": None if survived_grid is None else float(survived_grid),
            "success_rate_runs": float(np.mean(trials)) if trials else None,
            "nb_cases": len(rows),
            "nb_walks": len(trials),
            "censored_cases": int(sum(r.smallest_fallen is None for r in rows)),
            "wall_time_s": float(sum(r.wall_time for r in rows)),
        }
    return summary
