"""Swing feet that clear the terrain: the shaped swing keeps its clearance over the noses of
the stairs where paper M's would stub, and a flat walk keeps paper M's swing bit for bit."""

import math

import numpy as np
import pytest

from mpcwalk.footsteps import FootGeometry, Footstep, LegLimits, Side, StepTiming, VelocityPlanner
from mpcwalk.gait import (
    ContactSchedule,
    SwingFootTrajectory,
    measure_swing_clearance,
    sole_clearance,
)
from mpcwalk.gait.swing_clearance import CLEARANCE_KEPT, LINE_TOLERANCE, MIN_CLEARANCE
from mpcwalk.terrain import FLAT, Platform, Slope, Stairs, Terrain, TerrainReach

ISSUE = Terrain([Stairs(0.6, 0.15, 0.30, 5), Stairs(2.4, -0.15, 0.30, 5), Slope(4.5, 1.5, 10.0)])
BIG_SOLE = FootGeometry(0.2, 0.1)
SMALL_STAIRS = Terrain([Stairs(0.3, 0.05, 0.15, 4), Stairs(1.2, -0.05, 0.15, 4)])


@pytest.fixture(scope="module")
def issue_schedule():
    planner = VelocityPlanner(LegLimits(0.25, 0.15, 0.17, 0.4, 0.4, 0.09, 0.11), StepTiming(0.8))
    reach = TerrainReach.for_leg(BIG_SOLE.length, BIG_SOLE.width, 0.8)
    plan = planner.plan((0.1, 0.0, 0.0), 50, terrain=ISSUE, reach=reach)
    return ContactSchedule(plan, BIG_SOLE)


@pytest.fixture(scope="module")
def small_schedule():
    reach = TerrainReach.for_leg(0.10, 0.06, 0.2)
    plan = VelocityPlanner().plan((0.1, 0.0, 0.0), 30, terrain=SMALL_STAIRS, reach=reach)
    return ContactSchedule(plan, FootGeometry(0.10, 0.06))


def between_treads(schedule):
    """Steps whose swing goes from one height to another (stairs, ramp)."""
    plan = schedule.plan
    return [
        k
        for k, step in enumerate(plan.steps)
        if abs(step.position[2] - plan.stance(k)[step.side].position[2]) > 1e-9
    ]


@pytest.mark.parametrize("profile", ["cosine", "ctraj"])
def test_swings_over_the_issue_stairs_keep_their_clearance_where_paper_m_s_would_stub(
    issue_schedule, profile
):
    step_height = 0.08
    shaped = SwingFootTrajectory(issue_schedule, step_height, profile, terrain=ISSUE)
    report = measure_swing_clearance(shaped, ISSUE, dt=0.002)
    steps = between_treads(issue_schedule)
    assert len(steps) >= 20  # up, down, onto and off the ramp
    plan = issue_schedule.plan
    clearance = shaped.terrain_clearance
    ramp = [
        k
        for k in steps
        if clearance.shape(plan.stance(k)[plan.steps[k].side], plan.steps[k]) is None
    ]
    stairs = [k for k in steps if k not in ramp]
    assert ramp and all(plan.steps[k].xy[0] > 4.4 for k in ramp)  # up the even ramp
    assert len(stairs) >= 16  # up and down the stairs
    assert report.toe_stubs == 0
    # the apex keeps the whole clearance, an overlapping rise or lowering a share of it
    assert min(report.per_step[k] for k in stairs) >= CLEARANCE_KEPT * step_height
    assert report.min_clearance >= 0.0  # on the ramp too: paper M's swing rises above it
    plain = measure_swing_clearance(
        SwingFootTrajectory(issue_schedule, step_height, profile), ISSUE
    )
    assert plain.toe_stubs > 0
    assert min(plain.per_step[k] for k in steps) < -0.05  # the toe deep in a riser


def test_swings_over_small_stairs_keep_their_clearance(small_schedule):
    shaped = SwingFootTrajectory(small_schedule, 0.04, terrain=SMALL_STAIRS)
    report = measure_swing_clearance(shaped, SMALL_STAIRS, dt=0.002)
    steps = between_treads(small_schedule)
    assert len(steps) >= 10 and report.toe_stubs == 0
    assert min(report.per_step[k] for k in steps) >= CLEARANCE_KEPT * 0.04
    higher = SwingFootTrajectory(small_schedule, 0.04, terrain=SMALL_STAIRS, clearance=0.06)
    assert measure_swing_clearance(higher, SMALL_STAIRS).min_clearance >= CLEARANCE_KEPT * 0.06
    low = SwingFootTrajectory(small_schedule, 0.0, terrain=SMALL_STAIRS)
    assert low.terrain_clearance is not None
    assert low.terrain_clearance.clearance == MIN_CLEARANCE  # at least 1 cm
    plain = measure_swing_clearance(SwingFootTrajectory(small_schedule, 0.04), SMALL_STAIRS)
    assert plain.toe_stubs > 0


def test_a_shaped_swing_rises_travels_and_lowers_at_rest_at_both_ends(issue_schedule):
    trajectory = SwingFootTrajectory(issue_schedule, 0.08, terrain=ISSUE)
    plan, schedule = issue_schedule.plan, issue_schedule
    k = between_treads(issue_schedule)[1]  # from the floor onto the second tread
    landing = plan.steps[k]
    lift = plan.stance(k)[landing.side]
    start = schedule.walk_start + k * schedule.step_duration
    times = np.linspace(start + schedule.t_b, start + schedule.t_e - 1e-9, 2001)
    feet = [trajectory.foot_poses(t)[landing.side] for t in times]
    positions = np.array([f.position for f in feet])
    velocities = np.array([f.linear_velocity for f in feet])
    np.testing.assert_allclose(positions[0], lift.position, atol=1e-9)
    np.testing.assert_allclose(positions[-1], landing.position, atol=1e-6)
    np.testing.assert_allclose(velocities[[0, -1]], 0.0, atol=1e-5)
    dt = times[1] - times[0]
    np.testing.assert_allclose(
        np.gradient(positions, dt, axis=0)[1:-1], velocities[1:-1], atol=0.02
    )
    # the foot is above the landing tread's nose plus the clearance before its toe passes it
    nose = math.floor((landing.xy[0] - 0.6) / 0.3) * 0.3 + 0.6
    toe = positions[:, 0] + 0.5 * BIG_SOLE.length
    passing = np.flatnonzero(toe >= nose)[0]
    assert positions[passing, 2] >= landing.position[2] + 0.08


@pytest.mark.parametrize("profile", ["cosine", "ctraj"])
def test_a_flat_walk_keeps_paper_m_s_swing_bit_for_bit(profile):
    plan = VelocityPlanner().plan((0.1, 0.02, 0.2), 8)  # turning, sideways, flat
    schedule = ContactSchedule(plan)
    plain = SwingFootTrajectory(schedule, 0.04, profile)
    far = Terrain([Platform(30.0, 0.5, 0.05)])  # a terrain, nothing of it under the walk
    others = [
        SwingFootTrajectory(schedule, 0.04, profile, terrain=terrain)
        for terrain in (None, FLAT, far)
    ]
    for t in np.arange(0.0, schedule.duration, 0.003):
        expected = plain.foot_poses(t)
        for other in others:
            state = other.foot_poses(t)
            for side in Side:
                a, b = expected[side], state[side]
                assert np.array_equal(a.position, b.position)
                assert np.array_equal(a.linear_velocity, b.linear_velocity)
                assert (a.yaw, a.yaw_rate, a.roll, a.pitch) == (b.yaw, b.yaw_rate, b.roll, b.pitch)


def test_the_clearance_of_a_sole_over_a_nose():
    terrain = Terrain([Platform(0.5, 0.5, 0.1)])
    lift = Footstep(Side.LEFT, (0.2, 0.0, 0.0))
    landing = Footstep(Side.LEFT, (0.7, 0.0, 0.1))
    over = Footstep(Side.LEFT, (0.45, 0.0, 0.13))  # toe 5 cm past the nose, 3 cm above it
    assert sole_clearance(terrain, over, lift, landing, 0.1, 0.06) == pytest.approx(0.03)
    stub = Footstep(Side.LEFT, (0.47, 0.0, 0.08))  # toe in the platform's side
    assert sole_clearance(terrain, stub, lift, landing, 0.1, 0.06) == pytest.approx(-0.02)
    # over its own footprints only: nothing to clear
    assert sole_clearance(terrain, landing, lift, landing, 0.1, 0.06) == math.inf


def ramp_schedule(angle_deg, vx=0.1):
    terrain = Terrain([Slope(0.3, 3.0, angle_deg)])
    reach = TerrainReach.for_leg(BIG_SOLE.length, BIG_SOLE.width, 0.8)
    planner = VelocityPlanner(LegLimits(0.25, 0.15, 0.17, 0.4, 0.4, 0.09, 0.11), StepTiming(0.8))
    plan = planner.plan((vx, 0.0, 0.0), 24, terrain=terrain, reach=reach)
    return terrain, ContactSchedule(plan, BIG_SOLE)


def test_an_even_ramp_keeps_paper_m_s_swing_up_and_down():
    """Up an even ramp the ground under a swing lies on the line between its footholds:
    paper M's swing rises above it as above the floor (the shaped one, rising first, left
    g1 1.3 cm short per step up a 3 deg ramp, against 0.5 cm with paper M's). Down it too:
    the shaped swing that lowered only once its travel had ended dropped the foot 12 cm in
    the last tenth of a second, and atlas-like's landings slid back 2 to 5 cm each."""
    terrain, schedule = ramp_schedule(6.0)
    plan = schedule.plan
    shaped = SwingFootTrajectory(schedule, 0.08, terrain=terrain)
    plain = SwingFootTrajectory(schedule, 0.08)
    on_ramp = [k for k, step in enumerate(plan.steps) if 0.45 < step.xy[0] < 3.1]
    on_ramp = [k for k in on_ramp if plan.stance(k)[plan.steps[k].side].xy[0] > 0.45]
    assert len(on_ramp) >= 10
    for k in on_ramp:
        lift, landing = plan.stance(k)[plan.steps[k].side], plan.steps[k]
        assert landing.position[2] > lift.position[2]  # every one climbs
        assert shaped.terrain_clearance.shape(lift, landing) is None
        start = schedule.walk_start + k * schedule.step_duration
        for t in np.linspace(start, start + schedule.step_duration, 9):
            a, b = plain.foot_poses(t)[landing.side], shaped.foot_poses(t)[landing.side]
            assert np.array_equal(a.position, b.position)
    assert measure_swing_clearance(shaped, terrain).toe_stubs == 0
    down_ramp = Terrain([Slope(0.3, 3.0, -6.0)])  # a forward step 4.2 cm down it
    slope, pitch = -math.tan(math.radians(6.0)), math.radians(6.0)  # toes down
    lift = Footstep(Side.LEFT, (0.8, 0.0, 0.5 * slope), pitch=pitch)
    landing = Footstep(Side.LEFT, (1.2, 0.0, 0.9 * slope), pitch=pitch)
    descending = SwingFootTrajectory(schedule, 0.08, terrain=down_ramp).terrain_clearance
    assert descending.shape(lift, landing) is None
    down_terrain, down_schedule = ramp_schedule(-6.0)
    down = SwingFootTrajectory(down_schedule, 0.08, terrain=down_terrain)
    assert measure_swing_clearance(down, down_terrain).toe_stubs == 0


def test_a_swing_over_a_brow_keeps_paper_m_s_swing_while_it_clears_it():
    """Across the brow of a 5 deg ramp (a crest, 7 mm above the line between the
    footholds) paper M's swing keeps more than half its lift over the ground: it is kept.
    Over a 3 cm block between the footholds it would not: the swing is shaped."""
    brow = Terrain([Slope(0.2, 1.0, 5.0)])  # up from 0.2 to 1.2 m, then level
    top = math.tan(math.radians(5.0)) * 1.0
    pitch = -math.radians(5.0)  # toes up
    lift = Footstep(Side.LEFT, (1.0, 0.0, top - 0.2 * math.tan(math.radians(5.0))), pitch=pitch)
    landing = Footstep(Side.LEFT, (1.4, 0.0, top))
    schedule = ramp_schedule(6.0)[1]
    clearance = SwingFootTrajectory(schedule, 0.08, terrain=brow).terrain_clearance
    gaps_above_line = top - (lift.position[2] + 0.5 * (top - lift.position[2]))
    assert gaps_above_line > LINE_TOLERANCE  # not an even ramp: the lift covers it
    assert clearance.shape(lift, landing) is None
    block = Terrain([Platform(1.12, length=0.06, height=0.03)])
    flat_lift, flat_landing = Footstep(Side.LEFT, (0.9, 0.0)), Footstep(Side.LEFT, (1.4, 0.0))
    blocked = SwingFootTrajectory(schedule, 0.04, terrain=block).terrain_clearance
    assert blocked.shape(flat_lift, flat_landing) is not None
