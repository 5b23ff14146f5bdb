"""Bounds of the footstep variables along the world axes, as rows ``G x <= h`` of
:class:`~mpcwalk.qp.footstep_qp.FootstepQP`.

The footstep of variable ``j`` has its x in column ``2 N + j`` and its y in column
``2 N + nf + j`` of the QP's ``n`` columns (``N`` jerks per axis first). Each landing is
reachable from its predecessor (:func:`reach_rows`), and two kinds of bound hold it along
the world axes:

- the late step adjustment's box about each landing's published position (what the swing's
  time left allows), :func:`box_rows`;
- on a terrain, the band of the top each landing was placed on
  (:class:`~mpcwalk.footsteps.landing_bands.LandingBands`), :func:`band_rows`.
"""

import numpy as np

from mpcwalk.qp.footstep_supports import StepVariables


def reach_rows(steps: StepVariables, n: int, N: int, nf: int) -> tuple[np.ndarray, np.ndarray]:
    """``lower <= R(yaw_p)^T (F_j - F_p) <= upper`` for each active footstep ``j``: four rows
    (``+/-`` its local x, then ``+/-`` its local y) relative to its predecessor ``p`` (a
    variable, or a fixed footstep moving the bound); ``(G, h)`` with ``n`` columns."""
    active = np.flatnonzero(steps.active)
    yaw = steps.predecessor_yaw[active]
    c, s = np.cos(yaw), np.sin(yaw)
    e = np.empty((len(active), 4, 2))  # x axis, -x axis, y axis, -y axis
    e[:, 0, 0], e[:, 0, 1] = c, s
    e[:, 1, 0], e[:, 1, 1] = -c, -s
    e[:, 2, 0], e[:, 2, 1] = -s, c
    e[:, 3, 0], e[:, 3, 1] = s, -c
    bounds = np.empty((len(active), 4))
    bounds[:, 0], bounds[:, 1] = steps.upper[active, 0], -steps.lower[active, 0]
    bounds[:, 2], bounds[:, 3] = steps.upper[active, 1], -steps.lower[active, 1]
    rows = np.arange(4 * len(active)).reshape(-1, 4)
    G = np.zeros((4 * len(active), n))
    G[rows, (2 * N + active)[:, None]] += e[..., 0]
    G[rows, (2 * N + nf + active)[:, None]] += e[..., 1]
    predecessor = steps.predecessor[active]
    chained = predecessor >= 0
    if chained.any():
        p = predecessor[chained][:, None]
        G[rows[chained], 2 * N + p] -= e[chained, :, 0]
        G[rows[chained], 2 * N + nf + p] -= e[chained, :, 1]
    moved = np.einsum("rka,ra->rk", e, steps.predecessor_xy[active])
    h = np.where(chained[:, None], bounds, bounds + moved).ravel()
    return G, h


def box_rows(steps: StepVariables, n: int, N: int, nf: int) -> tuple[np.ndarray, np.ndarray]:
    """``|F_j - initial_j| <= box_j`` per world axis, for the finite half-widths of
    ``steps.box`` (the late step adjustment's bound on a landing change): ``(G, h)`` with
    ``n`` columns, the rows ``+F`` of every bound, then ``-F``."""
    if steps.box is None:
        return np.zeros((0, n)), np.zeros(0)
    j, a = np.nonzero(np.isfinite(steps.box) & steps.active[:, None])
    columns = 2 * N + a * nf + j
    G = np.zeros((2 * len(j), n))
    G[np.arange(len(j)), columns] = 1.0
    G[len(j) + np.arange(len(j)), columns] = -1.0
    centre, half = steps.initial[j, a], steps.box[j, a]
    return G, np.concatenate([centre + half, half - centre])


def band_rows(steps: StepVariables, n: int, N: int, nf: int) -> tuple[np.ndarray, np.ndarray]:
    """``band_lower_j <= F_j <= band_upper_j`` per world axis, for the finite bounds of the
    active footsteps (the top each landing was placed on): ``(G, h)`` with ``n`` columns,
    the upper bounds' rows, then the lower bounds'; no row without bands."""
    if steps.band_upper is None and steps.band_lower is None:
        return np.zeros((0, n)), np.zeros(0)
    rows, h = [np.zeros((0, n))], [np.zeros(0)]
    for bound, sign in ((steps.band_upper, 1.0), (steps.band_lower, -1.0)):
        if bound is None:
            continue
        j, a = np.nonzero(np.isfinite(bound) & steps.active[:, None])
        G = np.zeros((len(j), n))
        G[np.arange(len(j)), 2 * N + a * nf + j] = sign
        rows.append(G)
        h.append(sign * bound[j, a])
    return np.vstack(rows), np.concatenate(h)


__all__ = ["band_rows", "box_rows", "reach_rows"]
