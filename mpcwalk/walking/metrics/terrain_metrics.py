"""How a walk went over its terrain: landings in 3D, tread margins, swing clearance, toe
stubs and the CoM's height, from the log (the simulator's ground truth) after the walk.

- **landing error 3D**: distance [cm] from the measured sole centre to its footstep's
  position (x, y, z), at each landing's check time (:func:`landing_check_times`);
- **tread margin**: smallest distance [cm] of the measured sole's corners to the edges of
  the top it rests on (:meth:`~mpcwalk.terrain.Terrain.sole_support`), over the landings;
  two tops meeting without a step at a kink a sole may straddle
  (:data:`~mpcwalk.terrain.MAX_STRADDLED_KINK_DEG`: a ramp's foot and brow) count as one, as
  for the planner;
- **swing clearance**: smallest height [cm] of a swinging sole's corners above the terrain
  under them, over the middle of each swing (the first and last :data:`APPROACH_SHARE` of a
  swing lift off and set down on their own tops, where the clearance is zero by design);
- **toe stubs**: swings in whose middle a sole corner went :data:`STUB_DEPTH` or more
  below the terrain's surface under it (a toe or a heel hit a nose or a riser);
- **CoM height error**: RMS [cm] of the measured CoM height minus the height profile's
  (:class:`~mpcwalk.gait.height_profile.HeightProfile`).

Sole corners are taken with the sole's yaw and flat (the log holds the soles' centres and
yaws): a swinging sole's roll and pitch are small.
"""

import math
from typing import Any

import numpy as np

from mpcwalk.footsteps.footstep import Side
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.height_profile import height_profile
from mpcwalk.terrain import MAX_STRADDLED_KINK_DEG, Terrain
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics.cop_margins import sole_corners

#: Share of a swing at each end left out of the clearance: lift-off and touch-down.
APPROACH_SHARE = 0.15
#: Depth [m] below the terrain's surface from which a sole corner counts as a stub.
STUB_DEPTH = 0.005
_MAX_KINK = math.radians(MAX_STRADDLED_KINK_DEG)

_SIDES = (Side.LEFT, Side.RIGHT)


def terrain_metrics(
    log: WalkLog,
    schedule: ContactSchedule,
    terrain: Terrain,
    check_times: np.ndarray,
    com_height: float,
    end: float,
) -> dict[str, Any]:
    """The terrain metrics of a walk (see the module's documentation); None where a metric
    cannot be measured (no landing checked, no swing)."""
    length, width = schedule.foot.length, schedule.foot.width
    plan = schedule.plan
    out: dict[str, Any] = {}
    errors, height_errors, margins = [], [], []
    for k, t in enumerate(check_times):
        if t > end + 1e-9 or not len(log):
            break
        i = min(int(np.searchsorted(log.time, t - 1e-9)), len(log) - 1)
        step, j = plan.steps[k], _SIDES.index(plan.steps[k].side)
        landed = log.sole_positions[i, j]
        errors.append(float(np.linalg.norm(landed - step.position)))
        height_errors.append(abs(float(landed[2] - step.position[2])))
        support = terrain.sole_support(
            landed[:2], float(log.sole_yaws[i, j]), length, width, max_kink=_MAX_KINK
        )
        margins.append(support.margin)
    out["landing_error_3d_cm_mean"] = float(np.mean(errors) * 100) if errors else None
    out["landing_error_3d_cm_max"] = float(np.max(errors) * 100) if errors else None
    out["landing_height_error_cm_max"] = float(np.max(height_errors) * 100) if errors else None
    out["tread_margin_cm_min"] = float(np.min(margins) * 100) if margins else None
    clearance, stubs = _swings(log, schedule, terrain, end)
    out["swing_clearance_cm_min"] = None if clearance is None else clearance * 100
    out["toe_stubs"] = stubs
    if len(log):
        z_ref = height_profile(schedule, com_height).com(log.time)[0]
        error = log.com[:, 2] - z_ref
        out["com_height_error_cm_rms"] = float(np.sqrt(np.mean(error**2)) * 100)
    else:
        out["com_height_error_cm_rms"] = None
    return out


def _swings(
    log: WalkLog, schedule: ContactSchedule, terrain: Terrain, end: float
) -> tuple[float | None, int]:
    """Smallest clearance [m] of the swinging soles' corners over the middle of the swings,
    and the number of swings with a stub."""
    if not len(log):
        return None, 0
    length, width = schedule.foot.length, schedule.foot.width
    lowest, stubs = np.inf, 0
    for phase in schedule.phases:
        if not phase.single_support or phase.start > end:
            continue
        swing = phase.support_side.other if phase.support_side is not None else None
        if swing is None:
            continue
        margin = APPROACH_SHARE * phase.duration
        ticks = np.flatnonzero(
            (log.time >= phase.start + margin) & (log.time <= min(phase.end - margin, end))
        )
        if not len(ticks):
            continue
        j = _SIDES.index(swing)
        corners = sole_corners(log.sole_positions[ticks, j], log.sole_yaws[ticks, j], length, width)
        ground = terrain.height(corners[..., 0], corners[..., 1])
        heights = log.sole_positions[ticks, j, 2, None] - ground
        lowest = min(lowest, float(heights.min()))
        stubs += int(heights.min() < -STUB_DEPTH)
    return (None if not np.isfinite(lowest) else lowest), stubs


__all__ = ["APPROACH_SHARE", "STUB_DEPTH", "terrain_metrics"]
