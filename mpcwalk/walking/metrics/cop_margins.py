"""The CoP's margin in the support of the soles that carry the force, every tick at once.

At each tick of a walk's log (the simulator's ground truth), the margin is defined so that
it speaks of the soles that carry the robot then, on level ground or not:

1. **Loaded soles**: those whose measured normal force is at least 5 % of the feet's total
   (:data:`LOADED_SHARE`) and at least 0.5 N (:data:`LOADED_FLOOR`). The schedule plays no
   part: a landing foot that already pushes counts, a lifting foot that no longer does not.
   A tick with no loaded sole has no margin (NaN).
2. **The plane**: the horizontal plane at ``z_v``, the mean height of the loaded soles'
   origins weighted by their normal forces.
3. **The ZMP** of the measured contact wrench of the loaded soles on that plane: the point
   about which the wrench has no horizontal moment, ``p = (-M_y / F_z, M_x / F_z, z_v)`` for
   the resultant force ``F`` and moment ``M`` about ``(0, 0, z_v)``. The force of an
   unloaded sole is left out as its sole is left out of the region: the two speak of the
   same soles, so a CoP on level ground cannot leave the region it is made in.
4. **The support region**: the convex hull of the loaded soles' corners (rectangles of the
   schedule's sole size at their measured positions, heights and yaws) projected onto the
   plane centrally from the measured CoM ``c``: a corner ``p`` at height ``z_p`` maps to
   ``c + (p - c) (c_z - z_v) / (c_z - z_p)``. A tick whose CoM is not above every loaded
   sole has no margin (NaN).
5. **The margin**: the ZMP's signed distance to that hull [m], positive inside.

When the loaded soles are level, ``z_v`` is their height, the projection changes nothing
and the ZMP is the CoP of their forces: the margin is the usual CoP margin in the hull of
the loaded soles. The metrics compute it after the walk from the log, vectorised over the
ticks (:func:`signed_distances_to_hulls`).

The soles are flat rectangles at their origins' heights: a sole rocking on an edge stands
on it below its origin, and the ZMP on the origin's plane moves by that height times the
friction force over the normal force (a fraction of a millimetre beyond the edge, at worst).
"""

import numpy as np

from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.models.support_polygon import SupportPolygon
from mpcwalk.walking.log import WalkLog

#: A sole carries force when its normal force is at least this share of the feet's total...
LOADED_SHARE = 0.05
#: ... and at least this force [N] (below the share of the lightest robot's weight: it only
#: matters when the robot barely touches the ground).
LOADED_FLOOR = 0.5


def loaded_soles(log: WalkLog) -> np.ndarray:
    """Whether each sole carries force at each tick, shape (n, 2) bool (left, right):
    its measured normal force [N] is at least :data:`LOADED_SHARE` of the feet's total and
    at least :data:`LOADED_FLOOR` (never, in a log without the foot wrenches)."""
    normal = log.foot_wrenches[:, :, 2]
    total = normal.sum(axis=1, keepdims=True)
    with np.errstate(invalid="ignore"):
        return (normal >= LOADED_SHARE * total) & (normal >= LOADED_FLOOR)


def measured_zmp(log: WalkLog) -> tuple[np.ndarray, np.ndarray]:
    """ZMP of the loaded soles' measured contact wrench on the plane of their force-weighted
    mean height, per tick (NaN without a loaded sole).

    Returns:
        ``(zmp, height)``: the ZMP's x, y [m], shape (n, 2), and the plane's height
        ``z_v`` [m], shape (n,).
    """
    loaded = loaded_soles(log)
    wrenches = np.where(loaded[..., None], log.foot_wrenches, 0.0)  # (n, 2, 6)
    force = wrenches[..., :3].sum(axis=1)  # (n, 3)
    heights = np.where(loaded, log.sole_positions[:, :, 2], 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        height = np.einsum("nk,nk->n", wrenches[..., 2], heights) / force[:, 2]
        # moment about (0, 0, z_v): each sole's moment about its origin plus its lever
        levers = np.where(loaded[..., None], log.sole_positions, 0.0)
        levers[..., 2] -= np.where(loaded, height[:, None], 0.0)
        moment = (np.cross(levers, wrenches[..., :3]) + wrenches[..., 3:]).sum(axis=1)
        zmp = np.stack([-moment[:, 1], moment[:, 0]], axis=1) / force[:, 2:3]
    return zmp, height


def cop_margins(log: WalkLog, schedule: ContactSchedule) -> np.ndarray:
    """Signed distance [m] of the measured ZMP to the support region of the loaded soles,
    positive inside, per tick (NaN without a loaded sole): the module's definition, for all
    ticks at once (:func:`measured_zmp`, :func:`signed_distances_to_hulls`); the schedule
    gives the soles' size."""
    margins = np.full(len(log), np.nan)
    zmp, height = measured_zmp(log)
    ticks = np.flatnonzero(np.isfinite(zmp).all(axis=1))
    if not len(ticks):
        return margins
    points, valid = _support_corners(log, schedule, ticks, height[ticks])
    margins[ticks] = np.where(valid, signed_distances_to_hulls(points, zmp[ticks]), np.nan)
    return margins


def measured_support_polygon(
    log: WalkLog, schedule: ContactSchedule, tick: int
) -> SupportPolygon | None:
    """The support region of tick ``tick`` of the log: the hull of the loaded soles'
    corners projected onto the ZMP's plane from the CoM (None: no loaded sole, or the CoM
    not above them). :func:`cop_margins` is the ZMP's signed distance to it."""
    height = measured_zmp(log)[1][tick : tick + 1]
    if not np.isfinite(height).all():
        return None
    points, valid = _support_corners(log, schedule, np.array([tick]), height)
    return SupportPolygon.from_vertices(points[0]) if valid[0] else None


def _support_corners(
    log: WalkLog, schedule: ContactSchedule, ticks: np.ndarray, height: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Corners of the loaded soles at ``ticks`` (each with a loaded sole) projected onto the
    plane at ``height`` [m] centrally from the CoM, shape (n, 8, 2) (one loaded sole: its
    four corners twice), and whether the CoM is above every loaded sole, shape (n,)."""
    loaded = loaded_soles(log)[ticks]
    soles = log.sole_positions[ticks]  # (n, 2, 3)
    com = log.com[ticks]
    corners = sole_corners(
        soles[:, :, :2], log.sole_yaws[ticks], schedule.foot.length, schedule.foot.width
    )  # (n, 2, 4, 2)
    drop = com[:, 2:3] - soles[:, :, 2]  # (n, 2): CoM height above each sole
    valid = np.all((drop > 0.0) | ~loaded, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(loaded, (com[:, 2:3] - height[:, None]) / drop, 1.0)
    centre = com[:, None, None, :2]
    projected = centre + (corners - centre) * scale[:, :, None, None]
    first = np.where(loaded[:, 0], 0, 1)
    second = np.where(loaded[:, 1], 1, 0)
    rows = np.arange(len(ticks))
    points = np.concatenate([projected[rows, first], projected[rows, second]], axis=1)
    return points, valid


def sole_corners(centers: np.ndarray, yaws: np.ndarray, length: float, width: float) -> np.ndarray:
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
