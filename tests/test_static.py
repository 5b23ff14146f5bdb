"""Paper A's static gait as a CoM generator."""

import numpy as np
import pytest
from plans import arc_schedule

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import make_generator, rollout
from mpcwalk.generators.static import StaticGenerator, quintic

COMMANDS = {  # torso displacement per step (dx [m], dy [m], dyaw [rad])
    "straight": (0.05, 0.0, 0.0),  # 0.1 m/s at T = 0.5 s
    "turning": (0.05, 0.0, np.deg2rad(10.0)),  # 20 deg/s at T = 0.5 s
    "sideways": (0.0, 0.05, 0.0),
}
SLOW = dict(step_duration=4.0, r_ds=0.5)  # 2 s of double support per step


def test_quintic_boundary_conditions_and_derivatives():
    s, ds, dds = quintic(np.array([0.0, 1.0]))
    np.testing.assert_array_equal(s, [0.0, 1.0])
    np.testing.assert_array_equal(ds, [0.0, 0.0])
    np.testing.assert_array_equal(dds, [0.0, 0.0])
    h = 1e-3
    tau = np.linspace(0.01, 0.99, 99)
    s, ds, dds = quintic(tau)
    sp, _, _ = quintic(tau + h)
    sm, _, _ = quintic(tau - h)
    # Central differences: truncation h^2/6 max|s'''| (= 60) and h^2/12 max|s''''|
    # (= 360), plus rounding of order 1e-14 / h (resp. / h^2).
    assert np.abs((sp - sm) / (2 * h) - ds).max() < h**2 / 6 * 60 + 1e-14 / h
    assert np.abs((sp - 2 * s + sm) / h**2 - dds).max() < h**2 / 12 * 360 + 1e-14 / h**2
    assert np.all(np.diff(s) > 0)  # monotonic: the CoM never backs up


@pytest.mark.parametrize("command", list(COMMANDS))
def test_com_over_support_foot_and_inside_polygon_when_slow(command):
    schedule = arc_schedule(COMMANDS[command], 20, **SLOW)
    gen = make_generator("static", control_period=0.01)
    out = rollout(gen, schedule)
    single = schedule.is_single_support(out.times)
    assert single.sum() > 20 * 150
    # Above the support foot centre throughout every single support, at rest.
    assert np.abs(out.com[single] - schedule.support_center(out.times[single])).max() < 1e-9
    assert np.abs(out.com_velocity[single]).max() < 1e-9
    # CoM projection inside the support polygon at all times: min margin
    # measured 0.0300 m (half the foot width) for all three commands.
    assert support_margins(schedule, out.times, out.com).min() > 0.029
    # Slow enough that the ZMP stays inside too: measured 0.0286 (straight),
    # 0.0285 (turning), 0.0269 m (sideways).
    assert support_margins(schedule, out.times, out.zmp).min() > 0.02
    # Starts at rest between the feet and ends there.
    np.testing.assert_allclose(out.com[0], schedule.torso_waypoints[0], atol=1e-15)
    np.testing.assert_allclose(out.com[-1], schedule.torso_waypoints[-1], atol=1e-12)
    # ZMP of the LIPM.
    np.testing.assert_allclose(
        out.zmp, out.com - out.com_acceleration / gen.lipm.omega**2, atol=1e-15
    )


def test_shifts_are_quintic_between_the_support_feet():
    schedule = arc_schedule(COMMANDS["straight"], 4, **SLOW)
    gen = StaticGenerator()
    gen.reset(schedule)
    xs, T = schedule.support_positions, schedule.step_duration
    # Double support between the single supports of steps 1 and 2.
    start = schedule.walk_start + T + schedule.t_e
    end = schedule.walk_start + 2 * T + schedule.t_b
    ends = gen.evaluate([start, end, np.nextafter(end, -np.inf)])
    np.testing.assert_allclose(ends[0, 0], xs[1], atol=1e-15)
    np.testing.assert_allclose(ends[1, 0], xs[2], atol=1e-15)
    assert np.abs(ends[:, 1:]).max() < 1e-9  # zero velocity and acceleration at both ends
    mid = gen.evaluate([0.5 * (start + end)])[0]
    np.testing.assert_allclose(mid[0], 0.5 * (xs[1] + xs[2]), atol=1e-15)
    # Peak speed of the quintic: 15/8 distance / duration.
    peak_speed = 1.875 * np.linalg.norm(xs[2] - xs[1]) / (end - start)
    np.testing.assert_allclose(np.linalg.norm(mid[1]), peak_speed)


@pytest.mark.parametrize("command", list(COMMANDS))
def test_zmp_leaves_polygon_at_paper_m_speed(command):
    """The static gait's limit: with T = 0.5 s and r_ds = 0.2 the shifts take
    0.1 s and the ZMP is thrown far outside (measured min margins -1.22 m
    straight, -1.27 m turning, -2.39 m sideways), while the CoM projection
    itself stays inside (0.030 m)."""
    schedule = arc_schedule(COMMANDS[command], 20)
    out = rollout(StaticGenerator(control_period=0.01), schedule)
    assert support_margins(schedule, out.times, out.com).min() > 0.029
    assert support_margins(schedule, out.times, out.zmp).min() < -1.0


def test_no_double_support_is_rejected():
    schedule = arc_schedule(COMMANDS["straight"], 4, r_ds=0.0)
    with pytest.raises(ConfigurationError, match="double_support_ratio > 0"):
        StaticGenerator().reset(schedule)


def test_horizon_and_open_loop():
    schedule = arc_schedule(COMMANDS["turning"], 3, **SLOW)
    gen = StaticGenerator(control_period=0.01, horizon_time=0.5)
    first = rollout(gen, schedule)
    # Measured states are ignored (open loop).
    again = rollout(StaticGenerator(control_period=0.01), schedule, feedback=True)
    np.testing.assert_array_equal(first.com, again.com)
    gen.reset(schedule)
    out = gen.step()
    assert len(out.horizon.times) == 50
    np.testing.assert_allclose(out.horizon.com, gen.evaluate(out.horizon.times)[:, 0])


@pytest.mark.parametrize("name", ["static", "analytic"])
@pytest.mark.parametrize("horizon_time", [-0.1, float("nan"), "1"])
def test_closed_forms_refuse_a_bad_horizon_time(name, horizon_time):
    with pytest.raises(ConfigurationError, match=r"horizon_time must be a number >= 0 s, got"):
        make_generator(name, horizon_time=horizon_time)
