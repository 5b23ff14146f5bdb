"""Paper M's experiments on the bioloid-like robot, for every controller of the comparison.

Controllers are data: :data:`CONTROLLERS` maps a name to the keyword arguments of
:func:`~mpcwalk.walking.runner.run_walk` (generator, feedback, stabilizer, options); tune them there.
The experiments (parameters in :class:`PaperMConfig`, read from
``experiments/paper_m/paper_m.toml`` by :func:`load_config`):

1. turning walk (paper M Fig. 1): yaw after 3.5 s of walking and mean yaw rate
   (:func:`turning_summary`);
2. disturbances F1, F2 (paper M Fig. 2): yaw deviation after F2 against the same walk without
   pushes (:func:`mpcwalk.walking.metrics.yaw_deviation_deg`), with the stabilizer off and on;
3. push recovery: largest impulse survived per direction and gait phase
   (:mod:`mpcwalk.experiments.push_sweep`);
4. speed: the fastest forward walk without a fall (:func:`speed_search`).

:func:`run_paper_m` (in :mod:`mpcwalk.experiments.paper_m_report`) runs them as Ray tasks
(:func:`mpcwalk.sweep.map_tasks`) and writes the table and the figures.
"""

import dataclasses
import inspect
import itertools
import math
import sys
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mpcwalk.exceptions import ConfigurationError, InfeasibleCommand
from mpcwalk.experiments.push_sweep import (
    CaseResult,
    PushSweepConfig,
    SweepCase,
    find_largest_survived,
)
from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.robot.package_data import EXPERIMENT_DATA, package_data_dir
from mpcwalk.sim import ExternalForce
from mpcwalk.sweep.walks import worker_robot
from mpcwalk.walking.controllers import controller_config
from mpcwalk.walking.result import WalkResult
from mpcwalk.walking.runner import run_walk

#: The controllers compared: name -> keyword arguments of :func:`mpcwalk.walking.runner.run_walk`
#: (the named configurations of :mod:`mpcwalk.walking.controllers`, by hand so that the
#: disturbance experiment can toggle the stabilizer). Names that this installation does not
#: know (generator, stabilizer, argument) are skipped with the reason
#: (:func:`controller_availability`). Every ratio is taken against ``paper-m``, paper M's
#: whole engine; ``paper-m-open`` and ``analytic+gyro`` are in the tables for information.
CONTROLLERS: dict[str, dict[str, Any]] = {
    "paper-m-open": controller_config("paper-m-open").walk_kwargs(),
    "analytic+gyro": {**controller_config("paper-m-open").walk_kwargs(), "stabilizer": "gyro"},
    # paper M's whole engine: closed form, gyro stabilizer and arm swing (s = 0.8)
    "paper-m": controller_config("paper-m").walk_kwargs(),
    "preview": controller_config("preview").walk_kwargs(),
    "mpc": controller_config("mpc").walk_kwargs(),
    "mpc-steps": controller_config("mpc-steps").walk_kwargs(),
    # the QP alone, without the capture-point term (FootstepMpcGenerator.dcm_step_gain)
    "mpc-steps-qp-only": {
        **controller_config("mpc-steps").walk_kwargs(),
        "generator_options": {"dcm_step_gain": 0.0},
    },
}

#: Experiment names of :func:`mpcwalk.experiments.paper_m_report.run_paper_m`.
EXPERIMENTS = ("turning", "disturbance", "push", "speed")

DEFAULT_CONFIG = package_data_dir(EXPERIMENT_DATA) / "paper_m" / "paper_m.toml"


@dataclass(frozen=True)
class TurningConfig:
    """Paper M's turning walk: command ``(vx [m/s], vy [m/s], vyaw [rad/s])``, walking time
    [s], and the walking time [s] at which the yaw is read (paper M: about 70 deg at 3.5 s)."""

    command: tuple[float, float, float] = (0.1, 0.0, math.pi / 9.0)
    walking_duration: float = 10.0
    yaw_check_time: float = 3.5


@dataclass(frozen=True)
class DisturbanceConfig:
    """Paper M's disturbance walk: command, walking time [s], pushes as
    ``(start [s], duration [s], (fx, fy, fz) [N])`` on the torso, the stabilizer toggled for
    the ratio of the yaw deviations."""

    command: tuple[float, float, float] = (0.1, 0.0, 0.0)
    walking_duration: float = 5.0
    pushes: tuple[tuple[float, float, tuple[float, float, float]], ...] = (
        (0.0, 0.1, (0.0, 5.0, 0.0)),
        (3.0, 0.05, (10.0, 5.0, 0.0)),
    )
    stabilizer: str = "gyro"

    def external_forces(self) -> list[ExternalForce]:
        """The pushes as :class:`~mpcwalk.sim.ExternalForce` on the torso."""
        return [
            ExternalForce(start, duration, np.array(force, dtype=float))
            for start, duration, force in self.pushes
        ]

    @property
    def last_push_end(self) -> float:
        """End of the last push [s] (the yaw deviation is measured after it)."""
        return max(start + duration for start, duration, _ in self.pushes)


@dataclass(frozen=True)
class SpeedConfig:
    """Speed search: step durations tried [s], commanded steps per walk, tolerance [m/s]."""

    step_durations: tuple[float, ...] = (0.5, 0.4)
    nb_steps: int = 10
    tolerance: float = 0.005


@dataclass(frozen=True)
class PaperMConfig:
    """All of paper M's experiments (see the module docstring)."""

    robot: str = "bioloid-like"
    mode: str = "full"
    turning: TurningConfig = field(default_factory=TurningConfig)
    disturbance: DisturbanceConfig = field(default_factory=DisturbanceConfig)
    push_sweep: PushSweepConfig = field(default_factory=PushSweepConfig)
    speed: SpeedConfig = field(default_factory=SpeedConfig)


def _tuples(value):
    if isinstance(value, list):
        return tuple(_tuples(v) for v in value)
    return value


def _section(cls, values: Mapping[str, Any], where: str):
    names = {f.name for f in dataclasses.fields(cls)}
    unknown = sorted(set(values) - names)
    if unknown:
        raise ConfigurationError(
            f"Unknown key(s) {unknown} in [{where}]; the keys are {sorted(names)}."
        )
    return cls(**{key: _tuples(value) for key, value in values.items()})


def load_config(path=DEFAULT_CONFIG, *, mode: str = "full") -> PaperMConfig:
    """Read the experiments' parameters from a TOML file; ``mode="quick"`` applies its
    ``[quick.*]`` tables over the others (the reduced grid)."""
    if sys.version_info >= (3, 11):
        import tomllib
    else:  # the tomli package is tomllib before Python 3.11
        import tomli as tomllib

    with open(path, "rb") as stream:
        data = tomllib.load(stream)
    if mode not in ("full", "quick"):
        raise ConfigurationError(f"mode must be 'full' or 'quick', got {mode!r}.")
    sections = {
        "turning": TurningConfig,
        "disturbance": DisturbanceConfig,
        "push_sweep": PushSweepConfig,
        "speed": SpeedConfig,
    }
    values = {"robot": data.get("robot", "bioloid-like"), "mode": mode}
    for name, cls in sections.items():
        merged = dict(data.get(name, {}))
        if mode == "quick":
            merged.update(data.get("quick", {}).get(name, {}))
        values[name] = _section(cls, merged, name)
    return PaperMConfig(**values)


def controller_availability(
    controllers: Mapping[str, Mapping[str, Any]] = CONTROLLERS,
) -> dict[str, str | None]:
    """Name -> None if the controller can run here, else why not (unknown generator,
    stabilizer or :func:`run_walk` argument: built in parallel, not there yet)."""
    from mpcwalk.control.stabilizers import STABILIZERS
    from mpcwalk.generators import generator_names

    parameters = inspect.signature(run_walk).parameters
    reasons: dict[str, str | None] = {}
    for name, kwargs in controllers.items():
        unknown = [key for key in kwargs if key not in parameters]
        stabilizer = kwargs.get("stabilizer")
        if unknown:
            reasons[name] = f"run_walk has no argument(s) {unknown}"
        elif kwargs.get("generator", "mpc") not in generator_names():
            reasons[name] = f"no generator '{kwargs.get('generator')}'"
        elif isinstance(stabilizer, str) and stabilizer not in STABILIZERS:
            reasons[name] = f"no stabilizer '{stabilizer}'"
        else:
            reasons[name] = None
    return reasons


def with_stabilizer(kwargs: Mapping[str, Any], stabilizer: str | None) -> dict[str, Any]:
    """The same controller with another stabilizer (None: without one)."""
    return {**kwargs, "stabilizer": stabilizer}


def has_stabilizer(kwargs: Mapping[str, Any]) -> bool:
    """Whether the controller has a stabilizer."""
    return kwargs.get("stabilizer") not in (None, "none")


def walk_task(
    robot_name: str, kwargs: Mapping[str, Any], walk_args: Mapping[str, Any]
) -> WalkResult:
    """One walk of a controller (``kwargs``) with extra :func:`run_walk` arguments."""
    return run_walk(worker_robot(robot_name), progress=False, **{**kwargs, **walk_args})


def _stance_yaw(stance) -> float:
    left, right = stance[Side.LEFT].yaw, stance[Side.RIGHT].yaw
    return left + 0.5 * float(wrap_angle(right - left))


def turning_summary(result: WalkResult, config: TurningConfig) -> dict[str, Any]:
    """Yaw [deg] after ``config.yaw_check_time`` of walking, and the mean yaw rate [deg/s]
    over whole steps: from the end of the first step to the last step boundary before the
    closing step or the fall (IMU, beside the footsteps' planned rate and the command)."""
    schedule, log = result.schedule, result.log
    T, start = schedule.step_duration, schedule.walk_start
    yaw = np.unwrap(log.base_rpy[:, 2]) - log.base_rpy[0, 2]
    check = start + config.yaw_check_time
    yaw_at_check = (
        float(np.degrees(np.interp(check, log.time, yaw))) if check <= log.time[-1] + 1e-9 else None
    )
    end = min(schedule.walk_end - T, float(log.time[-1]))
    k_last = int(math.floor((end - start) / T + 1e-9))
    rate = planned = None
    if k_last > 1:
        t0, t1 = start + T, start + k_last * T
        rate = float(
            np.degrees(np.interp(t1, log.time, yaw) - np.interp(t0, log.time, yaw)) / (t1 - t0)
        )
        yaws = [_stance_yaw(stance) for stance in schedule.plan.stances()[1 : k_last + 1]]
        turned = sum(float(wrap_angle(b - a)) for a, b in itertools.pairwise(yaws))
        planned = float(np.degrees(turned) / (t1 - t0))
    commanded = float(np.degrees(config.command[2]))
    return {
        "fell": bool(result.fall.fell),
        "fall_time_s": result.metrics.fall_time_s,
        "yaw_at_check_deg": yaw_at_check,
        "yaw_check_time_s": config.yaw_check_time,
        "yaw_rate_deg_s": rate,
        "yaw_rate_planned_deg_s": planned,
        "yaw_rate_commanded_deg_s": commanded,
        "yaw_rate_error_percent": None if rate is None else 100.0 * (rate - commanded) / commanded,
        "roll_max_deg": float(np.degrees(np.abs(log.base_rpy[:, 0]).max())),
        "pitch_max_deg": float(np.degrees(np.abs(log.base_rpy[:, 1] - log.base_rpy[0, 1]).max())),
    }


def _survives(robot, kwargs, walk_args) -> tuple[bool, WalkResult]:
    result = run_walk(robot, progress=False, **{**kwargs, **walk_args})
    return not result.fall.fell, result


def push_case_task(
    robot_name: str, kwargs: Mapping[str, Any], config: PushSweepConfig, case: SweepCase
) -> CaseResult:
    """Largest impulse survived by one controller in one direction and gait phase."""
    robot = worker_robot(robot_name)
    start = config.push_start(
        case.phase,
        step_duration=robot.gait.step_duration,
        double_support_ratio=robot.gait.double_support_ratio,
    )
    wall = time.perf_counter()

    def survives(impulse: float) -> bool:
        push = ExternalForce(
            start, config.push_duration, config.push_force(case.direction_deg, impulse)
        )
        return _survives(
            robot,
            kwargs,
            {"command": config.command, "nb_steps": config.nb_steps, "pushes": [push]},
        )[0]

    found = find_largest_survived(
        survives,
        initial=config.initial_impulse,
        upper_limit=config.max_impulse,
        tolerance=config.tolerance,
        relative_tolerance=config.relative_tolerance,
    )
    return CaseResult(
        case,
        found.largest_survived,
        found.smallest_fallen,
        found.trials,
        time.perf_counter() - wall,
    )


def speed_task(
    robot_name: str, kwargs: Mapping[str, Any], config: SpeedConfig, step_duration: float
) -> dict[str, Any]:
    """Fastest forward command [m/s] walked ``config.nb_steps`` steps without a fall, by
    bisection up to the kinematic bound ``max_step_forward / T`` (the velocity planner
    refuses faster commands), and what limits it."""
    robot = worker_robot(robot_name)
    bound = robot.leg_limits.max_step_forward / step_duration
    walks: dict[float, tuple[bool, str, float | None]] = {}

    def survives(vx: float) -> bool:
        try:
            ok, result = _survives(
                robot,
                kwargs,
                {
                    "command": (vx, 0.0, 0.0),
                    "nb_steps": config.nb_steps,
                    "step_duration": step_duration,
                },
            )
        except InfeasibleCommand as error:
            walks[vx] = (False, f"infeasible: {error}", None)
            return False
        s = result.schedule
        t0, t1 = s.walk_start + s.step_duration, s.walk_end - s.step_duration
        speed = None
        if ok and t1 > t0:
            x0, x1 = np.interp([t0, t1], result.log.time, result.log.com[:, 0])
            speed = float((x1 - x0) / (t1 - t0))
        walks[vx] = (ok, result.fall.reason, speed)
        return ok

    wall = time.perf_counter()
    found = find_largest_survived(
        survives, initial=bound, upper_limit=bound, tolerance=config.tolerance
    )
    best = found.largest_survived
    if found.censored or found.smallest_fallen is None:
        limit = "kinematic bound (vx T = max_step_forward)"
    else:
        limit = f"falls at {found.smallest_fallen:.3f} m/s ({walks[found.smallest_fallen][1]})"
    return {
        "step_duration_s": step_duration,
        "bound_m_s": bound,
        "fastest_m_s": best,
        "fastest_measured_m_s": walks.get(best, (None, None, None))[2],
        "smallest_fallen_m_s": found.smallest_fallen,
        "limited_by": limit,
        "trials": [[round(vx, 6), ok] for vx, ok in found.trials],
        "wall_time_s": time.perf_counter() - wall,
    }
