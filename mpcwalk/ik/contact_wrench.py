"""The wrenches a flat sole can exert: a linearised contact wrench cone.

A rectangular sole of length ``L`` and width ``W`` on flat ground transmits a wrench
``f = (fx, fy, fz, tx, ty, tz)`` (sole frame, moment about the sole centre) when

- the normal force is unilateral and bounded: ``0 <= fz <= fz_max``;
- the tangential force lies in the friction pyramid inscribed in the cone of coefficient
  ``mu``: ``|fx|, |fy| <= mu / sqrt(2) fz``;
- the centre of pressure ``(-ty / fz, tx / fz)`` lies in the sole shrunk by a margin:
  ``|ty| <= m L / 2 fz``, ``|tx| <= m W / 2 fz``;
- the yaw moment does not make the sole spin: ``|tz| <= mu / sqrt(2) min(L, W) / 2 fz``
  (a conservative bound of Caron et al.'s contact wrench cone, ICRA 2015).

All rows are homogeneous in ``f`` except ``fz <= fz_max``: with ``fz_max = 0`` the cone
collapses to the zero wrench, which is how a sole's load is ramped to zero at lift-off.
"""

import math

import numpy as np

from mpcwalk.exceptions import ConfigurationError

#: Rows of :func:`wrench_cone` per sole.
CONE_ROWS = 12


def wrench_cone(
    sole_size: tuple[float, float], friction: float, cop_margin: float = 0.9
) -> np.ndarray:
    """Rows ``C`` of ``C f <= d`` for one sole (``d`` is zero but for the row of index 1,
    ``fz <= fz_max``, whose coefficient is set per tick: :func:`cone_bounds`).

    Args:
        sole_size: Sole length and width [m].
        friction: Friction coefficient of the ground, > 0.
        cop_margin: Share in (0, 1] of the half sole the CoP may reach.

    Returns:
        ``C``, shape (:data:`CONE_ROWS`, 6).

    Raises:
        ConfigurationError: A non-positive size or friction, or a margin out of (0, 1].
    """
    length, width = (float(s) for s in sole_size)
    if not (length > 0.0 and width > 0.0 and math.isfinite(length * width)):
        raise ConfigurationError(f"sole_size must be two lengths > 0 [m], got {sole_size!r}.")
    if not (math.isfinite(friction) and friction > 0.0):
        raise ConfigurationError(f"friction must be > 0, got {friction!r}.")
    if not 0.0 < cop_margin <= 1.0:
        raise ConfigurationError(f"cop_margin must be in (0, 1], got {cop_margin!r}.")
    mu = friction / math.sqrt(2.0)
    half_l, half_w = 0.5 * cop_margin * length, 0.5 * cop_margin * width
    spin = mu * 0.5 * min(length, width)
    C = np.zeros((CONE_ROWS, 6))
    C[0, 2] = -1.0  # fz >= 0
    C[1, 2] = 1.0  # fz <= fz_max
    for row, (index, bound) in enumerate(
        ((0, mu), (1, mu), (3, half_w), (4, half_l), (5, spin)), start=1
    ):
        C[2 * row, index], C[2 * row, 2] = 1.0, -bound
        C[2 * row + 1, index], C[2 * row + 1, 2] = -1.0, -bound
    return C


def cone_bounds(max_normal_force: float) -> np.ndarray:
    """``d`` of :func:`wrench_cone`'s rows for a sole whose normal force may reach
    ``max_normal_force`` [N], shape (:data:`CONE_ROWS`,)."""
    d = np.zeros(CONE_ROWS)
    d[1] = max_normal_force
    return d
