"""Linear MPC pattern generator (Wieber 2006) on 20-step walks."""

import functools

import numpy as np
import pytest
import qpsolvers
from conftest import walk_outputs
from plans import velocity_schedule as arc_schedule

from mpcwalk.exceptions import ConfigurationError, NoSolutionFound, SolverNotFound
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import make_generator
from mpcwalk.generators.mpc import MpcGenerator
from mpcwalk.models.com_state import ComState

COMMANDS = {  # (vx [m/s], vy [m/s], yaw rate [rad/s]) in the torso frame
    "straight": (0.1, 0.0, 0.0),
    "turning": (0.1, 0.0, np.deg2rad(20.0)),
    "sideways": (0.0, 0.1, 0.0),
}


@functools.cache
def schedule_of(name, nb_steps=20):
    return arc_schedule(COMMANDS[name], nb_steps)


def walk(generator, schedule, measured=None):
    """Outputs of a whole walk; ``measured(out)`` gives the next measurement."""
    return walk_outputs(generator, schedule, measured=measured)


@functools.cache
def default_walk(name):
    return walk(MpcGenerator(), schedule_of(name))


#: Executed ZMP margins are not constrained between samples; lower bounds
#: measured with the defaults (the sideways walk lags at the first instant of
#: single support, when the ZMP crosses 0.13 m in a 0.1 s double support).
EXECUTED_MARGIN = {"straight": 0.010, "turning": 0.010, "sideways": -0.005}  # [m]


def zmp_margins(schedule, outs):
    """Minimum ZMP margins [m]: over every planned horizon, and executed."""
    planned = min(support_margins(schedule, o.horizon.times, o.horizon.zmp).min() for o in outs[1:])
    times = np.array([o.time for o in outs])
    executed = support_margins(schedule, times, np.array([o.zmp for o in outs])).min()
    return planned, executed


@pytest.mark.parametrize("name", COMMANDS)
def test_planned_zmp_stays_in_the_support_polygon(name, record_property):
    schedule, outs = schedule_of(name), default_walk(name)
    assert all(o.solve.success for o in outs[1:])
    planned, executed = zmp_margins(schedule, outs)
    record_property("min_planned_zmp_margin_m", planned)
    record_property("min_executed_zmp_margin_m", executed)
    print(
        f"{name}: min ZMP margin planned {planned * 1e3:.2f} mm, executed {executed * 1e3:.2f} mm"
    )
    assert planned >= -1e-6
    assert executed >= EXECUTED_MARGIN[name]


@pytest.mark.parametrize("name", COMMANDS)
def test_next_tick_constraint_keeps_the_executed_zmp_inside(name, record_property):
    schedule = schedule_of(name)
    outs = walk(MpcGenerator(solver="daqp", constrain_next_tick=True), schedule)
    assert all(o.solve.success for o in outs[1:])
    planned, executed = zmp_margins(schedule, outs)
    record_property("min_executed_zmp_margin_m", executed)
    print(f"{name} (next tick constrained): executed {executed * 1e3:.2f} mm")
    assert planned >= -1e-6 and executed >= -1e-4  # measured -0.045 mm sideways


@pytest.mark.parametrize("name", COMMANDS)
def test_zmp_tracks_the_polygonal_reference_and_the_walk_ends_at_rest(name):
    schedule, outs = schedule_of(name), default_walk(name)
    times = np.array([o.time for o in outs])
    zmp = np.array([o.zmp for o in outs])
    error = np.linalg.norm(zmp - schedule.zmp_reference(times), axis=1)
    assert np.sqrt(np.mean(error**2)) < 0.009  # [m], measured 5-8 mm
    assert np.linalg.norm(outs[-1].com - schedule.torso_waypoints[-1]) < 0.005
    assert np.linalg.norm(outs[-1].com_velocity) < 0.02


@pytest.mark.parametrize("formulation", ["dense", "sparse"])
def test_feedback_of_the_output_matches_open_loop(formulation):
    schedule = schedule_of("turning", 6)
    open_loop = walk(MpcGenerator(formulation=formulation), schedule)
    closed = walk(MpcGenerator(formulation=formulation), schedule, measured=lambda o: o.state)
    com = np.array([o.com for o in open_loop])
    assert np.max(np.abs(np.array([o.com for o in closed]) - com)) < 1e-12
    # Position and velocity only: the generator keeps its own acceleration.
    no_acc = walk(
        MpcGenerator(formulation=formulation),
        schedule,
        measured=lambda o: ComState(o.com, o.com_velocity),
    )
    assert np.max(np.abs(np.array([o.com for o in no_acc]) - com)) < 1e-12


def test_warm_started_osqp_matches_cold_solvers():
    schedule = schedule_of("turning", 4)
    runs = {
        "osqp-direct": MpcGenerator(
            solver="osqp-direct", solver_settings=dict(eps_abs=1e-7, eps_rel=1e-7)
        ),
        "osqp": MpcGenerator(solver="osqp", solver_settings=dict(eps_abs=1e-7, eps_rel=1e-7)),
        "quadprog": MpcGenerator(solver="quadprog"),
    }
    outs, iterations = {}, {}
    for name, generator in runs.items():
        outs[name], iterations[name] = [generator.reset(schedule)], []
        while not generator.done:
            outs[name].append(generator.step())
            iterations[name].append(generator.last_result.iterations)
    com = {name: np.array([o.com for o in run]) for name, run in outs.items()}
    # Same OSQP stopping tolerance warm and cold; measured 3.0 and 0.9 um.
    assert np.max(np.abs(com["osqp-direct"] - com["quadprog"])) < 5e-6  # [m]
    assert np.max(np.abs(com["osqp"] - com["quadprog"])) < 5e-6
    # Vector-only updates on most ticks: the matrix changes with the polygons.
    ticks = len(outs["osqp-direct"]) - 1
    assert runs["osqp-direct"].qp.A_version < ticks / 3
    assert np.median(iterations["osqp-direct"]) < np.median(iterations["osqp"])


def test_sparse_and_dense_generators_agree():
    schedule = schedule_of("sideways", 4)
    dense = walk(MpcGenerator(solver="daqp"), schedule)
    sparse = walk(
        MpcGenerator(
            solver="osqp-direct",
            formulation="sparse",
            solver_settings=dict(eps_abs=1e-8, eps_rel=1e-8),
        ),
        schedule,
    )
    gap = np.max(np.abs(np.array([o.com for o in dense]) - np.array([o.com for o in sparse])))
    assert gap < 1e-6


@pytest.mark.parametrize("solver", ["osqp-direct", "daqp"])
def test_failed_solve_falls_back_on_the_previous_plan(solver):
    schedule = schedule_of("straight", 6)
    generator = MpcGenerator(solver=solver, terminal_dcm=True, max_fallback_ticks=3)
    out = generator.reset(schedule)
    for _ in range(150):
        out = generator.step()
    # A measured CoM 0.3 m outside the feet cannot be captured: infeasible.
    bad = ComState(out.com + [0.0, 0.3], out.com_velocity)
    failed = [generator.step(bad) for _ in range(2)]
    for count, o in enumerate(failed, start=1):
        assert not o.solve.success and o.solve.fallback
        assert o.solve.consecutive_failures == count
    # The previous plan went on: same reference as without the bad measurement.
    twin = MpcGenerator(solver=solver, terminal_dcm=True)
    twin.reset(schedule)
    for _ in range(152):
        expected = twin.step()
    assert np.linalg.norm(failed[-1].com - expected.com) < 1e-4
    rest = []
    while not generator.done:
        rest.append(generator.step())
    assert all(o.solve.success for o in rest)
    assert rest[0].solve.consecutive_failures == 0
    assert np.linalg.norm(rest[-1].com - schedule.torso_waypoints[-1]) < 0.005


def test_too_many_failures_raise_no_solution_found():
    schedule = schedule_of("straight", 4)
    generator = MpcGenerator(solver="daqp", terminal_dcm=True, max_fallback_ticks=2)
    out = generator.reset(schedule)
    bad = ComState(out.com + [0.0, 0.3], [0.0, 0.0])
    generator.step(bad)
    generator.step(bad)
    with pytest.raises(NoSolutionFound, match="'daqp' found no solution") as info:
        generator.step(bad)
    assert isinstance(info.value.problem, qpsolvers.Problem)


def test_unconstrained_configuration_for_the_preview_comparison():
    schedule = schedule_of("straight", 2)
    kwargs = dict(control_period=0.005, sampling_period=0.005, horizon=320, constrained=False)
    exact = MpcGenerator(solver="kkt", **kwargs)
    osqp = MpcGenerator(solver="osqp-direct", **kwargs)
    assert exact.qp.N == 320 and exact.qp.m == 0
    a, b = exact.reset(schedule), osqp.reset(schedule)
    for _ in range(100):
        a, b = exact.step(), osqp.step()
        assert a.solve.success and b.solve.success
    assert np.linalg.norm(a.com - b.com) < 1e-7


def test_configuration_errors_are_named():
    with pytest.raises(SolverNotFound, match="Unknown solver 'gurobo'; available: osqp-direct"):
        MpcGenerator(solver="gurobo")
    with pytest.raises(ConfigurationError, match="quadprog.*formulation='dense'"):
        MpcGenerator(solver="quadprog", formulation="sparse")
    with pytest.raises(ConfigurationError, match="Unknown MPC parameter.*horizon_time"):
        MpcGenerator(horizon_time=1.6)
    with pytest.raises(ConfigurationError, match="max_fallback_ticks"):
        MpcGenerator(max_fallback_ticks=-1)
    with pytest.raises(ConfigurationError, match="solves QPs without inequality"):
        MpcGenerator(solver="kkt")
    generator = make_generator("mpc", solver="daqp", horizon=20)
    assert isinstance(generator, MpcGenerator) and generator.parameters.horizon == 20


@pytest.mark.parametrize("com_height", [0.23, 0.68, 1.0925])
def test_default_mpc_is_stable_for_small_and_tall_robots(com_height):
    """A plain finite horizon lets a tall robot's CoM diverge (1e14 m measured at
    z_c = 1.09 m without the velocity term); the defaults must not."""
    from mpcwalk.models.lipm import LIPM

    scale = com_height / 0.23
    schedule = arc_schedule(
        (0.1 * scale, 0.0, 0.2), 10, step_duration=0.5 * np.sqrt(scale), half_width=0.04 * scale
    )
    # Unconstrained: the small test feet would not hold the tall robot's steps, and the
    # instability is one of the receding horizon itself.
    outs = walk(MpcGenerator(lipm=LIPM(com_height), constrained=False), schedule)
    com = np.array([o.com for o in outs])
    assert np.all(np.isfinite(com))
    np.testing.assert_allclose(com[-1], schedule.torso_waypoints[-1], atol=0.01 * scale)
    assert all(o.solve.success for o in outs[1:])
    unstable = MpcGenerator(lipm=LIPM(com_height), constrained=False, velocity_weight=0.0)
    if com_height > 1.0:
        # the failure the default guards against: the plans diverge until their jerks are
        # absurd, and the solve boundary refuses them (no CoM of 1e14 m reaches the robot)
        from mpcwalk.exceptions import NoSolutionFound

        with pytest.raises(NoSolutionFound, match="implausible solution: CoM jerk"):
            walk(unstable, schedule)
