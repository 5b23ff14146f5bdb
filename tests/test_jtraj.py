"""Joint-space trajectories (paper A's jtraj)."""

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.jtraj import JointTrajectory, jtraj

Q0 = np.array([0.0, 1.0, -0.5])  # [rad]
Q1 = np.array([1.0, -1.0, -0.5])  # [rad] (third joint does not move)
DELTA = Q1 - Q0


def test_quintic_endpoints_and_boundary_derivatives():
    traj = jtraj(Q0, Q1, 51)
    assert isinstance(traj, JointTrajectory)
    assert traj.q.shape == traj.qd.shape == traj.qdd.shape == (51, 3)
    assert traj.s[0] == 0.0 and traj.s[-1] == 1.0 and traj.nb_samples == 51
    np.testing.assert_array_equal(traj.q[0], Q0)
    np.testing.assert_array_equal(traj.q[-1], Q1)
    for row in (0, -1):
        np.testing.assert_allclose(traj.qd[row], 0.0, atol=1e-14)
        np.testing.assert_allclose(traj.qdd[row], 0.0, atol=1e-13)
    np.testing.assert_array_equal(traj.q[:, 2], -0.5)


def test_quintic_is_symmetric_with_known_peak():
    traj = jtraj(Q0, Q1, 101)
    # q(s) + q(1 - s) = q0 + q1, velocity even, acceleration odd about s = 1/2.
    np.testing.assert_allclose(traj.q + traj.q[::-1], np.tile(Q0 + Q1, (101, 1)), atol=1e-14)
    np.testing.assert_allclose(traj.qd, traj.qd[::-1], atol=1e-13)
    np.testing.assert_allclose(traj.qdd, -traj.qdd[::-1], atol=1e-12)
    np.testing.assert_allclose(traj.q[50], 0.5 * (Q0 + Q1), atol=1e-15)
    # Peak velocity of 10 s^3 - 15 s^4 + 6 s^5 is 15/8 at s = 1/2.
    np.testing.assert_allclose(traj.qd[50], 15.0 / 8.0 * DELTA, rtol=1e-14)
    np.testing.assert_allclose(np.abs(traj.qd).max(axis=0), 15.0 / 8.0 * np.abs(DELTA), rtol=1e-14)
    assert np.all(np.diff(traj.q[:, 0]) > 0.0)  # monotone


def _quintic_oracle(q0, q1, qd0, qd1):
    """Quintic coefficients (highest power first) from the six boundary
    conditions, solved as a linear system independently of jtraj."""
    rows = np.array(
        [
            [0, 0, 0, 0, 0, 1],  # q(0)
            [1, 1, 1, 1, 1, 1],  # q(1)
            [0, 0, 0, 0, 1, 0],  # q'(0)
            [5, 4, 3, 2, 1, 0],  # q'(1)
            [0, 0, 0, 2, 0, 0],  # q''(0)
            [20, 12, 6, 2, 0, 0],  # q''(1)
        ],
        dtype=float,
    )
    return np.linalg.solve(rows, [q0, q1, qd0, qd1, 0.0, 0.0])


def test_quintic_matches_the_boundary_value_oracle_and_finite_differences():
    n = 2001
    qd0, qd1 = np.array([0.3, -0.2, 0.1]), np.array([-0.4, 0.0, 0.2])
    traj = jtraj(Q0, Q1, n, qd0=qd0, qd1=qd1)
    ds = 1.0 / (n - 1)
    for j in range(3):
        coefficients = _quintic_oracle(Q0[j], Q1[j], qd0[j], qd1[j])
        np.testing.assert_allclose(traj.q[:, j], np.polyval(coefficients, traj.s), atol=1e-13)
        first, second = np.polyder(coefficients), np.polyder(coefficients, 2)
        np.testing.assert_allclose(traj.qd[:, j], np.polyval(first, traj.s), atol=1e-12)
        np.testing.assert_allclose(traj.qdd[:, j], np.polyval(second, traj.s), atol=1e-11)
        # Central differences of q: error <= max|q'''| ds^2 / 6 (+ rounding).
        third = np.abs(np.polyval(np.polyder(coefficients, 3), np.linspace(0, 1, 1001))).max()
        fd = (traj.q[2:, j] - traj.q[:-2, j]) / (2 * ds)
        bound = third * ds**2 / 6.0 + 1e-15 / ds
        np.testing.assert_allclose(traj.qd[1:-1, j], fd, rtol=0.0, atol=bound)


def test_quintic_boundary_velocities():
    qd0, qd1 = np.array([0.3, -0.2, 0.1]), np.array([-0.4, 0.0, 0.2])
    traj = jtraj(Q0, Q1, 11, qd0=qd0, qd1=qd1)
    np.testing.assert_allclose(traj.qd[0], qd0, atol=1e-15)
    np.testing.assert_allclose(traj.qd[-1], qd1, atol=1e-13)
    np.testing.assert_allclose(traj.qdd[0], 0.0, atol=1e-15)
    np.testing.assert_allclose(traj.qdd[-1], 0.0, atol=1e-12)
    np.testing.assert_array_equal(traj.q[-1], Q1)


@pytest.mark.parametrize("fraction", [1.0 / 3.0, 0.25, 0.5])
def test_trapezoidal_profile(fraction):
    n = 301
    traj = jtraj(Q0, Q1, n, profile="trapezoidal", acceleration_fraction=fraction)
    np.testing.assert_array_equal(traj.q[0], Q0)
    np.testing.assert_array_equal(traj.q[-1], Q1)
    np.testing.assert_allclose(traj.qd[0], 0.0, atol=1e-15)
    np.testing.assert_allclose(traj.qd[-1], 0.0, atol=1e-14)
    peak = DELTA / (1.0 - fraction)  # area of the trapezoid equals DELTA
    np.testing.assert_allclose(np.abs(traj.qd).max(axis=0), np.abs(peak), rtol=1e-12)
    cruise = (traj.s >= fraction) & (traj.s <= 1.0 - fraction)
    np.testing.assert_allclose(traj.qd[cruise], np.tile(peak, (cruise.sum(), 1)), rtol=1e-12)
    accelerating = traj.s < fraction
    np.testing.assert_allclose(
        traj.qdd[accelerating], np.tile(peak / fraction, (accelerating.sum(), 1))
    )
    np.testing.assert_allclose(traj.q + traj.q[::-1], np.tile(Q0 + Q1, (n, 1)), atol=1e-14)
    np.testing.assert_allclose(traj.qd, traj.qd[::-1], atol=1e-12)
    # Position and velocity agree: central differences, q'' bounded by peak / fraction.
    ds = 1.0 / (n - 1)
    fd = (traj.q[2:] - traj.q[:-2]) / (2 * ds)
    np.testing.assert_allclose(traj.qd[1:-1], fd, rtol=0.0, atol=np.abs(peak).max() / fraction * ds)


def test_default_trapezoid_peak_is_one_and_a_half_mean_velocity():
    traj = jtraj(0.0, 2.0, 7, profile="trapezoidal")
    assert traj.q.shape == (7, 1)
    np.testing.assert_allclose(traj.q[:, 0], [0.0, 0.125, 0.5, 1.0, 1.5, 1.875, 2.0], atol=1e-15)
    assert traj.qd.max() == pytest.approx(3.0, rel=1e-15)


def test_results_are_read_only():
    traj = jtraj(Q0, Q1, 5)
    with pytest.raises(ValueError):
        traj.q[0, 0] = 1.0


@pytest.mark.parametrize(
    "args, kwargs, message",
    [
        ((Q0, Q1, 1), {}, "integer >= 2"),
        ((Q0, Q1, 2.5), {}, "integer >= 2"),
        ((Q0, Q1, True), {}, "integer >= 2"),
        ((Q0, Q1[:2], 5), {}, "shape of q0"),
        ((Q0, [0.0, np.nan, 1.0], 5), {}, "must be finite"),
        ((np.eye(3), np.eye(3), 5), {}, "1-D joint vector"),
        ((Q0, "abc", 5), {}, "number or a 1-D array"),
        ((Q0, Q1, 5), {"profile": "cubic"}, "quintic, trapezoidal"),
        ((Q0, Q1, 5), {"qd0": [1.0, 0.0]}, "shape of q0"),
        (
            (Q0, Q1, 5),
            {"profile": "trapezoidal", "qd1": [1.0, 0.0, 0.0]},
            "starts and ends at rest",
        ),
        ((Q0, Q1, 5), {"profile": "trapezoidal", "acceleration_fraction": 0.6}, r"\(0, 0.5\]"),
        ((Q0, Q1, 5), {"profile": "trapezoidal", "acceleration_fraction": 0.0}, r"\(0, 0.5\]"),
    ],
)
def test_bad_input_raises(args, kwargs, message):
    with pytest.raises(ConfigurationError, match=message):
        jtraj(*args, **kwargs)
