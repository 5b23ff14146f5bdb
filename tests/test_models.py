"""Reduced models: LIPM, cart-table, support polygons."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.models import LIPM, CartTable, SupportPolygon, convex_hull, foot_rectangle


def test_lipm_omega_paper_m():
    lipm = LIPM(com_height=0.23)
    assert lipm.omega == pytest.approx(np.sqrt(9.81 / 0.23), rel=1e-12)


@pytest.mark.parametrize("bad", [0.0, -0.2, float("nan"), float("inf")])
def test_lipm_rejects_bad_height(bad):
    with pytest.raises(ConfigurationError, match="com_height"):
        LIPM(com_height=bad)


def test_lipm_propagation_is_exact_against_ode():
    """Closed-form propagation under an affine ZMP matches a tight ODE solve."""
    lipm = LIPM(com_height=0.23)
    w2 = lipm.omega**2
    c0, v0, p0, m, T = 0.03, -0.1, 0.05, 0.2, 0.4

    def f(t, y):
        return [y[1], w2 * (y[0] - (p0 + m * t))]

    sol = solve_ivp(f, (0.0, T), [c0, v0], rtol=1e-12, atol=1e-14)
    c, v, a = lipm.propagate(c0, v0, p0, T, m)
    assert c == pytest.approx(sol.y[0, -1], abs=1e-10)
    assert v == pytest.approx(sol.y[1, -1], abs=1e-9)
    # ZMP equation holds at the end point
    assert c - a / w2 == pytest.approx(p0 + m * T, abs=1e-12)


def test_cart_table_prediction_matches_recursion():
    model = CartTable(LIPM(0.23), 0.1)
    rng = np.random.default_rng(0)
    N = 12
    x0 = rng.normal(size=3)
    U = rng.normal(size=N)
    P = model.prediction_matrices(N)
    x = x0.copy()
    for i in range(N):
        x = model.A @ x + model.B * U[i]
        assert P["Pps"][i] @ x0 + P["Ppu"][i] @ U == pytest.approx(x[0], abs=1e-12)
        assert P["Pvs"][i] @ x0 + P["Pvu"][i] @ U == pytest.approx(x[1], abs=1e-12)
        assert P["Pas"][i] @ x0 + P["Pau"][i] @ U == pytest.approx(x[2], abs=1e-12)
        assert P["Pzs"][i] @ x0 + P["Pzu"][i] @ U == pytest.approx(model.C @ x, abs=1e-12)


def test_cart_table_integrate_any_duration_composes():
    model = CartTable(LIPM(0.23), 0.1)
    x0 = np.array([[0.01, -0.02], [0.1, 0.05], [0.3, -0.2]])
    jerk = np.array([1.5, -0.7])
    once = model.integrate(x0, jerk, 0.1)
    twice = model.integrate(model.integrate(x0, jerk, 0.04), jerk, 0.06)
    np.testing.assert_allclose(once, twice, atol=1e-14)
    np.testing.assert_allclose(once[:, 0], model.A @ x0[:, 0] + model.B * jerk[0], atol=1e-14)


def test_cart_table_rejects_bad_period():
    with pytest.raises(ConfigurationError, match="sampling_period"):
        CartTable(LIPM(), -0.1)


def test_foot_rectangle_at_yaw():
    rect = foot_rectangle([1.0, 2.0], np.pi / 2, 0.2, 0.1)
    # Rotated by 90 deg: length along y.
    assert rect.contains(np.array([1.0, 2.09]))
    assert not rect.contains(np.array([1.09, 2.0]))
    assert rect.signed_distance(np.array([1.0, 2.0])) == pytest.approx(0.05)
    np.testing.assert_allclose(rect.centroid, [1.0, 2.0], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(rect.A, axis=1), 1.0)


def test_signed_distance_outside_is_euclidean():
    rect = foot_rectangle([0.0, 0.0], 0.0, 0.2, 0.1)
    # Beyond a corner: distance to the corner, not to an edge line.
    assert rect.signed_distance(np.array([0.13, 0.09])) == pytest.approx(-np.hypot(0.03, 0.04))
    assert rect.signed_distance(np.array([0.0, -0.07])) == pytest.approx(-0.02)


def test_double_support_hull_contains_both_feet():
    left = foot_rectangle([0.05, 0.05], 0.2, 0.1, 0.06)
    right = foot_rectangle([0.0, -0.05], -0.1, 0.1, 0.06)
    hull = SupportPolygon.union_hull([left, right])
    for v in np.vstack([left.vertices, right.vertices]):
        assert hull.signed_distance(v) >= -1e-12
    assert hull.contains(np.array([0.025, 0.0]))
    assert len(hull.b) <= 8
    A, b = hull.padded_halfplanes(8)
    assert A.shape == (8, 2) and b.shape == (8,)
    # Padding rows never bind inside the polygon.
    pts = np.random.default_rng(1).uniform(-0.1, 0.1, size=(200, 2))
    inside = hull.contains(pts)
    np.testing.assert_array_equal(
        np.all(pts @ A.T <= b + 1e-12, axis=1), inside | (hull.signed_distance(pts) >= -1e-12)
    )


def test_convex_hull_ccw():
    pts = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]])
    hull = convex_hull(pts)
    assert len(hull) == 4
    area = 0.5 * np.sum(hull[:, 0] * np.roll(hull[:, 1], -1) - np.roll(hull[:, 0], -1) * hull[:, 1])
    assert area == pytest.approx(1.0)


def test_degenerate_polygon_is_a_named_error():
    with pytest.raises(ConfigurationError, match="non-collinear"):
        SupportPolygon.from_vertices(np.array([[0, 0], [1, 1], [2, 2]]))
