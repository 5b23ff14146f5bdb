"""The LIPM with a flywheel: its signs, its exact discretisation, its capture bounds."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.capturability import (
    capture_regions,
    flywheel_regions,
    largest_impulse,
    sole_box,
)
from mpcwalk.footsteps.footstep import Side
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.models.flywheel import (
    FlywheelLimits,
    FlywheelState,
    cmp_offset_bound,
    flywheel_transition,
)
from mpcwalk.models.lipm import LIPM

LIMITS = FlywheelLimits.small_humanoid()


def test_the_zmp_and_the_angular_momentum_rate_balance_the_moments_about_the_com():
    """Newton-Euler about the CoM: the ground reaction at the ZMP p = CMP - tau / (m g) has
    the moment L_dot of the flywheel's world angular momentum (FlywheelState's axes)."""
    lipm, m = LIPM(com_height=0.23), LIMITS.mass
    rng = np.random.default_rng(0)
    for _ in range(5):
        c, acc, tau = rng.normal(size=2), rng.normal(size=2), rng.normal(size=2)
        zmp = c - acc / lipm.omega**2 - tau / (m * lipm.gravity)
        force = m * np.array([acc[0], acc[1], lipm.gravity])
        lever = np.array([zmp[0] - c[0], zmp[1] - c[1], -lipm.com_height])
        moment = np.cross(lever, force)
        rate = FlywheelState(np.zeros(2), tau, np.zeros(2)).angular_momentum  # k_dot = tau
        np.testing.assert_allclose(moment[:2], rate[:2], atol=1e-12)


def test_the_discrete_flywheel_is_the_integral_of_the_continuous_one():
    """Three held torques over intervals of unequal length, against an ODE solver."""
    inertia, lengths, torques = 0.02, [0.013, 0.05, 0.05], [0.4, -0.7, 0.2]
    state = np.array([0.01, -0.003])
    x = state.copy()
    for length, tau in zip(lengths, torques):
        A, B = flywheel_transition(length, inertia)
        x = A @ x + B * tau
    ends = np.cumsum(lengths)

    def rhs(t, y):
        tau = torques[min(int(np.searchsorted(ends, t, side="right")), 2)]
        return [y[1] / inertia, tau]

    exact = solve_ivp(rhs, (0.0, ends[-1]), state, rtol=1e-11, atol=1e-13, max_step=1e-3)
    np.testing.assert_allclose(x, exact.y[:, -1], atol=1e-9)


def _offset_by_integration(limits: FlywheelLimits, omega: float, axis: int) -> float:
    """omega / (m g) int exp(-omega t) tau(t) dt of the bang-bang profile, and its lean."""
    tau, k_max = limits.max_torque[axis], limits.max_momentum[axis]
    inertia, phi = limits.inertia[axis], limits.max_angle[axis]
    t1 = min(math.sqrt(inertia * phi / tau), k_max / tau)
    tc = max(phi - tau * t1 * t1 / inertia, 0.0) * inertia / (tau * t1)
    t = np.linspace(0.0, 2 * t1 + tc, 200001)
    torque = np.where(t < t1, tau, np.where(t < t1 + tc, 0.0, -tau))
    momentum = np.concatenate([[0.0], np.cumsum(0.5 * (torque[1:] + torque[:-1]) * np.diff(t))])
    lean = np.trapezoid(momentum, t) / inertia
    assert lean == pytest.approx(phi, rel=1e-3)  # it stops at the limit
    assert np.max(np.abs(momentum)) <= k_max * (1 + 1e-4)  # the grid's step
    return omega / limits.weight * float(np.trapezoid(np.exp(-omega * t) * torque, t))


@pytest.mark.parametrize("axis", [0, 1])
def test_the_flywheel_bound_is_the_bang_bang_profile_within_the_limits(axis):
    omega = LIPM(com_height=0.23).omega
    offset = cmp_offset_bound(LIMITS, omega)[axis]
    assert offset > 0.0
    assert offset == pytest.approx(_offset_by_integration(LIMITS, omega, axis), rel=1e-4)
    # the momentum limit binds: a larger one moves the capture point further
    looser = FlywheelLimits(LIMITS.mass, LIMITS.inertia, LIMITS.max_torque, 1.0, LIMITS.max_angle)
    assert cmp_offset_bound(looser, omega)[axis] > offset


def test_the_flywheel_capture_bounds_contain_the_lipms_and_equal_them_without_a_flywheel():
    omega, mass = LIPM(com_height=0.23).omega, LIMITS.mass
    regions = capture_regions(
        2,
        omega=omega,
        sole=sole_box(0.1, 0.06),
        reach=LegLimits().rectangle(),
        first_swing=Side.LEFT,
        first_step_time=0.2,
        step_time=0.5,
    )
    with_flywheel = flywheel_regions(regions, cmp_offset_bound(LIMITS, omega))
    without = flywheel_regions(regions, cmp_offset_bound(LIMITS.without_flywheel(), omega))
    dcm = (0.01, -0.005)
    for angle in np.linspace(0.0, 2.0 * np.pi, 16, endpoint=False):
        for n in range(3):
            lipm = largest_impulse(regions[: n + 1], dcm, angle, mass=mass, omega=omega)
            bigger = largest_impulse(with_flywheel[: n + 1], dcm, angle, mass=mass, omega=omega)
            same = largest_impulse(without[: n + 1], dcm, angle, mass=mass, omega=omega)
            assert bigger > lipm + 1e-6
            assert same == lipm
    with pytest.raises(ConfigurationError, match="non-negative distances"):
        flywheel_regions(regions, (-0.01, 0.0))


def test_bad_limits_are_named():
    with pytest.raises(ConfigurationError, match="mass"):
        FlywheelLimits(0.0, 1.0, 1.0, 1.0, 1.0)
    with pytest.raises(ConfigurationError, match="max_torque"):
        FlywheelLimits(1.0, 1.0, -1.0, 1.0, 1.0)
    with pytest.raises(ConfigurationError, match="inertia"):
        FlywheelLimits(1.0, 0.0, 1.0, 1.0, 1.0)
