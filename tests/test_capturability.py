"""N-step capture regions of the LIPM on rectangular feet."""

import math

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.capturability import (
    Box,
    capture_region,
    capture_regions,
    largest_impulse,
    sole_box,
)
from mpcwalk.footsteps.footstep import Side
from mpcwalk.footsteps.leg_limits import LegLimits

OMEGA = math.sqrt(9.81 / 0.23)
SOLE = sole_box(0.10, 0.06)
REACH = LegLimits(half_stance_width=0.04).rectangle()


def region(n, first_swing=Side.LEFT, first=0.25, later=0.5):
    return capture_region(
        n,
        omega=OMEGA,
        sole=SOLE,
        reach=REACH,
        first_swing=first_swing,
        first_step_time=first,
        step_time=later,
    )


def test_forward_regions_follow_koolens_recursion():
    """Koolen 2012, eq. for the disc foot along one axis: d_N = (d_{N-1} - r + l) e^{-w t} + r."""
    a, reach = 0.05, REACH.x_max
    d = a
    for n in range(1, 4):
        d = (d - a + reach) * math.exp(-OMEGA * 0.4) + a
        assert region(n, first=0.4, later=0.4).x_high == pytest.approx(d, abs=1e-12)
    assert region(0) == SOLE


def _captured(dcm0: float, reach: float, first: float, a: float = 0.05) -> bool:
    """Integrate the 1-D DCM with the ZMP at the front edge, step to ``reach`` at ``first``,
    then hold the ZMP at the new front edge: captured if the DCM stops diverging."""
    dt, xi, foot = 1e-5, dcm0, 0.0
    for k in range(int(2.0 / dt)):
        if abs(k * dt - first) < dt / 2:
            foot = reach
        zmp = foot + a
        xi += dt * OMEGA * (xi - zmp)
        if xi - foot > 1.0:
            return False
    return xi - foot <= a + 1e-6


@pytest.mark.parametrize("first", [0.1, 0.25, 0.4])
def test_a_dcm_just_inside_the_one_step_region_is_captured_and_just_outside_is_not(first):
    edge = region(1, first=first).x_high
    assert _captured(edge - 1e-4, REACH.x_max, first)
    assert not _captured(edge + 1e-4, REACH.x_max, first)


def test_a_push_towards_the_stance_leg_needs_the_other_leg():
    """Right foot standing, left foot swinging: the left foot cannot land right of the right
    one (no cross-over), so its step makes a push to the right worse; the right foot's step
    after it wins some back, and beats standing still only when it comes soon and reaches
    far (on the small humanoid's legs and timing it does not: the LIPM then says that only
    the ankle holds such a push, and no controller should be asked for more)."""
    options = dict(omega=OMEGA, sole=SOLE, first_swing=Side.LEFT, first_step_time=0.25)
    zero, one, two = capture_regions(2, reach=REACH, step_time=0.5, **options)
    assert one.y_low > zero.y_low > two.y_low - 0.02  # the forced left landing hurts
    assert two.y_low < one.y_low  # the right foot steps back out
    right = -math.pi / 2
    bounds = [
        largest_impulse(r, np.zeros(2), right, mass=2.0, omega=OMEGA) for r in (zero, one, two)
    ]
    assert bounds[1] < bounds[2] < bounds[0]
    best = largest_impulse([zero, one, two], np.zeros(2), right, mass=2.0, omega=OMEGA)
    assert best == pytest.approx(bounds[0])
    wide = LegLimits(half_stance_width=0.04, max_step_lateral=0.3).rectangle()
    zero, _, two = capture_regions(2, reach=wide, step_time=0.2, **options)
    assert two.y_low < zero.y_low
    # pushed to the left, the first step is the one that helps
    left = largest_impulse([zero, one], np.zeros(2), math.pi / 2, mass=2.0, omega=OMEGA)
    assert left > largest_impulse(zero, np.zeros(2), math.pi / 2, mass=2.0, omega=OMEGA)


def test_an_earlier_landing_captures_more():
    """What step timing adaptation buys: the same step 0.1 s earlier."""
    assert region(1, first=0.15).x_high > region(1, first=0.25).x_high


def test_impulse_is_mass_omega_times_the_distance_to_the_border():
    box = Box(-0.1, 0.2, -0.05, 0.05)
    assert largest_impulse(box, [0.0, 0.0], 0.0, mass=2.0, omega=5.0) == pytest.approx(2.0)
    assert largest_impulse(box, [0.0, 0.0], math.pi, mass=2.0, omega=5.0) == pytest.approx(1.0)
    diagonal = largest_impulse(box, [0.0, 0.0], math.pi / 4, mass=1.0, omega=1.0)
    assert diagonal == pytest.approx(0.05 * math.sqrt(2.0))
    assert largest_impulse(box, [0.3, 0.0], 0.0, mass=2.0, omega=5.0) == 0.0


def test_bad_arguments_are_named():
    with pytest.raises(ConfigurationError, match="nb_steps"):
        region(-1)
    with pytest.raises(ConfigurationError, match="first_step_time"):
        region(1, first=-0.1)
    with pytest.raises(ConfigurationError, match="positive mass"):
        largest_impulse(SOLE, [0, 0], 0.0, mass=0.0, omega=1.0)
