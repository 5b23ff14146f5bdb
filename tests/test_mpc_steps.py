"""Footstep-adaptive MPC (Herdt et al. 2010): undisturbed walks, pushes, reachability."""

import dataclasses
import functools

import numpy as np
import pytest
from plans import velocity_schedule

from mpcwalk.exceptions import (
    ConfigurationError,
    InfeasibleStep,
    NoSolutionFound,
    NotReset,
    SolverNotFound,
)
from mpcwalk.footsteps import FootGeometry, Footstep, FootstepPlan, LegLimits, ReachabilityRectangle
from mpcwalk.footsteps.footstep import wrap_angle
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import generator_names, make_generator, rollout
from mpcwalk.generators.mpc import MpcGenerator
from mpcwalk.generators.mpc_steps import FootstepMpcGenerator
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM
from mpcwalk.models.support_polygon import SupportPolygon, foot_rectangle
from mpcwalk.qp.footstep_parameters import blended_rectangles

LIPM_SMALL = LIPM(com_height=0.23)  # bioloid-like
#: Push time: middle of step 2's single support, the right foot swinging, the left supporting.
PUSH_TIME = 2.2  # [s]


@functools.cache
def straight(nb_steps=10):
    return velocity_schedule((0.1, 0.0, 0.0), nb_steps)


@functools.cache
def turning(nb_steps=10):
    return velocity_schedule((0.1, 0.0, np.deg2rad(20.0)), nb_steps)


def generator(**options):
    return FootstepMpcGenerator(lipm=LIPM_SMALL, **options)


def deviations(schedule, nominal):
    """Footstep moves from the plan, shape (nb_steps, 2), in [m]."""
    return np.array([a.xy - b.xy for a, b in zip(schedule.plan.steps, nominal.plan.steps)])


def pushed_walk(gen, kick, schedule, push_time=PUSH_TIME):
    """Closed loop on a perfect LIPM plant pushed at ``push_time``: the plant's CoM velocity
    jumps by ``kick`` [m/s]; every tick the generator measures the plant, and the plant
    follows the jerk the generator applied (also when it falls back on its previous plan,
    which ignores the measurement).

    Returns:
        ``(outputs, error)``: the plant states as outputs (same solve reports), and the
        exception that stopped the walk or None.
    """
    cart = CartTable(gen.lipm, gen.control_period)
    out = gen.reset(schedule)
    plant, outs = out.state.as_cart_table(), [out]
    while not gen.done:
        if abs(gen.time - push_time) < 1e-9:
            plant[1] += kick
        try:
            out = gen.step(ComState(plant[0], plant[1], plant[2]))
        except NoSolutionFound as error:
            return outs, error
        if out.solve.success:  # the generator started from the plant
            plant = np.vstack([out.com, out.com_velocity, out.com_acceleration])
        else:  # same acceleration on both sides: the jerk is its change
            jerk = (out.com_acceleration - plant[2]) / gen.control_period
            plant = cart.integrate(plant, jerk, gen.control_period)
        zmp = plant[0] - plant[2] / gen.lipm.omega**2
        outs.append(
            dataclasses.replace(
                out, com=plant[0], com_velocity=plant[1], com_acceleration=plant[2], zmp=zmp
            )
        )
    return outs, None


def executed_margins(schedule, outs):
    times = np.array([o.time for o in outs])
    return support_margins(schedule, times, np.array([o.zmp for o in outs]))


#: name: (schedule, largest footstep move [m], smallest executed ZMP margin [m], most
#: schedules published). Measured: 1.7 mm, 25.8 mm, 3 straight; 8.6 mm, 25.4 mm, 32 turning
#: (one foot lands 5 mm short, the velocity cost against the plan's turning geometry).
UNDISTURBED = {"straight": (straight, 0.005, 0.015, 5), "turning": (turning, 0.01, 0.015, 40)}


@pytest.mark.parametrize("name", UNDISTURBED)
def test_undisturbed_walk_steps_on_the_plan(name, record_property):
    make_schedule, max_move, min_margin, max_publications = UNDISTURBED[name]
    schedule = make_schedule()
    gen = generator()
    run = rollout(gen, schedule)
    assert run.nb_failures == 0
    moved = np.linalg.norm(deviations(gen.schedule, schedule), axis=1)
    margin = support_margins(gen.schedule, run.times, run.zmp).min()
    record_property("max_footstep_move_m", float(moved.max()))
    record_property("min_executed_zmp_margin_m", float(margin))
    print(
        f"{name}: footsteps within {moved.max() * 1e3:.2f} mm of the plan, executed ZMP "
        f"margin >= {margin * 1e3:.2f} mm, {gen.nb_publications} schedules published"
    )
    assert moved.max() < max_move
    assert margin > min_margin  # the ZMP is pulled to the foot centres
    assert gen.nb_publications <= max_publications  # only moves beyond 1 mm are published
    # Sides, yaws and timing are the plan's.
    for new, planned in zip(gen.schedule.plan.steps, schedule.plan.steps):
        assert new.side is planned.side and new.yaw == planned.yaw
    assert gen.schedule.plan.timing == schedule.plan.timing


def test_the_grid_of_samples_does_not_slide():
    gen = generator()
    gen.reset(straight())
    times = [gen.qp.sample_times_at(t) for t in (0.0, 0.01, 0.04, 0.05, 0.06)]
    np.testing.assert_allclose(times[0][:3], [0.05, 0.10, 0.15])
    np.testing.assert_allclose(times[1], times[0])
    np.testing.assert_allclose(times[2], times[0])
    np.testing.assert_allclose(times[3][0], 0.10)
    np.testing.assert_allclose(times[4], times[3])


def test_same_walk_as_the_fixed_mpc_when_footsteps_are_pinned():
    """With a huge footstep weight the steps stay on the plan and the ZMP in the feet: the
    plan differs from the fixed-footstep MPC only by its cost (centring vs polygonal
    reference), so compare the executed CoM at the step boundaries."""
    schedule = straight(6)
    pinned = rollout(generator(footstep_weight=1e9), schedule)
    fixed = rollout(MpcGenerator(lipm=LIPM_SMALL), schedule)
    assert pinned.nb_failures == fixed.nb_failures == 0
    gap = np.abs(pinned.com - fixed.com).max()
    print(f"CoM gap to the fixed-footstep MPC: {gap * 1e3:.2f} mm")
    assert gap < 0.01


@pytest.mark.parametrize(
    "kick, axis, low, high",
    [
        ((0.0, -0.2), 1, -0.061, -0.04),  # outward for the swinging right foot: at the reach limit
        ((0.0, -0.15), 1, -0.04, -0.01),  # measured -22 mm
        ((0.0, -0.1), 1, -0.01, 0.0),  # measured -5.5 mm: the ZMP in the foot takes most
        ((0.3, 0.0), 0, 0.02, 0.031),  # forward: up to the reach limit (0.08 - 0.05 m)
        ((-0.2, 0.0), 0, -0.05, -0.02),  # backward: measured -35 mm (limit -0.04 - 0.05 m)
    ],
)
def test_a_push_moves_the_next_footstep_its_way(kick, axis, low, high, record_property):
    schedule = straight()
    gen = generator()
    outs, error = pushed_walk(gen, kick, schedule)
    assert error is None
    assert sum(not o.solve.success for o in outs[1:]) == 0
    move = deviations(gen.schedule, schedule)[2]  # step 2 swings during the push
    margin = executed_margins(gen.schedule, outs).min()
    record_property("step_move_m", move.tolist())
    record_property("min_executed_zmp_margin_m", float(margin))
    print(
        f"kick {kick} m/s: step 2 moved by {np.round(move * 1e3, 1)} mm, executed ZMP "
        f"margin {margin * 1e3:.2f} mm"
    )
    assert low <= move[axis] <= high
    assert abs(move[1 - axis]) < 0.005
    assert margin > -1e-3  # measured >= -0.04 mm (constrained at mid-interval too)
    final_stance = gen.schedule.torso_waypoints[-1]
    assert np.linalg.norm(outs[-1].com - final_stance) < 0.005  # it stops over its feet


@pytest.mark.parametrize(
    "kick, fixed_fails, adaptive_fails",
    [
        ((0.0, -0.2), True, False),
        ((0.3, 0.0), True, False),
        ((0.0, -0.15), False, False),  # the fixed MPC goes on, its ZMP 24 mm out of the foot
        ((0.0, 0.2), True, True),  # towards the support foot: the swing foot cannot cross
    ],
)
def test_against_the_fixed_footstep_mpc(kick, fixed_fails, adaptive_fails, record_property):
    """Same kicks on the fixed-footstep MPC: a failed plan (its fallback runs out and it
    raises), or a plan whose executed ZMP leaves the feet between samples; the adaptive
    one steps and keeps its ZMP inside. A push towards the support foot while the other
    foot swings defeats both (the swing foot cannot cross, the next step comes too late)."""
    schedule = straight()
    outs, error = pushed_walk(MpcGenerator(lipm=LIPM_SMALL), kick, schedule)
    assert isinstance(error, NoSolutionFound) is fixed_fails
    if fixed_fails:
        assert sum(o.solve.fallback for o in outs[1:]) >= 10
    else:
        fixed_margin = executed_margins(schedule, outs).min()
        record_property("fixed_mpc_min_zmp_margin_m", float(fixed_margin))
        assert fixed_margin < -0.015  # measured -23.9 mm
    gen = generator()
    outs, error = pushed_walk(gen, kick, schedule)
    assert isinstance(error, NoSolutionFound) is adaptive_fails
    if not adaptive_fails:
        assert all(o.solve.success for o in outs[1:])
        assert executed_margins(gen.schedule, outs).min() > -1e-3


def local_step(schedule, k):
    """Step ``k`` in its support foot's frame: (x [m], y [m], yaw [rad])."""
    plan = schedule.plan
    support = plan.support_foot(k)
    step = plan.steps[k]
    return np.append(support.to_local(step.xy), wrap_angle(step.yaw - support.yaw))


@pytest.mark.slow
def test_random_pushes_keep_every_footstep_reachable(record_property):
    rng = np.random.default_rng(7)
    schedule = straight(6)
    rectangle = LegLimits().rectangle()
    published = recovered = 0
    worst = np.inf
    for _ in range(12):
        angle, speed = rng.uniform(-np.pi, np.pi), rng.uniform(0.05, 0.3)
        gen = generator()
        outs, error = pushed_walk(
            gen,
            speed * np.array([np.cos(angle), np.sin(angle)]),
            schedule,
            push_time=round(rng.uniform(1.1, 3.6), 2),
        )
        recovered += error is None
        previous = schedule
        for out in outs:
            if out.schedule is None:
                continue
            published += 1
            for k in range(schedule.plan.nb_steps):
                lower, upper = rectangle.bounds(schedule.plan.steps[k].side)
                local = local_step(out.schedule, k)
                worst = min(worst, np.min(local - lower), np.min(upper - local))
                # Landed (or frozen) steps never move.
                landing = schedule.walk_start + k * schedule.step_duration + schedule.t_e
                if out.time - 0.01 >= landing - gen.freeze_before_landing:
                    assert np.array_equal(out.schedule.plan.steps[k].xy, previous.plan.steps[k].xy)
            previous = out.schedule
    record_property("schedules_checked", published)
    record_property("worst_reach_margin_m", float(worst))
    print(
        f"{published} schedules, {recovered}/12 pushes recovered, worst margin to the "
        f"reachability bounds {worst * 1e3:.4f} mm"
    )
    assert published > 50
    assert worst > -1e-6
    assert recovered >= 9


# --------------------------------------------------------------------- pieces
def test_blended_rectangles_stay_in_the_hull_of_the_feet():
    rng = np.random.default_rng(0)
    foot = FootGeometry()
    corners = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]]) * 0.5
    for _ in range(50):
        a, b = rng.uniform(-0.1, 0.1, 2), rng.uniform(-0.1, 0.1, 2)
        yaw_a, yaw_b, lam = rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform()
        normals, half = blended_rectangles(
            np.array([yaw_a]), np.array([yaw_b]), np.array([lam]), foot
        )
        front, left = normals[0, 0], normals[0, 2]
        centre = (1 - lam) * a + lam * b
        points = centre + 2 * (
            corners[:, :1] * half[0, 0] * front + corners[:, 1:] * half[0, 2] * left
        )
        hull = SupportPolygon.union_hull(
            [
                foot_rectangle(a, yaw_a, foot.length, foot.width),
                foot_rectangle(b, yaw_b, foot.length, foot.width),
            ]
        )
        assert hull.signed_distance(points).min() > -1e-12
    # Same yaws: the full sole.
    _, half = blended_rectangles(np.zeros(1), np.zeros(1), np.array([0.3]), foot)
    np.testing.assert_allclose(half[0], [0.05, 0.05, 0.03, 0.03])


def test_with_steps_matches_a_full_build():
    schedule = straight()
    steps = list(schedule.plan.steps)
    steps[3] = steps[3].moved(position=steps[3].position + [0.01, -0.02, 0.0])
    fast = schedule.with_steps(steps)
    full = ContactSchedule(fast.plan, schedule.foot)
    times = np.linspace(0.0, schedule.duration, 1001)
    for a, b in zip(fast.halfplanes(times), full.halfplanes(times)):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(fast.zmp_reference(times), full.zmp_reference(times))
    np.testing.assert_array_equal(fast.support_positions, full.support_positions)


def test_standing_schedule_without_steps():
    plan = FootstepPlan(Footstep("left", [0.0, 0.04]), Footstep("right", [0.0, -0.04]))
    run = rollout(generator(), ContactSchedule(plan))
    assert run.nb_failures == 0
    assert np.abs(run.com).max() < 1e-9 and np.abs(run.zmp).max() < 1e-9


def test_for_robot_takes_the_leg_limits_and_walks_in_mujoco(record_property):
    from mpcwalk.robot.loading import load_robot
    from mpcwalk.walking.runner import run_walk

    gen = FootstepMpcGenerator.for_robot(load_robot("bioloid-like", visual=False))
    assert gen.lipm.com_height == pytest.approx(0.23)
    assert (gen.reachability.y_min, gen.reachability.y_max) == pytest.approx((0.08, 0.12))
    result = run_walk("bioloid-like", controller="mpc-steps", command=(0.1, 0.0, 0.0), nb_steps=6)
    metrics = result.metrics
    record_property("foot_step_error_cm_max", metrics["foot_step_error_cm_max"])
    assert not metrics["fell"] and metrics["mpc_failures"] == 0
    assert metrics["steps_completed"] == metrics["steps_planned"]


# --------------------------------------------------------------------- errors
def test_registered_under_its_name():
    assert "mpc-steps" in generator_names()
    assert isinstance(make_generator("mpc-steps", lipm=LIPM_SMALL), FootstepMpcGenerator)


def test_a_rectangle_excluding_the_plan_is_a_named_error():
    short = ReachabilityRectangle(
        x_min=-0.04, x_max=0.03, y_min=0.08, y_max=0.14, yaw_min=-0.2, yaw_max=0.35
    )
    gen = generator(reachability=short)
    with pytest.raises(InfeasibleStep, match="Planned step 0 .*outside the reachability"):
        gen.reset(straight())


@pytest.mark.parametrize(
    "options, match",
    [
        ({"solver": "osqp-direct"}, "through qpsolvers"),
        ({"footstep_reference": "sideways"}, "footstep_reference"),
        ({"jerk_weight": 0.0}, "jerk_weight must be a positive"),
        ({"horizon_length": 3}, "Unknown footstep MPC parameter"),
        ({"reachability": (0.1, 0.2)}, "ReachabilityRectangle or LegLimits"),
        ({"publish_tolerance": -1.0}, "publish_tolerance"),
        ({"dcm_step_gain": -0.3}, "dcm_step_gain must be a non-negative"),
        ({"dcm_deadband": float("nan")}, "dcm_deadband must be a non-negative"),
    ],
)
def test_bad_configuration_is_a_named_error(options, match):
    with pytest.raises(ConfigurationError, match=match):
        generator(**options)


def test_unknown_solver_and_step_before_reset():
    with pytest.raises(SolverNotFound):
        generator(solver="no-such-solver")
    with pytest.raises(NotReset):
        generator().step()


def test_a_failed_solve_falls_back_then_raises():
    gen = generator(max_fallback_ticks=3)
    gen.reset(straight())
    for _ in range(150):
        gen.step()
    hopeless = ComState(gen._state[0], [0.0, 3.0])  # 3 m/s sideways
    for tick in range(1, 4):
        out = gen.step(hopeless)
        assert not out.solve.success and out.solve.fallback
        assert out.solve.consecutive_failures == tick and out.schedule is None
        assert np.all(np.isfinite(out.com))
    with pytest.raises(NoSolutionFound):
        gen.step(hopeless)
    recovered = generator(max_fallback_ticks=3)
    recovered.reset(straight())
    for _ in range(150):
        recovered.step()
    assert not recovered.step(hopeless).solve.success
    assert recovered.step().solve.success  # its own state again: the plan goes on


def test_a_reported_dcm_error_moves_the_next_landing_by_its_growth():
    """Capture-point stepping (dcm_step_gain): the controller reports a DCM error while the
    generator's own state is on the plan; the next landing's target moves by the gain times
    the error grown until the landing, and the QP moves the step that way."""
    schedule = straight()
    moves = {}
    for gain in (0.0, 1.0):
        gen = generator(dcm_step_gain=gain)
        gen.reset(schedule)
        while gen.time < PUSH_TIME - 1e-9:
            gen.step()
        # [m], DCM 1 cm to the right of the reference, the side of the swinging right foot
        # (to the left it could not go: the feet separation bounds it)
        error = np.array([0.0, -0.02])  # beyond the 5 mm deadband
        k = 2  # the step swinging at PUSH_TIME
        landing = gen._slots.landing[k]
        growth = np.exp(gen.lipm.omega * (landing - gen.time))
        beyond = error * (1.0 - gen.dcm_deadband / 0.02)  # the deadband is left out
        gen._dcm_error = error  # what step(dcm_error=error) gives the tick
        assert np.allclose(gen._capture_offset(gen.time, landing), gain * growth * beyond)
        gen._dcm_error = 0.2 * error  # within the deadband: no offset
        assert np.allclose(gen._capture_offset(gen.time, landing), 0.0)
        for _ in range(5):
            gen.step(dcm_error=error)
            np.testing.assert_array_equal(gen.dcm_error, error)
        moves[gain] = deviations(gen.schedule, schedule)[k]
    assert np.allclose(moves[0.0], 0.0, atol=1e-3)  # undisturbed: on the plan
    assert moves[1.0][1] < -0.003  # to the right, as the DCM error
    assert abs(moves[1.0][0]) < 0.002
    gen.step()  # no DCM error given: none this tick
    np.testing.assert_array_equal(gen.dcm_error, np.zeros(2))
    with pytest.raises(ConfigurationError, match="dcm_error must be 2 finite numbers"):
        gen.step(dcm_error=[np.nan, 0.0])


def test_mujoco_push_felling_the_closed_form_gait_is_recovered_by_the_adaptive_mpc():
    """A 0.3 N s forward push at the start of single support of the third step: paper M's
    open-loop closed form falls, the footstep-adaptive MPC with feedback walks on (largest
    forward impulses survived, ``results/paper_m``: below 0.1 N s against 0.55 N s)."""
    from mpcwalk.sim import ExternalForce
    from mpcwalk.walking.runner import run_walk
    from mpcwalk.walking.specification import WalkSpec

    push = [ExternalForce(2.05, 0.1, [3.0, 0.0, 0.0])]  # 0.3 N s
    runs = {
        name: run_walk(
            WalkSpec.build(
                "bioloid-like",
                generator=generator,
                command=(0.1, 0.0, 0.0),
                nb_steps=5,
                pushes=push,
                feedback=feedback,
            )
        ).metrics
        for name, generator, feedback in (
            ("open loop", "analytic", False),
            ("adaptive", "mpc-steps", True),
        )
    }
    assert runs["open loop"]["fell"]
    assert not runs["adaptive"]["fell"], runs["adaptive"]["fall_reason"]
    assert runs["adaptive"]["mpc_failures"] == 0
    assert runs["adaptive"]["steps_completed"] == runs["adaptive"]["steps_planned"]


@pytest.mark.parametrize("kick", [(0.0, 0.0), (0.25, 0.0), (0.0, 0.15), (0.0, -0.15)])
def test_every_plan_is_capturable_within_the_horizon(kick):
    """With ``capturability`` on, the DCM at the end of every plan returned lies in the
    support of the last sample (the robot could stop there), checked against the support
    half-planes the QP was given; a plan that cannot meet it is said and counted."""
    gen = generator(capturability=True)
    slacks, statuses = [], []
    core_solve = gen._checked_solve

    def solve_and_check(qp, shift):
        result = core_solve(qp, shift)
        statuses.append(result.status)
        if result.success and "not capturable" not in result.status:
            supports, last = qp.supports, len(qp.supports.rows) - 1
            rows = np.flatnonzero(supports.rows[last])
            centre = supports.weights[last] @ qp.footsteps(result.x)
            offset = supports.normals[last, rows] @ (qp.terminal_dcm(result.x) - centre)
            slacks.append(float(np.min(supports.offsets[last, rows] - offset)))
        return result

    gen._checked_solve = solve_and_check
    outs, error = pushed_walk(gen, np.array(kick), straight())
    assert error is None
    assert len(slacks) + gen.nb_not_capturable == len(statuses) == len(outs) - 1
    assert min(slacks) > -1e-7  # [m]
    assert sum("not capturable" in s for s in statuses) == gen.nb_not_capturable
    if kick == (0.0, 0.0):
        assert gen.nb_not_capturable == 0


def test_timing_adaptation_brings_the_landing_forward_under_a_forward_push():
    """A forward kick of 0.4 m/s in single support: with the step timing fixed the QP has no
    plan (its landing cannot reach the capture point in time); with the adaptation the
    swing foot lands earlier (the schedule's clock jumps ahead once) and the walk goes on.
    Unpushed, the adaptation never triggers and the walk is the same."""
    _, error = pushed_walk(generator(), np.array((0.4, 0.0)), straight())
    assert error is not None
    gen = generator(timing_adaptation=True)
    outs, error = pushed_walk(gen, np.array((0.4, 0.0)), straight())
    assert error is None and gen.nb_retimed == 1
    assert 0.1 < gen.time_offset < 0.25  # [s] measured 0.18 of the 0.2 s left of the swing
    assert outs[-1].time > outs[-2].time  # the clock goes on from there
    calm = generator(timing_adaptation=True)
    plain, _ = pushed_walk(calm, np.zeros(2), straight())
    reference, _ = pushed_walk(generator(), np.zeros(2), straight())
    assert calm.nb_retimed == 0
    np.testing.assert_array_equal([o.com for o in plain], [o.com for o in reference])


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_lift_off_is_put_off_while_the_dcm_error_points_to_the_lifting_foot(sign):
    """At the end of a double support, a DCM error of 2 cm towards the foot about to lift:
    the schedule's clock stops (both feet stay down, the ZMP may use that sole) for
    ``max_hold`` at most, then goes on. Towards the other foot nothing is put off."""
    schedule = straight()
    gen = generator(timing_adaptation=True, max_hold=0.2)
    gen.reset(schedule)
    k, plan = 3, schedule.plan
    lift_off = schedule.walk_start + k * schedule.step_duration + schedule.t_b
    feet = plan.stance(k)
    toward = feet[plan.steps[k].side].xy - feet[plan.steps[k].side.other].xy
    error = sign * 0.02 * toward / np.linalg.norm(toward)
    times = []
    while gen.time < lift_off + 0.5:
        near = lift_off - 0.1 < gen.time < lift_off + 0.3
        times.append(gen.step(dcm_error=error if near else None).time)
    steps = np.diff(times)
    if sign > 0:
        assert gen.nb_held == 20  # 0.2 s of 10 ms ticks, the clock still
        assert np.count_nonzero(steps < 1e-9) == 20
        held = {round(times[i], 9) for i in np.flatnonzero(steps < 1e-9)}
        (stopped,) = held  # one time, the last one before the lift-off
        assert lift_off - gen.control_period - 1e-9 <= stopped < lift_off
        assert gen.time_offset == pytest.approx(-0.2)
    else:
        assert gen.nb_held == 0 and gen.time_offset == 0.0
    assert steps.min() > -1e-9  # never backwards


def test_strides_placed_on_a_terrain_are_accepted_only_when_asked():
    """A tread further than a flat step: refused by the flat rectangle, taken (its bounds
    grown about the planned stride) with ``planned_strides``."""
    from mpcwalk.exceptions import InfeasibleStep
    from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming
    from mpcwalk.gait.contact_schedule import ContactSchedule
    from mpcwalk.generators.mpc_steps import FootstepMpcGenerator
    from mpcwalk.models.lipm import LIPM

    steps = [
        Footstep(Side.RIGHT, (0.15, -0.05, 0.03)),  # 0.15 m: beyond the 0.08 m flat reach
        Footstep(Side.LEFT, (0.15, 0.05, 0.03)),
    ]
    plan = FootstepPlan(
        Footstep(Side.LEFT, (0.0, 0.05, 0.0)),
        Footstep(Side.RIGHT, (0.0, -0.05, 0.0)),
        steps,
        StepTiming(0.8, 0.2, 0.5, 0.5),
    )
    schedule = ContactSchedule(plan)
    with pytest.raises(InfeasibleStep, match="outside the reachability rectangle"):
        FootstepMpcGenerator(lipm=LIPM(com_height=0.2)).reset(schedule)
    generator = FootstepMpcGenerator(lipm=LIPM(com_height=0.2), planned_strides=True)
    generator.reset(schedule)
    lower, upper = generator._slots.bounds[0]
    assert upper[0] == pytest.approx(0.15) and lower[0] < 0.0
    while not generator.done:
        generator.step()
