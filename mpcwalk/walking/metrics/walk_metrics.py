"""What a simulated walk measured: :class:`WalkMetrics`, computed from its log.

Landings are measured in the middle of the next single support, when the landed foot
carries the robot (as paper A's Fig. 8), or 0.5 s after the last landing
(:func:`landing_check_times`). The CoP margins are the signed distances of the measured CoP
to the support of the soles that carry force at each tick (:func:`cop_margins`).
"""

from dataclasses import asdict, dataclass, replace
from typing import Any

import numpy as np

from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.sim import FallStatus
from mpcwalk.terrain import Terrain
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics.attitude import attitude_metrics, planned_yaw_change, yaw_deviation_deg
from mpcwalk.walking.metrics.cop_margins import cop_margins, measured_support_polygon
from mpcwalk.walking.metrics.estimator_accuracy import EstimatorAccuracy
from mpcwalk.walking.metrics.terrain_metrics import terrain_metrics

_SIDES = (Side.LEFT, Side.RIGHT)


@dataclass(frozen=True)
class WalkMetrics:
    """Metrics of a simulated walk; the fields are the keys of ``metrics.json``.

    None where a metric cannot be measured (no landing checked, no CoP, a run shorter than
    the window). Units are in the names.

    Attributes:
        fell: The fall detector stopped the walk early.
        fall_reason: Why it fell ("" without a fall).
        fall_time_s: When it fell [s], None without a fall.
        time_planned_s: Duration of the schedule [s]: standing before, walking, standing after.
        walking_time_planned_s: Walking part of the schedule [s] (every step, the closing
            one included).
        time_simulated_s: Simulated time [s] (the schedule, or up to the fall).
        steps_planned: Footsteps of the plan, the closing step included.
        closing_steps: Footsteps added after the commanded ones to end side by side (1 for a
            velocity command, 0 for a path file).
        steps_completed: Steps whose landing was checked before the end of the run.
        foot_position_error_cm_mean: Landed sole against its footstep, world frame [cm]
            (includes the drift of all earlier landings); ``_max``: the largest.
        foot_yaw_error_deg_mean: Same for the yaw [deg]; ``_max``: the largest.
        foot_step_error_cm_mean: The landing relative to the measured support foot at the end
            of its swing, against the plan [cm] (no drift); ``_max``: the largest.
        foot_step_yaw_error_deg_mean: Same for the yaw [deg]; ``_max``: the largest.
        distance_m: Measured CoM, start to end [m].
        distance_planned_m: Midpoints of the first and last stance of the plan [m].
        distance_planned_reached_m: Same up to the last stance reached [m].
        yaw_change_deg: IMU yaw, start to end [deg].
        yaw_change_planned_deg: Heading of the planned stances, first to last [deg].
        cop_margin_min_m: Smallest signed distance of the measured CoP to the support of
            the soles carrying force [m], positive inside (on level ground: in the hull of
            the loaded soles; :mod:`~mpcwalk.walking.metrics.cop_margins`).
        cop_margin_p05_m: Its 5th percentile [m].
        cop_outside_share: Share of the ticks with the CoP outside.
        com_error_rms_m: Measured CoM against the generator's reference, world frame, RMS [m].
        com_error_max_m: Its largest value [m].
        ik_error_max_m: Largest CoM/sole position error of the IK [m].
        generator_tick_us_median: Median wall time of the generator per tick [us].
        ik_tick_us_median: Median wall time of the IK per tick [us].
        controller_tick_us_median: Median wall time of the whole controller tick [us].
        mujoco_step_us_median: Median wall time of the physics per control period [us].
        estimator_tick_us_median: Median wall time of the state estimator per tick [us]
            (None when the controller read the ground truth).
        real_time_factor: Simulated time over the loop's wall time (one process).
        nb_ticks: Control ticks simulated.
        torque_saturation_share: Share of the ticks with a servo at its torque limit.
        mpc_failures: Ticks whose generator reported a failed solve.
        roll_max_deg: Largest IMU roll away from its value at the start [deg].
        pitch_max_deg: Same for the pitch [deg].
        yaw_rate_deg_s: Mean IMU yaw rate over the walking phases [deg/s], start-up and stop
            excluded: from the end of the first step to the end of the one before the last
            (the closing step of a velocity command), or to the fall.
        yaw_rate_planned_deg_s: Rate of the footsteps' heading over the same steps [deg/s].
        estimator_com_error_rms_m: Estimated CoM against the true one (3D) at the time of
            the readings it came from, RMS over the ticks [m]; None when the controller read
            the ground truth (:class:`~mpcwalk.walking.metrics.estimator_accuracy.EstimatorAccuracy`).
        estimator_com_error_max_m: Its largest value [m].
        estimator_com_error_support_rms_m: Same for the CoM relative to the support (the
            mean of the soles in contact), RMS [m]: free of the odometry's drift.
        estimator_com_velocity_error_rms_m_s: Same for the CoM velocity, RMS [m/s].
        estimator_yaw_drift_deg: Estimated minus true base yaw at the end of the walk, less
            that at its start [deg].
        yaw_deviation_deg: After the last push, the largest IMU yaw difference with the same
            walk without the pushes [deg] (:func:`yaw_deviation_deg`; None without one).
        outcome: ``"walked"`` (the schedule's end reached standing), ``"fell"``, ``"stopped"``
            (the controller stopped the walk: faults beyond its bound) or ``"interrupted"``.
        stop_reason: Why the controller stopped the walk ("" otherwise).
        interrupted: The run was interrupted (SIGINT): the metrics are of the partial walk.
        sensor_faults: Ticks whose sensor readings or estimate were not finite or did not
            arrive (the last good estimate was used; :mod:`mpcwalk.control.faults`).
        ik_failures: Ticks whose IK output was not finite (the reference held).
        fallback_ticks: Ticks with any fault (a failed solve included).
        warnings: What makes the walk far from its plan though it did not fall
            (:func:`sanity_warnings`): large unplanned yaw, CoP long outside the soles,
            landings far from their footsteps; and, first, what the controller left out
            of its specification (the arm swing of a robot without shoulder pitch joints).
        landing_error_3d_cm_mean: On a terrain (None on the floor): landed sole centre
            against its footstep in 3D [cm]; ``_max``: the largest.
        landing_height_error_cm_max: On a terrain: largest landing height error [cm].
        tread_margin_cm_min: On a terrain: smallest distance of a landed sole's corners to
            the edges of its top [cm] (negative: overhanging).
        swing_clearance_cm_min: On a terrain: lowest height of a swinging sole's corners
            above the terrain under them, mid-swing [cm].
        toe_stubs: On a terrain: swings in which a sole corner went below the terrain.
        com_height_error_cm_rms: On a terrain: measured CoM height against the height
            profile's, RMS [cm].
    """

    fell: bool
    fall_reason: str
    fall_time_s: float | None
    time_planned_s: float
    walking_time_planned_s: float
    time_simulated_s: float
    steps_planned: int
    closing_steps: int
    steps_completed: int
    foot_position_error_cm_mean: float | None
    foot_position_error_cm_max: float | None
    foot_yaw_error_deg_mean: float | None
    foot_yaw_error_deg_max: float | None
    foot_step_error_cm_mean: float | None
    foot_step_error_cm_max: float | None
    foot_step_yaw_error_deg_mean: float | None
    foot_step_yaw_error_deg_max: float | None
    distance_m: float
    distance_planned_m: float
    distance_planned_reached_m: float
    yaw_change_deg: float
    yaw_change_planned_deg: float
    cop_margin_min_m: float | None
    cop_margin_p05_m: float | None
    cop_outside_share: float | None
    com_error_rms_m: float
    com_error_max_m: float
    ik_error_max_m: float
    generator_tick_us_median: float | None
    ik_tick_us_median: float | None
    controller_tick_us_median: float | None
    mujoco_step_us_median: float | None
    estimator_tick_us_median: float | None
    real_time_factor: float | None
    nb_ticks: int
    torque_saturation_share: float
    mpc_failures: int
    roll_max_deg: float | None
    pitch_max_deg: float | None
    yaw_rate_deg_s: float | None
    yaw_rate_planned_deg_s: float | None
    estimator_com_error_rms_m: float | None
    estimator_com_error_max_m: float | None
    estimator_com_error_support_rms_m: float | None
    estimator_com_velocity_error_rms_m_s: float | None
    estimator_yaw_drift_deg: float | None
    yaw_deviation_deg: float | None = None
    landing_error_3d_cm_mean: float | None = None
    landing_error_3d_cm_max: float | None = None
    landing_height_error_cm_max: float | None = None
    tread_margin_cm_min: float | None = None
    swing_clearance_cm_min: float | None = None
    toe_stubs: int | None = None
    com_height_error_cm_rms: float | None = None
    outcome: str = "walked"
    stop_reason: str = ""
    interrupted: bool = False
    sensor_faults: int = 0
    ik_failures: int = 0
    fallback_ticks: int = 0
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The metrics as a JSON-ready dictionary (the ``metrics.json`` keys)."""
        return asdict(self)

    def __getitem__(self, key: str) -> Any:
        """``metrics["fell"]`` reads ``metrics.fell`` (scripts written against the JSON)."""
        if key not in self.__dataclass_fields__:
            raise KeyError(key)
        return getattr(self, key)

    def with_yaw_deviation(self, deviation: float) -> "WalkMetrics":
        """A copy with ``yaw_deviation_deg`` set [deg]."""
        return replace(self, yaw_deviation_deg=float(deviation))


def landing_check_times(schedule: ContactSchedule) -> np.ndarray:
    """When each landing is measured [s]: the middle of the next single support (the landed
    foot then carries the robot), or 0.5 s after the last landing (at most half the final
    stance)."""
    plan, T = schedule.plan, schedule.step_duration
    middle = 0.5 * (schedule.t_b + schedule.t_e)
    times = [schedule.walk_start + (k + 1) * T + middle for k in range(plan.nb_steps - 1)]
    if plan.nb_steps:
        times.append(schedule.walk_end + min(0.5, 0.5 * plan.timing.final_duration))
    return np.array(times)


def _landing_metrics(log: WalkLog, schedule: ContactSchedule, end: float) -> dict[str, Any]:
    """Landings checked before ``end`` and their errors (world frame and per step)."""
    plan = schedule.plan
    checks = landing_check_times(schedule)
    done = [k for k, t in enumerate(checks) if t <= end + 1e-9 and len(log)]
    position_errors, yaw_errors, step_errors, step_yaw_errors = [], [], [], []
    for k in done:
        i = min(int(np.searchsorted(log.time, checks[k] - 1e-9)), len(log) - 1)
        step, j = plan.steps[k], _SIDES.index(plan.steps[k].side)
        landed, yaw = log.sole_positions[i, j, :2], log.sole_yaws[i, j]
        position_errors.append(float(np.linalg.norm(landed - step.xy)))
        yaw_errors.append(abs(float(wrap_angle(yaw - step.yaw))))
        # the same landing relative to the support foot it was taken from (no drift)
        support = plan.support_foot(k)
        start = int(
            np.searchsorted(
                log.time, schedule.walk_start + k * schedule.step_duration + schedule.t_e - 1e-9
            )
        )
        start = min(start, len(log) - 1)
        s_xy, s_yaw = log.sole_positions[start, 1 - j, :2], log.sole_yaws[start, 1 - j]
        c, s = np.cos(s_yaw), np.sin(s_yaw)
        relative = np.array([[c, s], [-s, c]]) @ (landed - s_xy)
        step_errors.append(float(np.linalg.norm(relative - support.to_local(step.xy))))
        step_yaw_errors.append(abs(float(wrap_angle((yaw - s_yaw) - (step.yaw - support.yaw)))))
    metrics: dict[str, Any] = {"steps_completed": len(done)}
    for name, values, scale in (
        ("foot_position_error_cm", position_errors, 100.0),
        ("foot_yaw_error_deg", yaw_errors, 180.0 / np.pi),
        ("foot_step_error_cm", step_errors, 100.0),
        ("foot_step_yaw_error_deg", step_yaw_errors, 180.0 / np.pi),
    ):
        metrics[f"{name}_mean"] = float(np.mean(values) * scale) if values else None
        metrics[f"{name}_max"] = float(np.max(values) * scale) if values else None
    start_mid = 0.5 * (plan.initial_left.xy + plan.initial_right.xy)
    last = plan.stance(min(len(done), plan.nb_steps))
    final_plan = plan.stance(plan.nb_steps)
    com = log.com[:, :2] if len(log) else np.zeros((1, 2))
    metrics["distance_m"] = float(np.linalg.norm(com[-1] - com[0]))
    metrics["distance_planned_m"] = float(
        np.linalg.norm(0.5 * (final_plan[Side.LEFT].xy + final_plan[Side.RIGHT].xy) - start_mid)
    )
    metrics["distance_planned_reached_m"] = float(
        np.linalg.norm(0.5 * (last[Side.LEFT].xy + last[Side.RIGHT].xy) - start_mid)
    )
    return metrics


def compute_walk_metrics(
    log: WalkLog,
    schedule: ContactSchedule,
    *,
    fall: FallStatus,
    wall_time: float,
    nb_generator_failures: int = 0,
    closing_steps: int = 0,
    state_source: str = "estimator",
    terrain: Terrain | None = None,
    com_height: float | None = None,
) -> WalkMetrics:
    """Metrics of a simulated walk (see :class:`WalkMetrics`).

    Args:
        log: The walk's log.
        schedule: The schedule that was followed.
        fall: Verdict of the fall detector at the end.
        wall_time: Wall time of the control loop [s].
        nb_generator_failures: Ticks whose generator reported a failed solve.
        closing_steps: Footsteps of the plan added after the commanded ones.
        state_source: Where the controller's state came from (``"estimator"`` or
            ``"oracle"``: no estimator metrics).
        terrain: The walk's terrain, for the terrain metrics (None: the floor, none).
        com_height: The CoM height above the ground reference [m] (the terrain metrics').
    """
    end = float(log.time[-1]) if len(log) else 0.0
    metrics: dict[str, Any] = {
        "fell": bool(fall.fell),
        "fall_reason": fall.reason,
        "fall_time_s": float(fall.time) if fall.fell else None,
        "time_planned_s": float(schedule.duration),
        "walking_time_planned_s": float(schedule.walk_end - schedule.walk_start),
        "time_simulated_s": end,
        "steps_planned": schedule.plan.nb_steps,
        "closing_steps": int(closing_steps),
    }
    metrics.update(_landing_metrics(log, schedule, end))
    if terrain is not None and not terrain.is_flat and com_height is not None:
        checks = landing_check_times(schedule)
        metrics.update(terrain_metrics(log, schedule, terrain, checks, com_height, end))
    yaw = np.unwrap(log.base_rpy[:, 2]) if len(log) else np.zeros(1)
    metrics["yaw_change_deg"] = float(np.degrees(yaw[-1] - yaw[0]))
    metrics["yaw_change_planned_deg"] = float(
        np.degrees(planned_yaw_change(schedule, schedule.plan.nb_steps + 1))
    )
    margins = cop_margins(log, schedule)
    valid = margins[np.isfinite(margins)]
    metrics["cop_margin_min_m"] = float(valid.min()) if valid.size else None
    metrics["cop_margin_p05_m"] = float(np.percentile(valid, 5)) if valid.size else None
    metrics["cop_outside_share"] = float(np.mean(valid < 0.0)) if valid.size else None
    com_error = (
        np.linalg.norm(log.com[:, :2] - log.com_reference, axis=1) if len(log) else np.zeros(1)
    )
    metrics["com_error_rms_m"] = float(np.sqrt(np.mean(com_error**2)))
    metrics["com_error_max_m"] = float(com_error.max())
    metrics["ik_error_max_m"] = float(log.ik_error.max()) if len(log) else 0.0
    for key, values in (
        ("generator_tick_us_median", log.generator_tick),
        ("ik_tick_us_median", log.ik_tick),
        ("controller_tick_us_median", log.controller_tick),
        ("mujoco_step_us_median", log.mujoco_step),
    ):
        metrics[key] = float(np.median(values) * 1e6) if len(log) else None
    metrics["estimator_tick_us_median"] = (
        float(np.median(log.estimator_tick) * 1e6)
        if len(log) and state_source == "estimator"
        else None
    )
    metrics["real_time_factor"] = float(end / wall_time) if wall_time > 0.0 else None
    metrics["nb_ticks"] = len(log)
    saturated = np.abs(log.actuator_force) >= 0.99 * log.torque_limit
    metrics["torque_saturation_share"] = float(np.mean(saturated.any(axis=1))) if len(log) else 0.0
    metrics["mpc_failures"] = int(nb_generator_failures)
    metrics.update(attitude_metrics(log, schedule, end))
    metrics.update(EstimatorAccuracy.from_log(log, state_source=state_source).to_dict())
    return WalkMetrics(**metrics)


__all__ = [
    "WalkMetrics",
    "compute_walk_metrics",
    "cop_margins",
    "landing_check_times",
    "measured_support_polygon",
    "sanity_warnings",
    "yaw_deviation_deg",
]


#: Beyond these a walk that did not fall is flagged (:func:`sanity_warnings`).
UNPLANNED_YAW_WARNING_DEG = 15.0
COP_OUTSIDE_WARNING_SHARE = 0.1
FOOT_ERROR_WARNING_CM = 10.0


def sanity_warnings(metrics: WalkMetrics) -> tuple[str, ...]:
    """Why a walk is far from its plan though it did not fall, in words (empty if not)."""
    out = []
    unplanned = metrics.yaw_change_deg - metrics.yaw_change_planned_deg
    if abs(unplanned) > UNPLANNED_YAW_WARNING_DEG:
        out.append(
            f"unplanned yaw of {unplanned:+.1f} deg (beyond {UNPLANNED_YAW_WARNING_DEG:g} deg)"
        )
    share = metrics.cop_outside_share
    if share is not None and share > COP_OUTSIDE_WARNING_SHARE:
        out.append(
            f"the CoP was outside the loaded soles on {100 * share:.0f} % of the ticks (beyond "
            f"{100 * COP_OUTSIDE_WARNING_SHARE:.0f} %)"
        )
    error = metrics.foot_position_error_cm_max
    if error is not None and error > FOOT_ERROR_WARNING_CM:
        out.append(f"landings up to {error:.1f} cm off their footsteps")
    return tuple(out)
