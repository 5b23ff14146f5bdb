"""Read-only arrays: the snapshots and references that results and states hand out."""

import numpy as np


def frozen_array(values, shape: tuple[int, ...] | None = None, dtype=float) -> np.ndarray:
    """Read-only copy of ``values`` as ``dtype`` (reshaped to ``shape`` when given)."""
    array = np.array(values, dtype=dtype)
    if shape is not None:
        array = array.reshape(shape)
    array.setflags(write=False)
    return array


def as_float(value) -> float:
    """``float(value)``, or NaN when it is not a number (callers then name the error)."""
    try:
        return float(value)
    except (TypeError, ValueError):
        return float("nan")


def as_float_array(value) -> np.ndarray:
    """``value`` as a float array, or an empty array when it is not one (callers then name
    the error from its shape)."""
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return np.full(0, np.nan)
