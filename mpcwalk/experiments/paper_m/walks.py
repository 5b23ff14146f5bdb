"""Paper M's walks for every controller of the comparison: the turning and disturbance
walks, one cell of the push sweep, the speed search.

Controllers are data: :data:`CONTROLLERS` maps a name to a
:class:`~mpcwalk.walking.specification.ControllerSpec` (generator, feedback, stabilizers, options);
tune them there. Each walk is a :class:`~mpcwalk.walking.specification.WalkSpec` of the controller
and the walk's fields (:func:`walk_task`). The parameters of each walk are :mod:`mpcwalk.experiments.paper_m.config`'s.
A walk survives by :func:`~mpcwalk.experiments.survival.survived`: it neither fell nor was
stopped by the controller.
"""

import itertools
import math
import time
from collections.abc import Mapping
from typing import Any

import numpy as np

from mpcwalk.exceptions import InfeasibleCommand
from mpcwalk.experiments.paper_m.config import SpeedConfig, TurningConfig
from mpcwalk.experiments.paper_m.push_grid import CaseResult, PushSweepConfig, SweepCase
from mpcwalk.experiments.survival import find_largest_survived, survived
from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.walking.result import WalkResult
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import ControllerSpec, WalkSpec
from mpcwalk.walking.sweep_cases import worker_robot

#: The controllers compared: name -> its :class:`~mpcwalk.walking.specification.ControllerSpec` (the
#: named controllers, ``mpcwalk controllers``, and two variants). Names that this
#: installation does not know (generator, stabilizer) are skipped with the reason
#: (:func:`controller_availability`). Every ratio is taken against ``paper-m``, paper M's
#: whole engine; ``paper-m-open`` and ``analytic+gyro`` are in the tables for information.
CONTROLLERS: dict[str, ControllerSpec] = {
    "paper-m-open": ControllerSpec.named("paper-m-open"),
    "analytic+gyro": ControllerSpec.named("paper-m-open").replace(stabilizers=("gyro",)),
    # paper M's whole engine: closed form, gyro stabilizer and arm swing (s = 0.8)
    "paper-m": ControllerSpec.named("paper-m"),
    "preview": ControllerSpec.named("preview"),
    "mpc": ControllerSpec.named("mpc"),
    "mpc-steps": ControllerSpec.named("mpc-steps"),
    # the QP alone, without the capture-point term (FootstepMpcGenerator.dcm_step_gain)
    "mpc-steps-qp-only": ControllerSpec.named("mpc-steps").replace(
        generator_options={"dcm_step_gain": 0.0}
    ),
}


def controller_availability(
    controllers: Mapping[str, ControllerSpec] = CONTROLLERS,
) -> dict[str, str | None]:
    """Name -> None if the controller can run here, else why not (an unknown generator or
    stabilizer: built in parallel, not there yet)."""
    from mpcwalk.control.stabilizers import STABILIZERS
    from mpcwalk.generators import generator_names

    reasons: dict[str, str | None] = {}
    for name, spec in controllers.items():
        unknown = [s for s in spec.stabilizers if s not in STABILIZERS]
        if spec.generator not in generator_names():
            reasons[name] = f"no generator '{spec.generator}'"
        elif unknown:
            reasons[name] = f"no stabilizer '{unknown[0]}'"
        else:
            reasons[name] = None
    return reasons


def with_stabilizer(spec: ControllerSpec, stabilizer: str | None) -> ControllerSpec:
    """The same controller with another stabilizer (None: without one)."""
    return spec.replace(stabilizers=() if stabilizer is None else (stabilizer,))


def has_stabilizer(spec: ControllerSpec) -> bool:
    """Whether the controller has a stabilizer."""
    return bool(spec.stabilizers)


def _push(push: Any) -> tuple[float, float, float, float, float]:
    """A push as ``(start [s], duration [s], fx, fy, fz [N])`` (from a tuple or an
    :class:`~mpcwalk.sim.ExternalForce`)."""
    if hasattr(push, "force"):
        fx, fy, fz = (float(f) for f in push.force)
        return (float(push.start), float(push.duration), fx, fy, fz)
    start, duration, fx, fy, fz = (float(v) for v in push)
    return (start, duration, fx, fy, fz)


def walk_spec(
    robot_name: str, controller: ControllerSpec, walk_args: Mapping[str, Any]
) -> WalkSpec:
    """The walk of a controller with the fields ``walk_args`` (``command``, ``duration``,
    ``nb_steps``, ``step_duration``, ``pushes``...: fields of a
    :class:`~mpcwalk.walking.specification.WalkSpec`)."""
    fields = dict(walk_args)
    if "pushes" in fields:
        fields["pushes"] = tuple(_push(p) for p in fields["pushes"])
    return WalkSpec.build(robot_name, controller=controller, **fields)


def walk_task(
    robot_name: str, controller: ControllerSpec, walk_args: Mapping[str, Any]
) -> WalkResult:
    """One walk of a controller with the fields ``walk_args`` (:func:`walk_spec`)."""
    spec = walk_spec(robot_name, controller, walk_args)
    return run_walk(spec, robot=worker_robot(robot_name))


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


def _survives(robot, controller, walk_args) -> tuple[bool, WalkResult]:
    result = run_walk(walk_spec(robot.name, controller, walk_args), robot=robot)
    return survived(result), result


def push_case_task(
    robot_name: str, controller: ControllerSpec, config: PushSweepConfig, case: SweepCase
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
        fx, fy, fz = (float(f) for f in config.push_force(case.direction_deg, impulse))
        push = (start, config.push_duration, fx, fy, fz)
        return _survives(
            robot,
            controller,
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
    robot_name: str, controller: ControllerSpec, config: SpeedConfig, step_duration: float
) -> dict[str, Any]:
    """Fastest forward command [m/s] that survives ``config.nb_steps`` steps, by
    bisection up to the kinematic bound ``max_step_forward / T`` (the velocity planner
    refuses faster commands), and what limits it."""
    robot = worker_robot(robot_name)
    bound = robot.leg_limits.max_step_forward / step_duration
    walks: dict[float, tuple[bool, str, float | None]] = {}

    def survives(vx: float) -> bool:
        try:
            ok, result = _survives(
                robot,
                controller,
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
        why = result.fall.reason if result.fall.fell else result.metrics.outcome
        walks[vx] = (ok, why, speed)
        return ok

    wall = time.perf_counter()
    found = find_largest_survived(
        survives, initial=bound, upper_limit=bound, tolerance=config.tolerance
    )
    best = found.largest_survived
    if found.censored or found.smallest_fallen is None:
        limit = "kinematic bound (vx T = max_step_forward)"
    else:
        limit = f"fails at {found.smallest_fallen:.3f} m/s ({walks[found.smallest_fallen][1]})"
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


__all__ = [
    "CONTROLLERS",
    "controller_availability",
    "has_stabilizer",
    "push_case_task",
    "speed_task",
    "turning_summary",
    "walk_spec",
    "walk_task",
    "with_stabilizer",
]
