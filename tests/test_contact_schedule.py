"""Contact schedule, timing and paper M's ZMP reference."""

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError, InfeasibleStep
from mpcwalk.footsteps import FootGeometry, Footstep, FootstepPlan, Side, StepTiming
from mpcwalk.gait import ContactSchedule


def make_plan(nb_steps=4, length=0.05, timing=StepTiming()):
    left = Footstep("left", [0.0, 0.05, 0.0])
    right = Footstep("right", [0.0, -0.05, 0.0])
    steps, side = [], Side.RIGHT
    for k in range(nb_steps):
        steps.append(Footstep(side, [length * (k + 1), side.sign * 0.05, 0.0]))
        side = side.other
    return FootstepPlan(left, right, steps, timing)


@pytest.mark.parametrize("T", [0.0, -0.5, float("nan")])
def test_negative_step_duration_is_rejected(T):
    with pytest.raises(ConfigurationError, match="step_duration"):
        StepTiming(step_duration=T)


@pytest.mark.parametrize("r", [-0.1, 1.0, 1.5])
def test_double_support_ratio_range(r):
    with pytest.raises(ConfigurationError, match=r"double_support_ratio must lie in \[0, 1\)"):
        StepTiming(double_support_ratio=r)


def test_steps_must_alternate():
    left = Footstep("left", [0, 0.05])
    right = Footstep("right", [0, -0.05])
    with pytest.raises(InfeasibleStep, match="alternate"):
        FootstepPlan(
            left, right, [Footstep("right", [0.05, -0.05]), Footstep("right", [0.1, -0.05])]
        )


def test_bad_side_is_named():
    with pytest.raises(ConfigurationError, match="'left' or 'right'"):
        Footstep("middle", [0, 0])


def test_phases_tile_time_and_match_paper_m_timing():
    timing = StepTiming(step_duration=0.5, double_support_ratio=0.2)
    sched = ContactSchedule(make_plan(4, timing=timing))
    assert sched.t_b == pytest.approx(0.05) and sched.t_e == pytest.approx(0.45)
    for a, b in zip(sched.phases[:-1], sched.phases[1:]):
        assert a.end == pytest.approx(b.start)
    assert sched.phases[0].start == 0.0
    assert sched.phases[-1].end == pytest.approx(sched.duration)
    assert sched.duration == pytest.approx(1.0 + 4 * 0.5 + 1.0)
    singles = [ph for ph in sched.phases if ph.single_support]
    assert len(singles) == 4
    assert all(ph.duration == pytest.approx(0.4) for ph in singles)
    # First step moves the right foot: the left supports.
    assert singles[0].support_side is Side.LEFT
    assert sched.step_phase(1.0 + 0.25) == pytest.approx(0.5)


def test_support_polygon_single_and_double():
    sched = ContactSchedule(make_plan(2), FootGeometry(0.1, 0.06))
    mid_single = 1.0 + 0.25
    poly = sched.support_polygon(mid_single)
    assert poly.contains(np.array([0.0, 0.05]))
    assert not poly.contains(np.array([0.0, -0.05]))
    ds = sched.support_polygon(0.5)
    assert ds.contains(np.array([0.0, 0.0]))
    A, b = sched.halfplanes(np.array([0.5, mid_single]))
    assert A.shape == (2, 8, 2)
    assert np.all(A[1] @ np.array([0.0, 0.05]) <= b[1])


def test_zmp_reference_is_continuous_and_hits_waypoints():
    sched = ContactSchedule(make_plan(6))
    t = np.linspace(0.0, sched.duration, 4001)
    p = sched.zmp_reference(t)
    # No jumps: the slope stays below (feet distance) / t_b ~ 1.2 m/s.
    assert np.max(np.abs(np.diff(p, axis=0))) < 1.5 * (t[1] - t[0])
    # Inside single support the reference sits on the support foot centre.
    for k in range(6):
        t_mid = sched.walk_start + k * 0.5 + 0.25
        np.testing.assert_allclose(
            sched.zmp_reference(t_mid), sched.support_positions[k], atol=1e-12
        )
        np.testing.assert_allclose(
            sched.zmp_reference(sched.walk_start + k * 0.5), sched.torso_waypoints[k], atol=1e-12
        )
    np.testing.assert_allclose(p[-1], sched.torso_waypoints[-1], atol=1e-12)


def test_zero_double_support_ratio():
    sched = ContactSchedule(make_plan(2, timing=StepTiming(double_support_ratio=0.0)))
    assert all(ph.duration > 0 for ph in sched.phases)
    assert sum(ph.single_support for ph in sched.phases) == 2


def test_a_schedule_with_later_steps_moved_keeps_the_phases_before_them():
    """``with_steps`` (the footstep MPC's publications) keeps the phases of the steps
    before the first moved one, and builds the same schedule as a full build."""
    from mpcwalk.footsteps import VelocityCommand, VelocityPlanner

    plan = VelocityPlanner().plan(VelocityCommand(vx=0.1, vy=0.02, vyaw=0.3), nb_steps=12)
    schedule = ContactSchedule(plan)
    for first, move in ((5, (0.004, -0.002)), (2, (0.001, 0.003)), (9, (-0.002, 0.0))):
        steps = list(schedule.plan.steps)
        for k in range(first, len(steps)):
            xy = steps[k].position[:2] + np.array(move)
            steps[k] = steps[k].moved(position=[*xy, steps[k].position[2]])
        moved = schedule.with_steps(steps)
        full = ContactSchedule(moved.plan, moved.foot)
        kept = [ph for ph in schedule.phases if ph.step_index < first]
        assert all(a is b for a, b in zip(moved.phases, kept))  # the same objects
        assert moved.phases[len(kept)] is not schedule.phases[len(kept)]
        assert len(moved.phases) == len(full.phases)
        for a, b in zip(moved.phases, full.phases):
            assert (a.start, a.end, a.step_index, a.support_side) == (
                b.start,
                b.end,
                b.step_index,
                b.support_side,
            )
            assert {s: f.position.tolist() for s, f in a.feet.items()} == {
                s: f.position.tolist() for s, f in b.feet.items()
            }
        for name in ("phase_centers", "support_positions", "zmp_breakpoint_values"):
            np.testing.assert_allclose(getattr(moved, name), getattr(full, name), atol=1e-12)
        A, b = moved.phase_halfplanes
        A_full, b_full = full.phase_halfplanes
        np.testing.assert_allclose(A, A_full, atol=1e-12)
        np.testing.assert_allclose(b, b_full, atol=1e-12)
        times = np.linspace(0.0, full.duration, 997)
        np.testing.assert_allclose(
            moved.zmp_reference(times), full.zmp_reference(times), atol=1e-12
        )
        schedule = moved
