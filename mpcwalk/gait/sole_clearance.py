"""How far a swing sole stays above the terrain: its clearance and its toe stubs.

A swing sole is checked at its toe, its heel, its corners and points along its edges and
its centre line (:func:`sole_points`: a 5 x 3 grid over the sole). At each instant of a
swing, a point's *gap* is its height above the terrain under it
(:meth:`~mpcwalk.terrain.Terrain.height`). Points over the footprint the sole lifted off
from or the one it lands on (the first lift off and the last approach) are exempt: the
sole rests there at both ends of the swing. The swing's *clearance* is the smallest gap of
the other points over the swing (:func:`sole_clearance` at one instant,
:func:`measure_swing_clearance` over a walk's swings); a *toe stub* is an instant where one
of them is below the terrain's surface (a gap below zero).
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.footsteps.footstep import Footstep, wrap_angle
from mpcwalk.terrain import Terrain

#: The sole's checked points as shares of its half length and half width.
_ALONG = np.array([-1.0, -0.5, 0.0, 0.5, 1.0])
_ACROSS = np.array([-1.0, 0.0, 1.0])
_GRID = np.array([(u, v) for u in _ALONG for v in _ACROSS])
#: Tolerance [m] of a point on a footprint's edge, and of a stub.
TOLERANCE = 1e-9


def foot_tilt(foot) -> tuple[float, float]:
    """Roll and pitch [rad] of a footstep or foot state (0 for a flat one)."""
    return float(getattr(foot, "roll", 0.0)), float(getattr(foot, "pitch", 0.0))


def sole_points(
    position,
    yaw: float,
    length: float,
    width: float,
    roll: float = 0.0,
    pitch: float = 0.0,
    grid: np.ndarray = _GRID,
) -> np.ndarray:
    """Toe, heel, corners, edge and centre-line points of a sole ``length`` x ``width``
    [m] centred at ``position`` (3,) [m], turned ``Rz(yaw) Ry(pitch) Rx(roll)``: shape
    (15, 3) [m] (or one point per row of ``grid``: shares (n, 2) of the half length and the
    half width)."""
    local = np.zeros((len(grid), 3))
    local[:, 0] = 0.5 * length * grid[:, 0]
    local[:, 1] = 0.5 * width * grid[:, 1]
    cy, sy = math.cos(yaw), math.sin(yaw)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cr, sr = math.cos(roll), math.sin(roll)
    rotation = (
        np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
        @ np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
        @ np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    )
    return np.asarray(position, dtype=float)[:3] + local @ rotation.T


def in_footprint(points, foot: Footstep, length: float, width: float) -> np.ndarray:
    """Whether points (n, 2+) lie over the footprint of a sole ``length`` x ``width`` [m]
    resting on ``foot`` (its horizontal rectangle), shape (n,)."""
    xy = np.asarray(points, dtype=float)[..., :2] - foot.xy
    c, s = math.cos(foot.yaw), math.sin(foot.yaw)
    along = xy[..., 0] * c + xy[..., 1] * s
    across = -xy[..., 0] * s + xy[..., 1] * c
    return (np.abs(along) <= 0.5 * length + TOLERANCE) & (np.abs(across) <= 0.5 * width + TOLERANCE)


def sole_gaps(
    terrain: Terrain, points, lift: Footstep, landing: Footstep, length: float, width: float
) -> tuple[np.ndarray, np.ndarray]:
    """Heights [m] of points (..., 3) above the terrain under them, and whether each is
    exempt (over the lift-off or the landing footprint)."""
    points = np.asarray(points, dtype=float)
    gaps = points[..., 2] - np.asarray(terrain.height(points[..., 0], points[..., 1]))
    exempt = in_footprint(points, lift, length, width) | in_footprint(
        points, landing, length, width
    )
    return gaps, exempt


def sole_clearance(
    terrain: Terrain, foot, lift: Footstep, landing: Footstep, length: float, width: float
) -> float:
    """Clearance [m] of a swing sole at one instant: the smallest gap of its checked points
    that are over neither the lift-off nor the landing footprint (inf when all are).

    Args:
        terrain: The ground.
        foot: The sole's pose: anything with ``position`` (3,) [m] and ``yaw`` [rad] (a
            :class:`~mpcwalk.gait.swing_foot.FootState`, a :class:`Footstep`), tilted by
            its ``roll`` and ``pitch`` [rad] when it has them.
        lift: The footstep the sole lifted off from.
        landing: The footstep it lands on.
        length: Sole length [m].
        width: Sole width [m].
    """
    points = sole_points(foot.position, float(foot.yaw), length, width, *foot_tilt(foot))
    gaps, exempt = sole_gaps(terrain, points, lift, landing, length, width)
    checked = gaps[~exempt]
    return float(checked.min()) if checked.size else math.inf


@dataclass(frozen=True)
class ClearanceReport:
    """The clearance of a walk's swings over a terrain.

    Attributes:
        min_clearance: Smallest clearance [m] over every sampled instant of every swing
            (inf when no checked point ever left the footprints).
        toe_stubs: Sampled instants where a checked point is below the terrain's surface.
        worst_step: Step of the smallest clearance (-1 without a swing).
        worst_time: Time [s] of the smallest clearance (nan without a swing).
        samples: Instants sampled.
        per_step: Smallest clearance [m] of each step's swing.
    """

    min_clearance: float
    toe_stubs: int
    worst_step: int
    worst_time: float
    samples: int
    per_step: tuple[float, ...] = ()


def measure_swing_clearance(trajectory, terrain: Terrain, dt: float = 0.002) -> ClearanceReport:
    """Clearance and toe stubs of every swing of ``trajectory`` (a
    :class:`~mpcwalk.gait.swing_foot.SwingFootTrajectory`) over ``terrain``, sampled every
    ``dt`` [s] of each single support, with the sole of its schedule's ``foot``."""
    schedule = trajectory.schedule
    length, width = schedule.foot.length, schedule.foot.width
    plan = schedule.plan
    best, stubs, samples, per_step = (math.inf, -1, math.nan), 0, 0, []
    for k, landing in enumerate(plan.steps):
        lift = plan.stance(k)[landing.side]
        start = schedule.walk_start + k * schedule.step_duration
        step_min = math.inf
        for t in np.arange(start + schedule.t_b, start + schedule.t_e, dt):
            foot = trajectory.foot_poses(float(t))[landing.side]
            if foot.in_contact:
                continue
            samples += 1
            clearance = sole_clearance(terrain, foot, lift, landing, length, width)
            stubs += clearance < -TOLERANCE
            step_min = min(step_min, clearance)
            if clearance < best[0]:
                best = (clearance, k, float(t))
        per_step.append(step_min)
    return ClearanceReport(best[0], stubs, best[1], best[2], samples, tuple(per_step))


def swing_pose(
    lift: Footstep, landing: Footstep, h: float
) -> tuple[np.ndarray, float, float, float]:
    """Horizontal position (2,) [m], yaw, roll and pitch [rad] of a swing a share ``h`` of
    its way (each interpolated as :class:`~mpcwalk.gait.swing_foot.SwingFootTrajectory`
    does)."""
    delta_yaw = float(wrap_angle(landing.yaw - lift.yaw))
    (lift_roll, lift_pitch), (land_roll, land_pitch) = foot_tilt(lift), foot_tilt(landing)
    return (
        lift.xy + h * (landing.xy - lift.xy),
        lift.yaw + h * delta_yaw,
        lift_roll + h * (land_roll - lift_roll),
        lift_pitch + h * (land_pitch - lift_pitch),
    )


__all__ = [
    "TOLERANCE",
    "ClearanceReport",
    "foot_tilt",
    "in_footprint",
    "measure_swing_clearance",
    "sole_clearance",
    "sole_gaps",
    "sole_points",
    "swing_pose",
]
