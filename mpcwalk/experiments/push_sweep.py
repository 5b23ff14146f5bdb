"""Push recovery: the largest impulse a walking controller survives, and the LIPM's bounds.

A push is a horizontal force on the torso for ``push_duration`` (0.1 s), of impulse ``J``
[N s] (force = J / duration), in one of several directions of the world frame (0 deg:
forward, 90 deg: left), applied at a gait phase of one step of a straight walk. For each
(controller, direction, phase) :func:`find_largest_survived` brackets and bisects the
impulse: a walk *survives* when the fall detector has not fired by the end of the run.

Reference: the capturability of the linear inverted pendulum (mass ``m``, ``omega =
sqrt(g / z_c)``). An impulse moves the divergent component of motion (DCM) by
``J / (m omega)``; with the ZMP at most ``d`` from the foot centre in that direction, the robot
stops without stepping when ``J <= m omega d`` (:func:`capture_impulse_bound`). With one step
that lands ``t`` after the push, at most ``L`` further in that direction, the DCM has grown by
``exp(omega t)`` and the bound becomes ``m omega (d + L exp(-omega t))``.
"""

import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError

GRAVITY = 9.81  # [m/s^2]


def rectangle_ray_distance(
    direction: float, forward: float, backward: float, lateral: float
) -> float:
    """Distance [m] from the origin to the border of a rectangle along a direction.

    Args:
        direction: Direction [rad] (0: +x forward, pi/2: +y left).
        forward: Extent of the rectangle along +x [m].
        backward: Extent along -x [m].
        lateral: Half-width along +-y [m].
    """
    c, s = math.cos(direction), math.sin(direction)
    candidates = []
    if c > 1e-12:
        candidates.append(forward / c)
    elif c < -1e-12:
        candidates.append(backward / -c)
    if abs(s) > 1e-12:
        candidates.append(lateral / abs(s))
    return float(min(candidates))


def capture_impulse_bound(
    direction: float,
    *,
    mass: float,
    com_height: float,
    half_length: float = 0.05,
    half_width: float = 0.03,
    step_reach: tuple[float, float, float] | None = None,
    step_time: float = 0.25,
    gravity: float = GRAVITY,
) -> float:
    """Largest impulse [N s] the LIPM can absorb, without a step or with one step.

    Args:
        direction: Push direction [rad] in the foot frame (0: forward).
        mass: Robot mass [kg].
        com_height: CoM height z_c [m].
        half_length: Half sole length [m] (ZMP reach forward and backward).
        half_width: Half sole width [m] (ZMP reach sideways).
        step_reach: ``(forward, backward, lateral)`` reach of one step [m]; None: no step.
        step_time: Time from the push to the step's landing [s].
        gravity: [m/s^2].

    Returns:
        ``m omega (d + L exp(-omega t))`` with ``d`` the sole's extent and ``L`` the step's
        reach in that direction (``L = 0`` without a step).
    """
    if mass <= 0.0 or com_height <= 0.0:
        raise ConfigurationError(
            f"capture_impulse_bound needs mass > 0 kg and com_height > 0 m, got {mass!r} kg "
            f"and {com_height!r} m."
        )
    omega = math.sqrt(gravity / com_height)
    d = rectangle_ray_distance(direction, half_length, half_length, half_width)
    reach = 0.0 if step_reach is None else rectangle_ray_distance(direction, *step_reach)
    return mass * omega * (d + reach * math.exp(-omega * step_time))


@dataclass(frozen=True)
class BisectionResult:
    """Outcome of :func:`find_largest_survived`.

    Attributes:
        largest_survived: Largest value that survived (0 if none was tried and survived).
        smallest_fallen: Smallest value that fell, None if none fell (censored at the limit).
        trials: ``(value, survived)`` in the order they were tried.
    """

    largest_survived: float
    smallest_fallen: float | None
    trials: tuple[tuple[float, bool], ...]

    @property
    def censored(self) -> bool:
        """True when even the upper limit survived (the threshold is above it)."""
        return self.smallest_fallen is None


def find_largest_survived(
    survives: Callable[[float], bool],
    *,
    initial: float,
    upper_limit: float,
    tolerance: float,
    relative_tolerance: float = 0.0,
    lower_limit: float | None = None,
) -> BisectionResult:
    """Threshold of a survival oracle that is monotone (survives below, falls above).

    Brackets from ``initial`` (doubling while it survives, halving while it falls), then
    bisects until the bracket is narrower than ``max(tolerance, relative_tolerance * hi)``.
    Value 0 is assumed to survive and is never tried.

    Args:
        survives: Oracle, e.g. a walk with a push of that impulse.
        initial: First value tried (> 0).
        upper_limit: Largest value tried; if it survives, the result is censored there.
        tolerance: Absolute bracket width at which to stop.
        relative_tolerance: Relative bracket width at which to stop.
        lower_limit: Smallest value tried when halving (default: ``tolerance``); below it
            the result is 0.

    Returns:
        The bracket and every trial.
    """
    if not (0.0 < initial <= upper_limit) or tolerance <= 0.0:
        raise ConfigurationError(
            f"find_largest_survived needs 0 < initial <= upper_limit and tolerance > 0, got "
            f"initial={initial!r}, upper_limit={upper_limit!r}, tolerance={tolerance!r}."
        )
    floor = tolerance if lower_limit is None else lower_limit
    trials: list[tuple[float, bool]] = []

    def trial(value: float) -> bool:
        ok = bool(survives(value))
        trials.append((float(value), ok))
        return ok

    value, lo, hi = initial, 0.0, None
    if trial(value):
        lo = value
        while lo < upper_limit:
            value = round(min(2.0 * lo, upper_limit), 9)
            if value <= lo:  # the limit, rounded, was tried: nothing is left above
                break
            if not trial(value):
                hi = value
                break
            lo = value
        if hi is None:
            return BisectionResult(lo, None, tuple(trials))
    else:
        hi = value
        while hi / 2.0 >= floor:
            value = round(hi / 2.0, 9)
            if trial(value):
                lo = value
                break
            hi = value
    while hi - lo > max(tolerance, relative_tolerance * hi):
        value = round(0.5 * (lo + hi), 9)
        if trial(value):
            lo = value
        else:
            hi = value
    return BisectionResult(lo, hi, tuple(trials))


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
