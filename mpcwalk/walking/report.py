"""What a simulated walk leaves behind: the per-tick log, its metrics and its figures.

Metrics of :func:`compute_walk_metrics` (units in the key names):

- ``fell``, ``fall_reason``, ``time_simulated_s``, ``steps_planned``, ``steps_completed``
  (steps whose landing was checked before the end of the run);
- ``distance_m`` (measured CoM, start to end) beside ``distance_planned_m`` (midpoints of the
  first and last stance), ``yaw_change_deg`` (IMU yaw) beside ``yaw_change_planned_deg``;
- ``foot_position_error_cm_*`` and ``foot_yaw_error_deg_*``: each landed sole against its
  footstep, world frame, measured in the middle of the next single support, when the landed
  foot carries the robot (as paper A's Fig. 8), or 0.5 s after the last landing; the world
  error includes the drift of all earlier landings, ``foot_step_error_cm_*`` and
  ``foot_step_yaw_error_deg_*`` do not (the landing relative to the measured support foot at
  the end of its swing, against the plan);
- ``zmp_margin_min_m``: smallest signed distance of the measured CoP to the support polygon
  of the feet the schedule puts on the ground, at their measured poses (positive inside),
  with its 5th percentile and the share of ticks outside;
- ``com_error_*_m``: measured CoM against the generator's reference, world frame;
- ``generator_tick_us_median``, ``ik_tick_us_median``, ``mujoco_step_us_median``,
  ``controller_tick_us_median`` and ``real_time_factor`` (simulated time over the loop's wall
  time, one process);
- ``torque_saturation_share`` (ticks with a servo at its torque limit), ``mpc_failures``
  (ticks whose generator reported a failed solve);
- ``yaw_rate_deg_s``: mean yaw rate of the IMU over the walking phases (single and double
  supports) with the start-up and the stop excluded, i.e. from the end of the first step to
  the end of the one before the last (the closing step of a velocity command), or to the
  fall, beside ``yaw_rate_planned_deg_s``, the rate of the footsteps' heading over the same
  steps;
- ``roll_max_deg``, ``pitch_max_deg``: largest IMU roll and pitch away from their values at
  the start;
- ``yaw_deviation_deg`` (:func:`yaw_deviation_deg`): after the last push, the largest
  difference of IMU yaw with the same walk without the pushes (None without a reference).
"""

import itertools
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from mpcwalk._checks import frozen_array
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.models.support_polygon import SupportPolygon, foot_rectangle

_SIDES = (Side.LEFT, Side.RIGHT)


@dataclass(frozen=True)
class WalkLog:
    """Per-tick log of a simulated walk (n ticks, world frame, SI units).

    Attributes:
        time: End of each tick [s], shape (n,).
        com: Measured CoM [m], (n, 3). com_velocity: [m/s], (n, 3).
        com_reference: Generator CoM [m], (n, 2). zmp_reference: Generator ZMP [m], (n, 2).
        zmp_command: Desired ZMP with the DCM feedback [m], (n, 2).
        com_target: IK CoM target [m], (n, 3). dcm_error: [m], (n, 2).
        cop: Measured CoP (paper M eq. 31) [m], (n, 3), NaN without contact.
        contact: Measured contact of the left and right soles, (n, 2) bool.
        sole_positions: Measured soles [m], (n, 2, 3). sole_yaws: [rad], (n, 2).
        feet_reference: Sole references of the gait [m], (n, 2, 3).
        base_rpy: IMU roll, pitch, yaw [rad], (n, 3).
        joint_positions: Measured joints [rad], (n, nj). joint_targets: Servo targets, (n, nj).
        actuator_force: Servo torques [N m], (n, nu).
        ik_error: Largest CoM/sole position error of the IK [m], (n,).
        generator_failed: Generator reported a failed solve, (n,) bool.
        generator_tick, ik_tick, controller_tick, mujoco_step: Wall times [s], (n,).
        joint_names: Joint names (``robot.joint_names``).
        torque_limit: Torque limit of each actuator [N m] (inf: none), (nu,).
    """

    time: np.ndarray
    com: np.ndarray
    com_velocity: np.ndarray
    com_reference: np.ndarray
    zmp_reference: np.ndarray
    zmp_command: np.ndarray
    com_target: np.ndarray
    dcm_error: np.ndarray
    cop: np.ndarray
    contact: np.ndarray
    sole_positions: np.ndarray
    sole_yaws: np.ndarray
    feet_reference: np.ndarray
    base_rpy: np.ndarray
    joint_positions: np.ndarray
    joint_targets: np.ndarray
    actuator_force: np.ndarray
    ik_error: np.ndarray
    generator_failed: np.ndarray
    generator_tick: np.ndarray
    ik_tick: np.ndarray
    controller_tick: np.ndarray
    mujoco_step: np.ndarray
    joint_names: tuple
    torque_limit: np.ndarray

    @staticmethod
    def recorder(robot, schedule: ContactSchedule) -> "WalkLogRecorder":
        """An empty recorder for a walk of ``robot``."""
        return WalkLogRecorder(robot)

    def __len__(self) -> int:
        return len(self.time)

    def save(self, path: str | Path) -> Path:
        """Write the log as ``.npz`` (every field) or ``.csv`` (the scalar and planar series,
        one row per tick, with a header). Returns the path."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".csv":
            columns = self.csv_columns()
            data = np.column_stack(list(columns.values()))
            np.savetxt(path, data, delimiter=",", header=",".join(columns), comments="", fmt="%.6g")
            return path
        if path.suffix != ".npz":
            from mpcwalk.exceptions import ConfigurationError

            raise ConfigurationError(
                f"A walk log is written as .npz or .csv, got '{path.name}'; use e.g. walk_log.npz."
            )
        np.savez_compressed(
            path, **{f.name: np.asarray(getattr(self, f.name)) for f in fields(self)}
        )
        return path

    def csv_columns(self) -> dict[str, np.ndarray]:
        """Named columns of the CSV form of the log."""
        columns = {"time": self.time}
        for name, axes in (
            ("com", "xyz"),
            ("com_velocity", "xyz"),
            ("com_reference", "xy"),
            ("zmp_reference", "xy"),
            ("zmp_command", "xy"),
            ("cop", "xy"),
            ("dcm_error", "xy"),
            ("base_rpy", ("roll", "pitch", "yaw")),
        ):
            values = getattr(self, name)
            for i, axis in enumerate(axes):
                columns[f"{name}_{axis}"] = values[:, i]
        for j, side in enumerate(("left", "right")):
            columns[f"{side}_contact"] = self.contact[:, j].astype(float)
            for i, axis in enumerate("xyz"):
                columns[f"{side}_sole_{axis}"] = self.sole_positions[:, j, i]
            columns[f"{side}_sole_yaw"] = self.sole_yaws[:, j]
        for name in ("ik_error", "generator_tick", "ik_tick", "controller_tick", "mujoco_step"):
            columns[name] = getattr(self, name)
        columns["generator_failed"] = self.generator_failed.astype(float)
        return columns


class WalkLogRecorder:
    """Accumulates the ticks of a walk, then :meth:`freeze` makes the :class:`WalkLog`."""

    def __init__(self, robot) -> None:
        self.robot = robot
        self.rows: dict[str, list] = {
            f.name: [] for f in fields(WalkLog) if f.name not in ("joint_names", "torque_limit")
        }

    def append(
        self, output, state, actuator_force, mujoco_step: float, controller_tick: float
    ) -> None:
        """Record one tick: controller output, simulation state after the tick, wall times."""
        rows, m = self.rows, state.measurements
        rows["time"].append(state.time)
        rows["com"].append(m.com)
        rows["com_velocity"].append(m.com_velocity)
        rows["com_reference"].append(output.generator.com)
        rows["zmp_reference"].append(output.generator.zmp)
        rows["zmp_command"].append(output.zmp_command)
        rows["com_target"].append(output.com_target)
        rows["dcm_error"].append(output.dcm_error)
        rows["cop"].append(m.cop)
        rows["contact"].append((m.left_foot.in_contact, m.right_foot.in_contact))
        rows["sole_positions"].append(state.sole_positions)
        rows["sole_yaws"].append(state.sole_yaws)
        rows["feet_reference"].append((output.feet.left.position, output.feet.right.position))
        rows["base_rpy"].append((m.imu.roll, m.imu.pitch, m.imu.yaw))
        rows["joint_positions"].append(m.joint_positions)
        rows["joint_targets"].append(output.joint_targets)
        rows["actuator_force"].append(np.array(actuator_force))
        rows["ik_error"].append(output.ik.task_errors.position_max)
        rows["generator_failed"].append(output.generator_failed)
        rows["generator_tick"].append(output.generator_tick)
        rows["ik_tick"].append(output.ik_tick)
        rows["controller_tick"].append(controller_tick)
        rows["mujoco_step"].append(mujoco_step)

    def freeze(self) -> WalkLog:
        """The log so far."""
        model = self.robot.mj_model
        limit = np.where(
            model.actuator_forcelimited.astype(bool),
            np.abs(model.actuator_forcerange).max(axis=1),
            np.inf,
        )
        nj, nu = len(self.robot.joint_names), model.nu
        empty = {
            "com": (0, 3),
            "com_velocity": (0, 3),
            "com_reference": (0, 2),
            "zmp_reference": (0, 2),
            "zmp_command": (0, 2),
            "com_target": (0, 3),
            "dcm_error": (0, 2),
            "cop": (0, 3),
            "contact": (0, 2),
            "sole_positions": (0, 2, 3),
            "sole_yaws": (0, 2),
            "feet_reference": (0, 2, 3),
            "base_rpy": (0, 3),
            "joint_positions": (0, nj),
            "joint_targets": (0, nj),
            "actuator_force": (0, nu),
        }
        arrays = {}
        for name, values in self.rows.items():
            dtype = bool if name in ("contact", "generator_failed") else float
            arrays[name] = frozen_array(
                values if values else np.zeros(empty.get(name, (0,))), dtype=dtype
            )
        return WalkLog(
            **arrays, joint_names=tuple(self.robot.joint_names), torque_limit=frozen_array(limit)
        )


def measured_support_polygon(
    schedule: ContactSchedule, t: float, sole_positions: np.ndarray, sole_yaws: np.ndarray
) -> SupportPolygon:
    """Support polygon of the feet the schedule puts on the ground at ``t``, at their
    measured poses (soles of the schedule's size)."""
    feet = schedule.phase(t).feet
    rectangles = [
        foot_rectangle(
            sole_positions[i][:2], float(sole_yaws[i]), schedule.foot.length, schedule.foot.width
        )
        for i, side in enumerate(_SIDES)
        if side in feet
    ]
    return rectangles[0] if len(rectangles) == 1 else SupportPolygon.union_hull(rectangles)


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


def _planned_yaw_change(schedule: ContactSchedule, nb_stances: int) -> float:
    yaws, total = [], 0.0
    for stance in schedule.plan.stances()[:nb_stances]:
        left, right = stance[Side.LEFT].yaw, stance[Side.RIGHT].yaw
        yaws.append(left + 0.5 * float(wrap_angle(right - left)))
    for a, b in itertools.pairwise(yaws):
        total += float(wrap_angle(b - a))
    return total


def compute_walk_metrics(
    log: WalkLog,
    schedule: ContactSchedule,
    robot,
    *,
    fall,
    wall_time: float,
    nb_generator_failures: int = 0,
) -> dict[str, Any]:
    """Metrics of a simulated walk (see the module docstring); JSON-ready."""
    plan = schedule.plan
    end = float(log.time[-1]) if len(log) else 0.0
    metrics: dict[str, Any] = {
        "fell": bool(fall.fell),
        "fall_reason": fall.reason,
        "fall_time_s": float(fall.time) if fall.fell else None,
        "time_simulated_s": end,
        "steps_planned": plan.nb_steps,
    }
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
    metrics["steps_completed"] = len(done)
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
    yaw = np.unwrap(log.base_rpy[:, 2]) if len(log) else np.zeros(1)
    metrics["yaw_change_deg"] = float(np.degrees(yaw[-1] - yaw[0]))
    metrics["yaw_change_planned_deg"] = float(
        np.degrees(_planned_yaw_change(schedule, plan.nb_steps + 1))
    )
    margins = cop_margins(log, schedule)
    valid = margins[np.isfinite(margins)]
    metrics["zmp_margin_min_m"] = float(valid.min()) if valid.size else None
    metrics["zmp_margin_p05_m"] = float(np.percentile(valid, 5)) if valid.size else None
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
    metrics["real_time_factor"] = float(end / wall_time) if wall_time > 0.0 else None
    metrics["nb_ticks"] = len(log)
    saturated = np.abs(log.actuator_force) >= 0.99 * log.torque_limit
    metrics["torque_saturation_share"] = float(np.mean(saturated.any(axis=1))) if len(log) else 0.0
    metrics["mpc_failures"] = int(nb_generator_failures)
    metrics.update(_attitude_metrics(log, schedule, end))
    metrics["yaw_deviation_deg"] = None
    return metrics


def _attitude_metrics(log: WalkLog, schedule: ContactSchedule, end: float) -> dict[str, Any]:
    """Yaw rate over the walking phases (start-up excluded), roll/pitch excursions."""
    if not len(log):
        return {
            "yaw_rate_deg_s": None,
            "yaw_rate_planned_deg_s": None,
            "roll_max_deg": None,
            "pitch_max_deg": None,
        }
    rpy = np.unwrap(log.base_rpy, axis=0)
    excursion = np.degrees(np.abs(rpy - rpy[0]).max(axis=0))
    metrics = {
        "roll_max_deg": float(excursion[0]),
        "pitch_max_deg": float(excursion[1]),
        "yaw_rate_deg_s": None,
        "yaw_rate_planned_deg_s": None,
    }
    start = schedule.walk_start + schedule.step_duration
    stop = min(schedule.walk_end - schedule.step_duration, end)
    nb_steps = int(np.floor((stop - schedule.walk_start) / schedule.step_duration + 1e-9))
    stop = schedule.walk_start + nb_steps * schedule.step_duration
    if stop - start < schedule.step_duration - 1e-9:
        return metrics
    yaw_start, yaw_stop = np.interp([start, stop], log.time, rpy[:, 2])
    metrics["yaw_rate_deg_s"] = float(np.degrees(yaw_stop - yaw_start) / (stop - start))
    planned = _planned_yaw_change(schedule, nb_steps + 1) - _planned_yaw_change(schedule, 2)
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


def cop_margins(log: WalkLog, schedule: ContactSchedule) -> np.ndarray:
    """Signed distance [m] of the measured CoP to the measured support polygon, per tick
    (NaN without contact)."""
    margins = np.full(len(log), np.nan)
    for i in np.flatnonzero(np.isfinite(log.cop[:, 0])):
        polygon = measured_support_polygon(
            schedule, log.time[i], log.sole_positions[i], log.sole_yaws[i]
        )
        margins[i] = float(polygon.signed_distance(log.cop[i : i + 1, :2])[0])
    return margins


def _label_as_measured(ax) -> None:
    """The planning plots draw a planned ZMP and CoM; here they are the measured CoP and CoM."""
    for line in ax.get_lines():
        if line.get_label() == "ZMP":
            line.set_label("CoP (measured)")
            line.set_color("tab:red")
            line.set_linewidth(0.6)
        elif line.get_label() == "CoM":
            line.set_label("CoM (measured)")


def plot_walk_top_view(schedule: ContactSchedule, log: WalkLog, *, title: str = ""):
    """Planned footsteps, landed soles, measured CoM and CoP seen from above (paper M
    Fig. 1a, paper A Fig. 5)."""
    from matplotlib.patches import Polygon

    from mpcwalk.walking.plan_figures import place_legend_below, plot_top_view

    fig = plot_top_view(schedule, log.time, log.com[:, :2], log.cop[:, :2], title=title)
    ax = fig.axes[0]
    _label_as_measured(ax)
    ax.plot(
        log.com_reference[:, 0],
        log.com_reference[:, 1],
        "--",
        color="0.5",
        lw=1.0,
        label="CoM reference",
    )
    checks = landing_check_times(schedule)
    for k, t in enumerate(checks):
        if t > log.time[-1] + 1e-9:
            break
        i = min(int(np.searchsorted(log.time, t - 1e-9)), len(log) - 1)
        j = _SIDES.index(schedule.plan.steps[k].side)
        rect = foot_rectangle(
            log.sole_positions[i, j, :2],
            float(log.sole_yaws[i, j]),
            schedule.foot.length,
            schedule.foot.width,
        )
        ax.add_patch(
            Polygon(
                rect.vertices,
                closed=True,
                fill=True,
                alpha=0.15,
                color="tab:blue" if j == 0 else "tab:red",
                lw=0,
                label="landed soles" if k == 0 else None,
            )
        )
    place_legend_below(ax)
    return fig


def plot_walk_over_time(schedule: ContactSchedule, log: WalkLog, *, title: str = ""):
    """CoM (measured and reference), ZMP reference and measured CoP over time, per axis."""
    from mpcwalk.walking.plan_figures import plot_com_zmp

    fig = plot_com_zmp(
        schedule,
        log.time,
        log.com[:, :2],
        log.cop[:, :2],
        zmp_reference=log.zmp_reference,
        title=title,
    )
    for axis, ax in enumerate(fig.axes):
        _label_as_measured(ax)
        ax.plot(
            log.time, log.com_reference[:, axis], "--", color="0.4", lw=1.0, label="CoM reference"
        )
    fig.axes[0].legend(loc="best", fontsize=8)
    return fig
