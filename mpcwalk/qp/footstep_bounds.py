"""Bounds of the footstep variables along the world axes, as rows ``G x <= h`` of
:class:`~mpcwalk.qp.footstep_qp.FootstepQP`.

The footstep of variable ``j`` has its x in column ``2 N + j`` and its y in column
``2 N + nf + j`` of the QP's ``n`` columns (``N`` jerks per axis first). Two kinds of bound:

- the late step adjustment's box about each landing's published position (what the swing's
  time left allows), :func:`box_rows`;
- on a terrain, the band of the top each landing was placed on
  (:class:`~mpcwalk.footsteps.landing_bands.LandingBands`), :func:`band_rows`.
"""

import numpy as np

from mpcwalk.qp.footstep_supports import StepVariables


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


__all__ = ["band_rows", "box_rows"]
