"""Attitude metrics of a walk: roll/pitch excursions, yaw rate over the walking phases, and
the yaw deviation a push causes (paper M's measure of its stabilizer)."""

import itertools
from typing import Any

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.walking.log import WalkLog


def attitude_metrics(log: WalkLog, schedule: ContactSchedule, end: float) -> dict[str, Any]:
    """Yaw rate over the walking phases (start-up excluded), roll/pitch excursions."""
    metrics: dict[str, Any] = {
        "roll_max_deg": None,
        "pitch_max_deg": None,
        "yaw_rate_deg_s": None,
        "yaw_rate_planned_deg_s": None,
    }
    if not len(log):
        return metrics
    rpy = np.unwrap(log.base_rpy, axis=0)
    excursion = np.degrees(np.abs(rpy - rpy[0]).max(axis=0))
    metrics["roll_max_deg"] = float(excursion[0])
    metrics["pitch_max_deg"] = float(excursion[1])
    start = schedule.walk_start + schedule.step_duration
    stop = min(schedule.walk_end - schedule.step_duration, end)
    nb_steps = int(np.floor((stop - schedule.walk_start) / schedule.step_duration + 1e-9))
    stop = schedule.walk_start + nb_steps * schedule.step_duration
    if stop - start < schedule.step_duration - 1e-9:
        return metrics
    yaw_start, yaw_stop = np.interp([start, stop], log.time, rpy[:, 2])
    metrics["yaw_rate_deg_s"] = float(np.degrees(yaw_stop - yaw_start) / (stop - start))
    planned = planned_yaw_change(schedule, nb_steps + 1) - planned_yaw_change(schedule, 2)
    metrics["yaw_rate_planned_deg_s"] = float(np.degrees(planned) / (stop - start))
    return metrics


def yaw_deviation_deg(
    log: WalkLog, reference: WalkLog, after: float, *, statistic: str = "max"
) -> float:
    """IMU yaw of a walk against the same walk without its pushes [deg].

    ``|yaw(t) - yaw_reference(t)|`` (difference wrapped to [-180, 180) deg, the reference
    interpolated at the walk's ticks) over ``after <= t <= end``, ``after`` the end of the
    last push and ``end`` the end of the shorter log; ``statistic`` "max" (paper M's
    deviation caused by F2, the default) or "final" (at ``end``). 0 when no tick lies in the
    window.

    Raises:
        ConfigurationError: Another statistic.
    """
    if statistic not in ("max", "final"):
        raise ConfigurationError(f"statistic must be 'max' or 'final', got {statistic!r}.")
    if not len(log) or not len(reference):
        return 0.0
    end = min(float(log.time[-1]), float(reference.time[-1]))
    mask = (log.time >= after - 1e-9) & (log.time <= end + 1e-9)
    if not np.any(mask):
        return 0.0
    reference_yaw = np.interp(log.time[mask], reference.time, np.unwrap(reference.base_rpy[:, 2]))
    deviation = np.abs(wrap_angle(np.unwrap(log.base_rpy[:, 2])[mask] - reference_yaw))
    return float(np.degrees(deviation.max() if statistic == "max" else deviation[-1]))


def planned_yaw_change(schedule: ContactSchedule, nb_stances: int) -> float:
    """The heading [rad] the plan's first ``nb_stances`` stances turn through (the mid-yaw
    of each stance's two soles, summed stance to stance)."""
    yaws, total = [], 0.0
    for stance in schedule.plan.stances()[:nb_stances]:
        left, right = stance[Side.LEFT].yaw, stance[Side.RIGHT].yaw
        yaws.append(left + 0.5 * float(wrap_angle(right - left)))
    for a, b in itertools.pairwise(yaws):
        total += float(wrap_angle(b - a))
    return total
