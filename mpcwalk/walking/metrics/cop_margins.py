"""The CoP's margin in the measured support polygon, for every tick of a walk at once.

The support polygon of a tick is the hull of the soles the schedule puts on the ground, at
their measured poses; the margin is the CoP's signed distance to it (positive inside). The
metrics compute it after the walk from the log, vectorised over the ticks.
"""

import numpy as np

from mpcwalk.footsteps.footstep import Side
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.models.support_polygon import SupportPolygon, foot_rectangle
from mpcwalk.walking.log import WalkLog

_SIDES = (Side.LEFT, Side.RIGHT)


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


def cop_margins(log: WalkLog, schedule: ContactSchedule) -> np.ndarray:
    """Signed distance [m] of the measured CoP to the measured support polygon, per tick
    (NaN without contact): :func:`measured_support_polygon` at each tick, computed for all
    ticks at once from the log (:func:`signed_distances_to_hulls`)."""
    margins = np.full(len(log), np.nan)
    ticks = np.flatnonzero(np.isfinite(log.cop[:, 0]))
    if not len(ticks):
        return margins
    on_ground = np.array([[side in phase.feet for side in _SIDES] for phase in schedule.phases])
    contact = on_ground[schedule.phase_index(log.time[ticks])]  # (n, 2) left, right
    corners = _sole_corners(
        log.sole_positions[ticks, :, :2],
        log.sole_yaws[ticks],
        schedule.foot.length,
        schedule.foot.width,
    )  # (n, 2, 4, 2)
    # one foot on the ground: its rectangle twice (a hull of the same four corners)
    first = np.where(contact[:, 0], 0, 1)
    second = np.where(contact[:, 1], 1, 0)
    rows = np.arange(len(ticks))
    points = np.concatenate([corners[rows, first], corners[rows, second]], axis=1)
    margins[ticks] = signed_distances_to_hulls(points, log.cop[ticks, :2])
    return margins


def _sole_corners(centers: np.ndarray, yaws: np.ndarray, length: float, width: float) -> np.ndarray:
    """Corners of flat sole rectangles as :func:`~mpcwalk.models.support_polygon.
    foot_rectangle` places them, for centres (..., 2) and yaws (...): shape (..., 4, 2)."""
    half = 0.5 * np.array([[length, width], [-length, width], [-length, -width], [length, -width]])
    c, s = np.cos(yaws)[..., None], np.sin(yaws)[..., None]
    x = centers[..., 0:1] + (half[:, 0] * c - half[:, 1] * s)
    y = centers[..., 1:2] + (half[:, 0] * s + half[:, 1] * c)
    return np.stack([x, y], axis=-1)


def signed_distances_to_hulls(points: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """Signed distance [m] of each query point to the convex hull of its set of points,
    positive inside (as :meth:`SupportPolygon.signed_distance` of the hull), vectorised.

    The hull's edges are the ordered pairs of points (i, j) with every point on the left of
    i -> j (counter-clockwise); collinear points on an edge add sub-edges of the same line,
    which change neither the distance inside (the same line) nor outside (the same segment).

    Args:
        points: Shape (n, m, 2): ``n`` sets of ``m`` points (repeated points allowed).
        queries: Shape (n, 2).
    """
    _, m, _ = points.shape
    i, j = np.nonzero(~np.eye(m, dtype=bool))
    start, end = points[:, i], points[:, j]  # (n, pairs, 2)
    edge = end - start
    length2 = np.einsum("npk,npk->np", edge, edge)
    relative = points[:, None, :, :] - start[:, :, None, :]  # (n, pairs, m, 2)
    side = edge[..., None, 0] * relative[..., 1] - edge[..., None, 1] * relative[..., 0]
    scale = np.sqrt(length2)
    tolerance = 1e-12 * np.maximum(scale, 1e-300)
    is_edge = (length2 > 1e-24) & np.all(side >= -tolerance[..., None], axis=2)
    to_query = queries[:, None, :] - start  # (n, pairs, 2)
    cross = edge[..., 0] * to_query[..., 1] - edge[..., 1] * to_query[..., 0]
    with np.errstate(invalid="ignore", divide="ignore"):
        inner = np.where(is_edge, cross / scale, np.inf).min(axis=1)
        ratio = np.clip(np.einsum("npk,npk->np", to_query, edge) / length2, 0.0, 1.0)
    closest = start + np.where(is_edge, ratio, 0.0)[..., None] * edge
    gap = np.linalg.norm(queries[:, None, :] - closest, axis=-1)
    outer = np.where(is_edge, gap, np.inf).min(axis=1)
    return np.where(inner >= 0.0, inner, -outer)
