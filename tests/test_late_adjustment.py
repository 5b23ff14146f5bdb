"""Late step adjustment: the bound on a landing change, the quintic re-plan of the swing, the
box in the footstep QP, and a late push that the frozen landing does not recover."""

import numpy as np
import pytest
from plans import velocity_schedule

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.swing_foot import SwingFootTrajectory
from mpcwalk.gait.swing_retarget import (
    PEAK_ACCELERATION,
    PEAK_VELOCITY,
    QuinticRetarget,
    SwingLimits,
)
from mpcwalk.generators import make_generator
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM


def test_the_bound_follows_the_time_left_and_the_limits():
    """Velocity-bound early (linear in the time left), acceleration-bound late (quadratic),
    zero at touch-down; the gait's rule on bioloid-like's numbers."""
    limits = SwingLimits(velocity=1.5, acceleration=23.0)
    assert limits.landing_change_bound(0.0) == 0.0
    assert limits.landing_change_bound(-0.1) == 0.0
    assert limits.landing_change_bound(1.0) == pytest.approx(1.5 / PEAK_VELOCITY)
    assert limits.landing_change_bound(0.05) == pytest.approx(23.0 * 0.05**2 / PEAK_ACCELERATION)
    np.testing.assert_allclose(
        limits.landing_change_bound(np.array([0.05, 1.0])),
        [23.0 * 0.05**2 / PEAK_ACCELERATION, 1.5 / PEAK_VELOCITY],
    )
    gait = SwingLimits.for_gait(single_support=0.4, longest_swing=0.16)
    assert gait.velocity == pytest.approx(1.5)
    assert gait.acceleration == pytest.approx(23.09, abs=0.01)
    assert gait.landing_change_bound(0.1) == pytest.approx(0.04, abs=1e-3)
    with pytest.raises(ConfigurationError, match="SwingLimits.velocity must be a positive"):
        SwingLimits(velocity=0.0, acceleration=1.0)


def test_the_peaks_of_the_quintic_move_are_the_bound_s():
    """A quintic from rest to a landing moved by the bound stays within the limits and
    touches one of them (the bound is tight)."""
    limits = SwingLimits(velocity=1.5, acceleration=23.0)
    for tau in (0.02, 0.075, 0.2, 0.4):
        delta = limits.landing_change_bound(tau)
        quintic = QuinticRetarget(0.0, tau, np.zeros(1), np.zeros(1), np.zeros(1), [delta])
        states = [quintic.evaluate(t) for t in np.linspace(0.0, tau, 2001)]
        velocity = max(abs(float(v[0])) for _, v, _ in states)
        acceleration = max(abs(float(a[0])) for _, _, a in states)
        assert velocity <= limits.velocity * (1 + 1e-9)
        assert acceleration <= limits.acceleration * (1 + 1e-6)
        assert max(velocity / limits.velocity, acceleration / limits.acceleration) > 0.999


def test_the_quintic_meets_its_boundary_conditions():
    p0, v0, a0, p1 = np.array([0.1, -0.2]), np.array([0.5, 0.1]), np.array([-3.0, 2.0]), [0.3, 0.0]
    quintic = QuinticRetarget(1.0, 0.2, p0, v0, a0, p1)
    start, end = quintic.evaluate(1.0), quintic.evaluate(1.2)
    for got, want in zip(start, (p0, v0, a0)):
        np.testing.assert_allclose(got, want, atol=1e-12)
    for got, want in zip(end, (p1, np.zeros(2), np.zeros(2))):
        np.testing.assert_allclose(got, want, atol=1e-9)
    with pytest.raises(ConfigurationError, match="duration must be a positive"):
        QuinticRetarget(0.0, 0.0, p0, v0, a0, p1)


def test_a_retargeted_swing_is_c1_and_within_the_limits():
    """Step 2's landing moved forward by the bound 0.1 s before touch-down: the swing foot's
    position and velocity do not jump at the re-plan, it lands on the new landing at rest, and
    the move adds no more than the limits to the nominal swing (by finite differences)."""
    schedule = velocity_schedule((0.1, 0.0, 0.0), 6)
    trajectory = SwingFootTrajectory(schedule)
    k = 2
    landing_time = schedule.walk_start + k * schedule.step_duration + schedule.t_e
    t0 = landing_time - 0.1
    side = schedule.plan.steps[k].side
    limits = SwingLimits.for_gait(single_support=schedule.t_e - schedule.t_b, longest_swing=0.16)
    delta = limits.landing_change_bound(0.1)
    steps = list(schedule.plan.steps)
    steps[k] = steps[k].moved(position=steps[k].position + np.array([delta, 0.0, 0.0]))
    moved = SwingFootTrajectory(schedule.with_steps(steps))
    dt = 1e-5
    foot = trajectory.foot_poses(t0)[side]
    before = trajectory.foot_poses(t0 - dt)[side]
    acceleration = (foot.linear_velocity - before.linear_velocity) / dt
    moved.restart_swing(t0, foot, acceleration)
    after = moved.foot_poses(t0)[side]
    np.testing.assert_allclose(after.position, foot.position, atol=1e-12)
    np.testing.assert_allclose(after.linear_velocity, foot.linear_velocity, atol=1e-9)
    landed = moved.foot_poses(landing_time - 1e-9)[side]
    np.testing.assert_allclose(landed.position[:2], steps[k].position[:2], atol=1e-6)
    np.testing.assert_allclose(landed.linear_velocity[:2], 0.0, atol=1e-5)
    times = np.linspace(t0, landing_time - 1e-6, 400)
    old = np.array([trajectory.foot_poses(t)[side].linear_velocity[0] for t in times])
    new = np.array([moved.foot_poses(t)[side].linear_velocity[0] for t in times])
    assert np.max(np.abs(new - old)) <= limits.velocity + 0.05  # the move's share, + the
    assert np.max(np.abs(new)) > 0.0  # cosine's and the quintic's difference at rest
    acc_old, acc_new = np.gradient(old, times), np.gradient(new, times)
    assert np.max(np.abs(acc_new - acc_old)) <= limits.acceleration * 1.5


def _swing_landing_moves(late: bool):
    """Largest move of step 2's published landing in its last 0.1 s, with a forward kick of
    0.3 m/s 70 ms before its touch-down."""
    schedule = velocity_schedule((0.1, 0.0, 0.0), 6)
    gen = make_generator("mpc-steps", lipm=LIPM(com_height=0.23), late_adjustment=late)
    gen.reset(schedule, ComState([0.0, 0.0]))
    k = 2
    landing_time = schedule.walk_start + k * schedule.step_duration + schedule.t_e
    start = gen.schedule.plan.steps[k].position[:2].copy()
    published, kicked = [], False
    while gen.time < landing_time - 1e-9:
        measured = None
        if not kicked and gen.time >= landing_time - 0.07 - 1e-9:
            state = gen._state
            measured = ComState(state[0], state[1] + np.array([0.3, 0.0]), state[2])
            kicked = True
        out = gen.step(measured)
        if out.schedule is not None:
            published.append((out.time, out.schedule.plan.steps[k].position[:2].copy()))
    return gen, start, published, landing_time


def test_late_landings_move_within_the_box_and_frozen_ones_do_not():
    frozen, start, published, landing_time = _swing_landing_moves(late=False)
    assert frozen.freeze_before_landing == 0.1
    late_moves = [p for t, p in published if t > landing_time - 0.1]
    assert all(np.allclose(p, start, atol=2e-3) for p in late_moves)  # nothing late moves
    late, start, published, landing_time = _swing_landing_moves(late=True)
    assert late.freeze_before_landing == pytest.approx(0.02)
    assert late.late_adjustment
    limits = SwingLimits.for_gait(single_support=0.4, longest_swing=0.16)
    previous, moved = None, 0.0
    for t, position in published:
        if previous is not None and t > landing_time - 0.1:
            change = np.abs(position - previous)
            assert np.all(change <= limits.landing_change_bound(landing_time - t) + 1e-6)
            moved = max(moved, float(change[0]))
        previous = position
    assert moved > 0.002  # the kick moved the landing forward late


@pytest.mark.slow
def test_a_late_forward_push_is_recovered_only_by_the_late_adjustment(record_property):
    """bioloid-like stepping in place, a 0.6 N s forward torso push at 3/4 of the third
    step (the push-map's cell 0 deg, phase 0.75): ``mpc-steps`` (landing frozen 0.1 s before
    touch-down) falls, ``mpc-late`` walks on."""
    from mpcwalk.experiments.survival import survived
    from mpcwalk.walking.runner import run_walk
    from mpcwalk.walking.specification import WalkSpec

    start = 1.0 + 2.75 * 0.5
    results = {}
    for controller in ("mpc-steps", "mpc-late"):
        spec = WalkSpec.build(
            "bioloid-like",
            controller=controller,
            command=(0.0, 0.0, 0.0),
            nb_steps=5,
            control_period=0.01,
            pushes=((start, 0.1, 6.0, 0.0, 0.0),),
            seed=0,
        )
        results[controller] = survived(run_walk(spec))
    record_property("survived", results)
    assert results == {"mpc-steps": False, "mpc-late": True}


def test_a_bad_late_adjustment_flag_is_a_named_error():
    with pytest.raises(ConfigurationError, match="late_adjustment must be True or False"):
        make_generator("mpc-steps", late_adjustment="yes")
    with pytest.raises(ConfigurationError, match="SwingLimits.acceleration"):
        make_generator("mpc-steps", late_adjustment=True, swing_limits=(1.0, -1.0))


def test_the_box_rows_exist_only_with_the_late_adjustment():
    """Without late adjustment the QP has no box rows (the walks stay as they were)."""
    schedule = velocity_schedule((0.1, 0.0, 0.0), 4)
    gens = {}
    for late in (False, True):
        gen = make_generator("mpc-steps", lipm=LIPM(com_height=0.23), late_adjustment=late)
        gen.reset(schedule, ComState([0.0, 0.0]))
        for _ in range(150):
            gen.step()
        gens[late] = gen.qp.m
    assert gens[True] == gens[False] + 4 * 3  # three landings in the 1.6 s horizon, 4 rows each
