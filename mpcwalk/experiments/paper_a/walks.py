"""Paper A's walks: one controller of the comparison on one ``.mdat`` path, and what is
measured of it.

Every controller walks the same robot (``atlas-like``) on the same path files with paper A's
state machine re-aiming each step from the measured support foot
(:class:`~mpcwalk.control.stabilizers.footstep_reaiming.FootstepReaiming`); they differ in the
pattern generator, the stabilizer and the timing (:class:`TimedController`; the comparison's
are in the ``config.toml`` beside this module).
"""

from dataclasses import dataclass

import numpy as np

from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.terrain import read_terrain
from mpcwalk.walking.metrics import landing_check_times
from mpcwalk.walking.result import WalkResult
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import ControllerSpec, WalkSpec


@dataclass(frozen=True)
class TimedController:
    """One controller of the comparison at its timing (a
    :class:`~mpcwalk.walking.specification.ControllerSpec` is made of it: :meth:`controller`).

    Attributes:
        label: Name in the table.
        generator: Pattern generator name.
        step_duration: Step duration T [s].
        double_support_ratio: r_ds.
        ankle_imu: Add paper A's ankle strategy and IMU correction.
        reaim: Re-aim each step from the measured support foot (paper A's state machine).
        feedback: Close the generator's loop on the measured CoM (observer and DCM feedback).
        generator_options: Keyword arguments of the generator, as ``(name, value)`` pairs.
        swing_profile: Swing-foot profile: ``"ctraj"`` for paper A's gait (quintic Cartesian
            lift and lower), ``"cosine"`` (paper M) otherwise.
    """

    label: str
    generator: str
    step_duration: float
    double_support_ratio: float = 0.2
    ankle_imu: bool = False
    reaim: bool = True
    feedback: bool = True
    generator_options: tuple[tuple[str, float], ...] = ()
    swing_profile: str = "cosine"

    def controller(self) -> ControllerSpec:
        """The walk's controller: the generator, its options, the feedback, the re-aiming
        state machine and, for paper A's gait, the ankle strategy with the IMU correction."""
        stabilizers: tuple[str, ...] = ("reaim",) if self.reaim else ()
        stabilizers += ("ankle-imu",) if self.ankle_imu else ()
        return ControllerSpec(
            generator=self.generator,
            generator_options=dict(self.generator_options),
            feedback=self.feedback,
            stabilizers=stabilizers,
            swing_profile=self.swing_profile,
        )


def walk_path(
    spec: "TimedController",
    path,
    *,
    nb_steps: int | None = None,
    robot: str = "atlas-like",
    terrain=None,
) -> WalkResult:
    """Walk one path file with one controller (no progress bar), on ``terrain`` (a terrain
    file; None: the floor)."""
    walk = WalkSpec.build(
        robot,
        controller=spec.controller(),
        path=str(path),
        nb_steps=nb_steps,
        step_duration=spec.step_duration,
        double_support_ratio=spec.double_support_ratio,
        terrain=None if terrain is None else read_terrain(terrain),
    )
    return run_walk(walk)


def placement_errors(result: WalkResult) -> tuple[np.ndarray, np.ndarray]:
    """Per landed step: position error [cm] and yaw error [deg] of the landed sole against
    the planned (file) pose, measured in the next single support (as the walk metrics); the
    position in 3D on a terrain, else on the ground plane."""
    schedule, log = result.schedule, result.log
    positions, yaws = [], []
    if not len(log):
        return np.zeros(0), np.zeros(0)
    axes = 3 if result.spec.world.terrain is not None else 2
    for k, t in enumerate(landing_check_times(schedule)):
        if t > log.time[-1] + 1e-9:
            break
        i = min(int(np.searchsorted(log.time, t - 1e-9)), len(log) - 1)
        step = schedule.plan.steps[k]
        j = 0 if step.side is Side.LEFT else 1
        error = log.sole_positions[i, j, :axes] - step.position[:axes]
        positions.append(100.0 * float(np.linalg.norm(error)))
        yaws.append(np.degrees(abs(float(wrap_angle(log.sole_yaws[i, j] - step.yaw)))))
    return np.array(positions), np.array(yaws)


def table_row(spec: TimedController, experiment: str, result: WalkResult) -> dict:
    """One row of the comparison table (JSON-ready)."""
    from mpcwalk.gait.support_margins import support_margins

    m, log = result.metrics, result.log
    # on a terrain, the landings' 3D errors (heights count)
    in_3d = m.landing_error_3d_cm_mean is not None
    com_margin = (
        support_margins(result.schedule, log.time, log.com[:, :2]) if len(log) else np.zeros(1)
    )
    return {
        "controller": spec.label,
        "experiment": experiment,
        "generator": spec.generator,
        "fell": m.fell,
        "fall_time_s": m.fall_time_s,
        "step_duration_s": spec.step_duration,
        "double_support_ratio": spec.double_support_ratio,
        "steps": f"{m.steps_completed}/{m.steps_planned}",
        "total_time_s": m.time_simulated_s,
        "position_error_mean_cm": (
            m.landing_error_3d_cm_mean if in_3d else m.foot_position_error_cm_mean
        ),
        "position_error_max_cm": (
            m.landing_error_3d_cm_max if in_3d else m.foot_position_error_cm_max
        ),
        "yaw_error_mean_deg": m.foot_yaw_error_deg_mean,
        "yaw_error_max_deg": m.foot_yaw_error_deg_max,
        "cop_margin_min_cm": None if m.cop_margin_min_m is None else 100.0 * m.cop_margin_min_m,
        "com_margin_min_cm": 100.0 * float(np.min(com_margin)),
        "generator_tick_us": m.generator_tick_us_median,
        "controller_tick_us": m.controller_tick_us_median,
    }


__all__ = ["TimedController", "placement_errors", "table_row", "walk_path"]
