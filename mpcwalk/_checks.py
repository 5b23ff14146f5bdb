"""Read-only arrays: the snapshots and references that results and states hand out."""

import math
from collections.abc import Callable

import numpy as np


def all_finite(arrays, scalars=()) -> bool:
    """Whether every value of the numpy ``arrays`` and of the ``scalars`` is finite, in one
    pass (the per-tick checks at the loop's boundaries: one concatenation, one test)."""
    if not all(map(math.isfinite, scalars)):
        return False
    if not arrays:
        return True
    return bool(np.isfinite(np.concatenate(arrays, axis=None)).all())  # flattened


def frozen_array(values, shape: tuple[int, ...] | None = None, dtype=float) -> np.ndarray:
    """Read-only copy of ``values`` as ``dtype`` (reshaped to ``shape`` when given)."""
    array = np.array(values, dtype=dtype)
    if shape is not None:
        array = array.reshape(shape)
    array.setflags(write=False)
    return array


def freeze(array: np.ndarray) -> np.ndarray:
    """``array`` itself made read-only (no copy: for a fresh array nobody else holds)."""
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


def checked_number(
    name: str,
    value,
    *,
    low: float | None = None,
    high: float | None = None,
    low_inclusive: bool = True,
    unit: str = "",
    fix: str = "",
    error: Callable[[str], Exception] | None = None,
) -> float:
    """``value`` as a float when it is a real number within ``[low, high]`` (``(low,
    high]`` without ``low_inclusive``); else a ConfigurationError that says what was expected,
    what came and ``fix`` (or the error ``error`` builds from what was expected, e.g. ``"a
    number >= 0"``). Strings and booleans are refused, not coerced."""
    from mpcwalk.exceptions import ConfigurationError

    unit_text = f" {unit}" if unit else ""
    if low is not None and high is not None:
        bracket = "[" if low_inclusive else "("
        expected = f"a number in {bracket}{low:g}, {high:g}]{unit_text}"
    elif low is not None:
        expected = f"a number {'>=' if low_inclusive else '>'} {low:g}{unit_text}"
    elif high is not None:
        expected = f"a number <= {high:g}{unit_text}"
    else:
        expected = f"a finite number{unit_text}"
    ok = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(
        value, (bool, np.bool_)
    )
    number = float(value) if ok else float("nan")
    if ok and np.isfinite(number):
        above = low is None or (number >= low if low_inclusive else number > low)
        if above and (high is None or number <= high):
            return number
    if error is not None:
        raise error(expected)
    suffix = f"; {fix}" if fix else ""
    raise ConfigurationError(f"{name} must be {expected}, got {value!r}{suffix}.")
