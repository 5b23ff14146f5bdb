"""Paper M's interpolation profiles h (eq. 20) and v (eq. 22-23)."""

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.interpolation import (
    step_interpolation,
    step_interpolation_derivative,
    swing_height_profile,
    swing_height_profile_derivative,
)

PHI_B, PHI_E = 0.1, 0.9  # r_ds = 0.2 (paper M, Table 1)
WIDTH = PHI_E - PHI_B
EPS = 1e-5  # finite-difference step in phi
ROUNDOFF = 4.0 * np.finfo(float).eps / EPS  # rounding error of a difference quotient


def h(phi):
    return step_interpolation(phi, PHI_B, PHI_E)


def v(phi):
    return swing_height_profile(phi, PHI_B, PHI_E)


def central_difference(f, phi, eps=EPS):
    return (f(phi + eps) - f(phi - eps)) / (2.0 * eps)


def test_h_boundary_values():
    assert h(0.0) == 0.0
    assert h(PHI_B) == 0.0
    assert h(PHI_E) == 1.0
    assert h(1.0) == 1.0
    assert h(0.5 * (PHI_B + PHI_E)) == pytest.approx(0.5, abs=1e-15)
    assert h(0.5 * PHI_B) == 0.0  # flat in the opening double support
    assert h(0.5 * (PHI_E + 1.0)) == 1.0  # flat in the closing double support


def test_h_is_monotone_and_bounded():
    values = h(np.linspace(0.0, 1.0, 1001))
    assert np.all(np.diff(values) >= 0.0)
    assert values.min() == 0.0 and values.max() == 1.0


@pytest.mark.parametrize("corner", [PHI_B, PHI_E])
def test_h_is_c1_at_the_corners(corner):
    # Central difference of a C1 function whose second derivative is bounded
    # by M = (pi / w)^2 / 2: error <= M eps / 2; the true slope is 0.
    tolerance = 0.25 * (np.pi / WIDTH) ** 2 * EPS + ROUNDOFF
    assert abs(central_difference(h, corner)) <= tolerance
    assert step_interpolation_derivative(corner, PHI_B, PHI_E) == pytest.approx(0.0, abs=1e-15)


def test_v_boundary_values():
    assert v(PHI_B) == 0.0
    assert v(PHI_E) == 0.0
    assert v(0.5 * (PHI_B + PHI_E)) == 1.0
    assert v(0.0) == 0.0 and v(1.0) == 0.0
    values = v(np.linspace(0.0, 1.0, 1001))
    assert values.min() == 0.0 and values.max() == pytest.approx(1.0, abs=1e-15)


@pytest.mark.parametrize("corner", [PHI_B, PHI_E])
def test_v_is_c1_at_the_corners(corner):
    # Second derivative bounded by M = 2 (pi / w)^2.
    tolerance = (np.pi / WIDTH) ** 2 * EPS + ROUNDOFF
    assert abs(central_difference(v, corner)) <= tolerance
    assert swing_height_profile_derivative(corner, PHI_B, PHI_E) == pytest.approx(0.0, abs=1e-14)


def test_analytic_derivatives_match_finite_differences():
    # Points of single and double support, each farther than EPS from a corner.
    phi = np.concatenate(
        [
            np.linspace(0.0, PHI_B - 0.01, 5),
            np.linspace(PHI_B + 0.01, PHI_E - 0.01, 41),
            np.linspace(PHI_E + 0.01, 1.0, 5),
        ]
    )
    # Central-difference error <= max|f'''| eps^2 / 6.
    tol_h = 0.5 * (np.pi / WIDTH) ** 3 * EPS**2 / 6.0 + ROUNDOFF
    tol_v = 0.5 * (2.0 * np.pi / WIDTH) ** 3 * EPS**2 / 6.0 + ROUNDOFF
    np.testing.assert_allclose(
        step_interpolation_derivative(phi, PHI_B, PHI_E),
        central_difference(h, phi),
        rtol=0.0,
        atol=tol_h,
    )
    np.testing.assert_allclose(
        swing_height_profile_derivative(phi, PHI_B, PHI_E),
        central_difference(v, phi),
        rtol=0.0,
        atol=tol_v,
    )


def test_time_derivative_scales_with_step_duration():
    phi = np.linspace(0.0, 1.0, 21)
    T = 0.5  # [s]
    np.testing.assert_allclose(
        step_interpolation_derivative(phi, PHI_B, PHI_E, step_duration=T),
        step_interpolation_derivative(phi, PHI_B, PHI_E) / T,
        rtol=1e-15,
    )
    np.testing.assert_allclose(
        swing_height_profile_derivative(phi, PHI_B, PHI_E, step_duration=T),
        swing_height_profile_derivative(phi, PHI_B, PHI_E) / T,
        rtol=1e-15,
    )
    # Peak rates: pi / (2 w T) for h at mid single support, pi / (w T) for v
    # at a quarter and three quarters of it.
    mid = 0.5 * (PHI_B + PHI_E)
    assert step_interpolation_derivative(mid, PHI_B, PHI_E, step_duration=T) == pytest.approx(
        np.pi / (2.0 * WIDTH * T), rel=1e-14
    )
    quarter = PHI_B + 0.25 * WIDTH
    assert swing_height_profile_derivative(quarter, PHI_B, PHI_E, step_duration=T) == pytest.approx(
        np.pi / (WIDTH * T), rel=1e-14
    )


def test_shapes_scalars_and_no_double_support():
    assert isinstance(h(0.3), float) and isinstance(v(0.3), float)
    grid = np.linspace(0.0, 1.0, 12).reshape(3, 4)
    assert h(grid).shape == (3, 4) and v(grid).shape == (3, 4)
    assert step_interpolation_derivative(grid, PHI_B, PHI_E).shape == (3, 4)
    # r_ds = 0: the window is the whole step.
    assert step_interpolation(0.0, 0.0, 1.0) == 0.0
    assert step_interpolation(1.0, 0.0, 1.0) == 1.0
    assert swing_height_profile(0.5, 0.0, 1.0) == 1.0


def test_bad_window_and_duration_raise():
    with pytest.raises(ConfigurationError, match="phi_b < phi_e"):
        step_interpolation(0.5, 0.9, 0.1)
    with pytest.raises(ConfigurationError, match="phi_b < phi_e"):
        swing_height_profile(0.5, 0.5, 0.5)
    with pytest.raises(ConfigurationError, match="phi_b < phi_e"):
        step_interpolation(0.5, float("nan"), 0.9)
    with pytest.raises(ConfigurationError, match="step_duration must be a positive"):
        step_interpolation_derivative(0.5, PHI_B, PHI_E, step_duration=0.0)
    with pytest.raises(ConfigurationError, match="phi must be a number"):
        swing_height_profile("half", PHI_B, PHI_E)
