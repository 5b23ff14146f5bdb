"""Smooth interpolation profiles of paper M (eq. 19-23).

Both profiles are functions of the normalised step time ``phi = t / T`` in
[0, 1] and of the single-support window ``[phi_b, phi_e)``:

- ``h(phi)`` (eq. 20) rises from 0 to 1 with a half cosine during single
  support and is flat in double support. It drives the swing foot's
  horizontal pose (eq. 21) and the torso yaw (eq. 19).
- ``v(phi)`` (eq. 22-23) is a full raised cosine, 0 at both ends of single
  support and 1 in the middle. It scales the swing-foot height.

Both are C1: their derivatives vanish at ``phi_b`` and ``phi_e``, so the
foot lifts off and touches down with zero velocity. The derivative
functions return time derivatives ``d/dt = (1 / T) d/dphi`` when given the
step duration ``T``, or ``d/dphi`` with the default ``step_duration=1``.
"""

from typing import overload

import numpy as np

from mpcwalk.exceptions import ConfigurationError

ArrayLike = float | np.ndarray


def _window(phi, phi_b: float, phi_e: float) -> tuple[np.ndarray, float]:
    """Validated phases as an array and the window length ``phi_e - phi_b``."""
    phi_b, phi_e = float(phi_b), float(phi_e)
    if not (np.isfinite(phi_b) and np.isfinite(phi_e)) or not phi_b < phi_e:
        raise ConfigurationError(
            f"The single-support window needs finite phi_b < phi_e, got "
            f"phi_b={phi_b!r}, phi_e={phi_e!r}; use phi_b = r_ds / 2 and "
            "phi_e = 1 - r_ds / 2 with a double support ratio r_ds in [0, 1)."
        )
    try:
        phases = np.asarray(phi, dtype=float)
    except (TypeError, ValueError):
        raise ConfigurationError(
            f"phi must be a number or an array of numbers, got {phi!r}."
        ) from None
    return phases, phi_e - phi_b


def _check_duration(step_duration: float) -> float:
    step_duration = float(step_duration)
    if not np.isfinite(step_duration) or step_duration <= 0.0:
        raise ConfigurationError(
            f"step_duration must be a positive number of seconds, got "
            f"{step_duration!r}; pass 1.0 to get derivatives with respect to phi."
        )
    return step_duration


def _output(values: np.ndarray, phi) -> ArrayLike:
    return float(values) if np.ndim(phi) == 0 else values


def _raised_cosine(ratio, frequency: int):
    """``0.5 (1 - cos(frequency pi ratio))`` of the clipped window ratio: ``h`` (frequency 1,
    a half cosine) or ``v`` (frequency 2, a full one)."""
    return 0.5 * (1.0 - np.cos(frequency * np.pi * ratio))


def _raised_cosine_rate(ratio, width: float, frequency: int, step_duration: float):
    """Time derivative of :func:`_raised_cosine` over a window of ``width`` (in phase) of a
    step of ``step_duration`` [s], at the clipped window ratio ``ratio``."""
    return 0.5 * frequency * np.pi / width * np.sin(frequency * np.pi * ratio) / step_duration


def _rate_in_window(phi, phi_b: float, phi_e: float, step_duration: float, frequency: int):
    """The checked, vectorised derivative of :func:`_raised_cosine`: zero outside single
    support."""
    phases, width = _window(phi, phi_b, phi_e)
    step_duration = _check_duration(step_duration)
    ratio = (phases - phi_b) / width
    inside = (ratio >= 0.0) & (ratio < 1.0)
    rate = _raised_cosine_rate(np.clip(ratio, 0.0, 1.0), width, frequency, 1.0)
    return _output(np.where(inside, rate, 0.0) / step_duration, phi)


@overload
def step_interpolation(phi: float, phi_b: float, phi_e: float) -> float: ...
@overload
def step_interpolation(phi: np.ndarray, phi_b: float, phi_e: float) -> np.ndarray: ...
def step_interpolation(phi: ArrayLike, phi_b: float, phi_e: float) -> ArrayLike:
    """Paper M's ``h(phi)`` (eq. 20): 0 before single support, 1 after it.

    Args:
        phi: Normalised step time(s) ``t / T``, scalar or array.
        phi_b: Normalised time single support begins.
        phi_e: Normalised time single support ends (``phi_b < phi_e``).

    Returns:
        ``h`` in [0, 1], same shape as ``phi`` (a float for a scalar).

    Raises:
        ConfigurationError: If ``phi_b >= phi_e`` or a bound is not finite.
    """
    phases, width = _window(phi, phi_b, phi_e)
    ratio = np.clip((phases - phi_b) / width, 0.0, 1.0)
    return _output(_raised_cosine(ratio, 1), phi)


@overload
def step_interpolation_derivative(
    phi: float, phi_b: float, phi_e: float, *, step_duration: float = ...
) -> float: ...
@overload
def step_interpolation_derivative(
    phi: np.ndarray, phi_b: float, phi_e: float, *, step_duration: float = ...
) -> np.ndarray: ...
def step_interpolation_derivative(
    phi: ArrayLike, phi_b: float, phi_e: float, *, step_duration: float = 1.0
) -> ArrayLike:
    """Time derivative of :func:`step_interpolation`.

    Args:
        phi: Normalised step time(s) ``t / T``.
        phi_b: Normalised time single support begins.
        phi_e: Normalised time single support ends.
        step_duration: Step duration ``T`` in [s]; the result is ``dh/dt`` in
            [1/s]. With the default 1, it is ``dh/dphi``.

    Returns:
        The derivative, same shape as ``phi``; zero in double support.
    """
    return _rate_in_window(phi, phi_b, phi_e, step_duration, 1)


@overload
def swing_height_profile(phi: float, phi_b: float, phi_e: float) -> float: ...
@overload
def swing_height_profile(phi: np.ndarray, phi_b: float, phi_e: float) -> np.ndarray: ...
def swing_height_profile(phi: ArrayLike, phi_b: float, phi_e: float) -> ArrayLike:
    """Paper M's ``v(phi)`` (eq. 22-23): raised cosine over single support.

    ``v`` is 0 outside ``[phi_b, phi_e)``, 0 with zero slope at both ends of
    single support and 1 at its middle. The swing-foot height is
    ``z_step * v``.

    Args:
        phi: Normalised step time(s) ``t / T``, scalar or array.
        phi_b: Normalised time single support begins.
        phi_e: Normalised time single support ends (``phi_b < phi_e``).

    Returns:
        ``v`` in [0, 1], same shape as ``phi`` (a float for a scalar).
    """
    phases, width = _window(phi, phi_b, phi_e)
    ratio = (phases - phi_b) / width
    inside = (ratio >= 0.0) & (ratio < 1.0)
    values = _raised_cosine(np.clip(ratio, 0.0, 1.0), 2)
    return _output(np.where(inside, values, 0.0), phi)


@overload
def swing_height_profile_derivative(
    phi: float, phi_b: float, phi_e: float, *, step_duration: float = ...
) -> float: ...
@overload
def swing_height_profile_derivative(
    phi: np.ndarray, phi_b: float, phi_e: float, *, step_duration: float = ...
) -> np.ndarray: ...
def swing_height_profile_derivative(
    phi: ArrayLike, phi_b: float, phi_e: float, *, step_duration: float = 1.0
) -> ArrayLike:
    """Time derivative of :func:`swing_height_profile`.

    Args:
        phi: Normalised step time(s) ``t / T``.
        phi_b: Normalised time single support begins.
        phi_e: Normalised time single support ends.
        step_duration: Step duration ``T`` in [s]; the result is ``dv/dt`` in
            [1/s]. With the default 1, it is ``dv/dphi``.

    Returns:
        The derivative, same shape as ``phi``; zero in double support.
    """
    return _rate_in_window(phi, phi_b, phi_e, step_duration, 2)


def step_interpolation_scalar(
    phi: float, phi_b: float, phi_e: float, step_duration: float
) -> tuple[float, float]:
    """``h`` and ``dh/dt`` (:func:`step_interpolation` and its derivative) at one phase,
    without the checks and arrays of the vectorised functions (the per-tick path: the
    window and the duration come from a checked schedule). Same operations, same values."""
    width = phi_e - phi_b
    ratio = (phi - phi_b) / width
    clipped = min(max(ratio, 0.0), 1.0)
    h = float(_raised_cosine(clipped, 1))
    if not 0.0 <= ratio < 1.0:
        return h, 0.0
    return h, float(_raised_cosine_rate(clipped, width, 1, step_duration))


def swing_height_scalar(
    phi: float, phi_b: float, phi_e: float, step_duration: float
) -> tuple[float, float]:
    """``v`` and ``dv/dt`` (:func:`swing_height_profile` and its derivative) at one phase,
    as :func:`step_interpolation_scalar`."""
    width = phi_e - phi_b
    ratio = (phi - phi_b) / width
    if not 0.0 <= ratio < 1.0:
        return 0.0, 0.0
    clipped = min(max(ratio, 0.0), 1.0)
    v = float(_raised_cosine(clipped, 2))
    return v, float(_raised_cosine_rate(clipped, width, 2, step_duration))
