"""Paper M's closed-form CoM (eq. 6-18) and the analytic generator."""

import numpy as np
import pytest
from plans import arc_schedule

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import make_generator, rollout
from mpcwalk.generators.analytic import AnalyticGenerator
from mpcwalk.generators.closed_form_step import closed_form_step
from mpcwalk.models.lipm import LIPM

T, Z_C, R_DS = 0.5, 0.23, 0.2  # paper M, Table 1
OMEGA = LIPM(Z_C).omega
T_B, T_E = 0.5 * R_DS * T, T - 0.5 * R_DS * T
COMMANDS = {  # torso displacement per step (dx [m], dy [m], dyaw [rad]) at T = 0.5 s
    "straight": (0.05, 0.0, 0.0),  # 0.1 m/s
    "turning": (0.05, 0.0, np.deg2rad(10.0)),  # 0.1 m/s, 20 deg/s
    "sideways": (0.0, 0.05, 0.0),  # 0.1 m/s to the left
}


def random_steps(rng, n):
    """Random 2D boundary values, each (n, 2) in [m]."""
    return [rng.uniform(-0.1, 0.1, size=(n, 2)) for _ in range(3)]


def test_boundary_values_and_lipm_equation_table1():
    rng = np.random.default_rng(0)
    times = np.linspace(0.0, T, 2001)
    worst_bc, worst_lipm = 0.0, 0.0
    for x_t0, x_s, x_t1 in zip(*random_steps(rng, 50)):
        cf = closed_form_step(x_t0, x_s, x_t1, T, T_B, T_E, OMEGA)
        worst_bc = max(worst_bc, np.abs(cf.com(0.0) - x_t0).max(), np.abs(cf.com(T) - x_t1).max())
        residual = cf.com(times) - cf.com_acceleration(times) / OMEGA**2 - cf.zmp(times)
        worst_lipm = max(worst_lipm, np.abs(residual).max())
        # eq. 8: the ZMP reference passes through the waypoints.
        np.testing.assert_allclose(cf.zmp([0.0, T_B, T_E, T]), [x_t0, x_s, x_s, x_t1], atol=1e-15)
    assert worst_bc < 1e-12  # measured 2.8e-17
    assert worst_lipm < 1e-9  # measured 2.8e-17


def test_c1_continuity_at_single_support_limits():
    rng = np.random.default_rng(1)
    for x_t0, x_s, x_t1 in zip(*random_steps(rng, 50)):
        cf = closed_form_step(x_t0, x_s, x_t1, T, T_B, T_E, OMEGA)
        for t in (T_B, T_E):
            left, right = np.nextafter(t, -np.inf), t
            assert np.abs(cf.com(left) - cf.com(right)).max() < 1e-9
            assert np.abs(cf.com_velocity(left) - cf.com_velocity(right)).max() < 1e-9
        # The ZMP slope jumps there (from m_d1 to 0 and from 0 to m_d2) but
        # the acceleration stays continuous because c and p are.
        left_acc = cf.com_acceleration(np.nextafter(T_B, -np.inf))
        assert np.abs(left_acc - cf.com_acceleration(T_B)).max() < 1e-9


@pytest.mark.parametrize("h", [1e-3, 1e-4])
def test_derivatives_match_finite_differences(h):
    rng = np.random.default_rng(2)
    x_t0, x_s, x_t1 = (v[0] for v in random_steps(rng, 1))
    cf = closed_form_step(x_t0, x_s, x_t1, T, T_B, T_E, OMEGA)
    times = np.linspace(0.0, T, 401)
    away = np.min(np.abs(times[:, None] - np.array([0.0, T_B, T_E, T])[None]), axis=1) > 2 * h
    t = times[away]
    c_plus, c, c_minus = cf.com(t + h), cf.com(t), cf.com(t - h)
    vel_fd = (c_plus - c_minus) / (2 * h)
    acc_fd = (c_plus - 2 * c + c_minus) / h**2
    # Truncation h^2 / 6 |c'''| and h^2 / 12 |c''''| with |c^(n)| <= omega^n * scale,
    # plus rounding eps |c| / h^2.
    scale = 1.0  # [m], generous bound on |c - p| and its derivatives / omega^n
    tol_vel = h**2 / 6 * OMEGA**3 * scale + 1e-15 / h
    tol_acc = h**2 / 12 * OMEGA**4 * scale + 4e-16 / h**2
    assert np.abs(vel_fd - cf.com_velocity(t)).max() < tol_vel
    assert np.abs(acc_fd - cf.com_acceleration(t)).max() < tol_acc
    # LIPM equation with the finite-difference acceleration.
    assert np.abs(c - acc_fd / OMEGA**2 - cf.zmp(t)).max() < tol_acc / OMEGA**2


def test_random_timings_and_long_steps():
    rng = np.random.default_rng(3)
    for _ in range(30):
        step = rng.uniform(0.2, 12.0)  # up to paper A's 12 s steps: no overflow
        r_ds = rng.uniform(0.01, 0.95)
        omega = LIPM(rng.uniform(0.2, 1.0)).omega
        x_t0, x_s, x_t1 = (v[0] for v in random_steps(rng, 1))
        cf = closed_form_step(x_t0, x_s, x_t1, step, r_ds * step / 2, step - r_ds * step / 2, omega)
        times = np.linspace(0.0, step, 3001)
        assert np.all(np.isfinite(cf.com(times)))
        np.testing.assert_allclose(cf.com([0.0, step]), [x_t0, x_t1], atol=1e-12)
        residual = cf.com(times) - cf.com_acceleration(times) / omega**2 - cf.zmp(times)
        assert np.abs(residual).max() < 1e-9


def test_no_double_support_is_the_limit_of_short_ones():
    x_t0, x_s, x_t1 = np.array([0.0, 0.0]), np.array([0.03, -0.04]), np.array([0.05, 0.0])
    cf0 = closed_form_step(x_t0, x_s, x_t1, T, 0.0, T, OMEGA)
    eps = 1e-7
    cf_eps = closed_form_step(x_t0, x_s, x_t1, T, eps, T - eps, OMEGA)
    times = np.linspace(0.0, T, 501)
    assert np.abs(cf0.com(times) - cf_eps.com(times)).max() < 1e-6
    np.testing.assert_allclose(cf0.com([0.0, T]), [x_t0, x_t1], atol=1e-15)
    # The ZMP sits on the support foot for the whole step.
    inner = times[1:-1]
    np.testing.assert_allclose(cf0.zmp(inner), np.broadcast_to(x_s, (len(inner), 2)), atol=0)
    residual = cf0.com(times) - cf0.com_acceleration(times) / OMEGA**2 - cf0.zmp(times)
    assert np.abs(residual).max() < 1e-9
    # And the generator accepts r_ds = 0 schedules.
    out = rollout(AnalyticGenerator(), arc_schedule(COMMANDS["straight"], 4, r_ds=0.0))
    assert np.all(np.isfinite(out.com))


@pytest.mark.parametrize(
    "args, match",
    [
        ((0.0, 0.1, 0.2, 0.5, 0.3, 0.2, OMEGA), "t_b <= t_e"),
        ((0.0, 0.1, 0.2, -0.5, 0.0, 0.0, OMEGA), "T > 0"),
        ((0.0, 0.1, np.nan, 0.5, 0.05, 0.45, OMEGA), "non-finite"),
        ((np.zeros(2), np.zeros(3), 0.0, 0.5, 0.05, 0.45, OMEGA), "same shape|one shape"),
    ],
)
def test_bad_inputs_are_rejected(args, match):
    with pytest.raises(ConfigurationError, match=match):
        closed_form_step(*args)


@pytest.mark.parametrize("command", list(COMMANDS))
def test_generator_follows_paper_m_reference_inside_polygon(command):
    schedule = arc_schedule(COMMANDS[command], 20)
    out = rollout(make_generator("analytic", control_period=0.01), schedule)
    # The planned ZMP is the schedule's eq. 6-8 reference...
    assert np.abs(out.zmp - schedule.zmp_reference(out.times)).max() < 1e-9
    # ... which stays in the support polygon: min margin measured 0.0300 m (the
    # half foot width, at the support foot centre) for all three commands.
    assert support_margins(schedule, out.times, out.zmp).min() > 0.029
    # At rest above the feet midpoint before the first step and after the last.
    before, after = out.times < schedule.walk_start, out.times >= schedule.walk_end
    assert np.abs(out.com[before] - schedule.torso_waypoints[0]).max() < 1e-15
    assert np.abs(out.com[after] - schedule.torso_waypoints[-1]).max() < 1e-15
    assert np.abs(out.com_velocity[before | after]).max() == 0.0


def test_velocity_jumps_at_step_boundaries_as_in_the_paper():
    schedule = arc_schedule(COMMANDS["straight"], 6)
    gen = AnalyticGenerator()
    gen.reset(schedule)
    starts = schedule.walk_start + T * np.arange(7)
    at = gen.evaluate(starts)
    just_before = gen.evaluate(starts - 1e-12)
    # Positions and accelerations are continuous...
    assert np.abs(at[:, 0] - just_before[:, 0]).max() < 1e-9
    assert np.abs(at[:, 2] - just_before[:, 2]).max() < 1e-9
    # ... the velocity is not: each step is its own boundary value problem.
    # Measured: 0.203 m/s (mostly lateral) when the walk starts, 0.013 m/s at
    # the second step (the first step is half as long), 0.25 m/s at the stop.
    jumps = np.linalg.norm(at[:, 1] - just_before[:, 1], axis=1)
    assert jumps[0] > 0.15 and jumps[-1] > 0.15
    np.testing.assert_allclose(jumps[0], np.linalg.norm(gen.steps[0].com_velocity(0.0)), rtol=1e-9)
    # In steady walking consecutive steps mirror each other and the jump vanishes.
    assert jumps[2:-1].max() < 1e-9


def test_horizon_is_the_rest_of_the_step():
    schedule = arc_schedule(COMMANDS["turning"], 4)
    gen = AnalyticGenerator(control_period=0.01, horizon_time=None)
    assert gen.reset(schedule).horizon is None  # standing
    while gen.time < schedule.walk_start + 0.2 - 1e-9:
        out = gen.step()
    h = out.horizon
    assert h.times[-1] == pytest.approx(schedule.walk_start + T)
    assert len(h.times) == 30
    np.testing.assert_allclose(h.com, gen.evaluate(h.times)[:, 0])
    np.testing.assert_allclose(h.zmp, schedule.zmp_reference(h.times), atol=1e-12)
    assert AnalyticGenerator().reset(schedule).horizon is None  # default: no horizon


def test_matches_literal_eq_11_to_18():
    """The stable evaluation is the paper's formula, term by term."""
    rng = np.random.default_rng(4)
    times = np.linspace(0.0, T, 1001)[:, None]
    for x_t0, x_s, x_t1 in zip(*random_steps(rng, 20)):
        cf = closed_form_step(x_t0, x_s, x_t1, T, T_B, T_E, OMEGA)
        w = OMEGA
        m_d1, m_d2 = (x_s - x_t0) / T_B, (x_t1 - x_s) / (T - T_E)  # eq. 6-7
        k_d1 = -(m_d1 / w) * np.sinh(w * T_B)  # eq. 15
        k_d2 = (m_d2 / w) * np.sinh(w * (T - T_E))  # eq. 16
        C1 = (k_d2 - k_d1 * np.exp(-w * T)) / (np.exp(w * T) - np.exp(-w * T))  # eq. 17
        C2 = (k_d1 * np.exp(w * T) - k_d2) / (np.exp(w * T) - np.exp(-w * T))  # eq. 18
        np.testing.assert_allclose(
            [cf.C1, cf.C2, cf.k_d1, cf.k_d2], [C1, C2, k_d1, k_d2], rtol=1e-12, atol=1e-15
        )
        p = np.where(
            times < T_B, x_t0 + m_d1 * times, np.where(times < T_E, x_s, x_s + m_d2 * (times - T_E))
        )  # eq. 8
        c2 = np.where(
            times < T_B,
            -(m_d1 / w) * np.sinh(w * (times - T_B)),
            np.where(times < T_E, 0.0, -(m_d2 / w) * np.sinh(w * (times - T_E))),
        )  # eq. 13
        c = p + C1 * np.exp(w * times) + C2 * np.exp(-w * times) + c2  # eq. 11-12
        assert np.abs(cf.com(times[:, 0]) - c).max() < 1e-12


def test_scalar_fast_path_equals_vectorised_evaluation():
    schedule = arc_schedule(COMMANDS["turning"], 6)
    gen = AnalyticGenerator()
    gen.reset(schedule)
    times = np.linspace(-0.1, schedule.duration + 0.1, 1501)
    fast = np.array([gen.state_at(t) for t in times])
    np.testing.assert_allclose(fast, gen.evaluate(times), atol=1e-14)
