"""Footsteps placed on a terrain: whole soles on tops with margins, within the legs' reach,
one or two feet per tread, stones only, the highest block of a rough patch."""

import dataclasses
import math

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError, InfeasibleStep
from mpcwalk.footsteps import (
    LegLimits,
    Side,
    StepTiming,
    VelocityPlanner,
    place_on_terrain,
    terrain_steps,
    terrain_tops,
)
from mpcwalk.footsteps.terrain_steps import DESCENT_HEEL_ROOM
from mpcwalk.terrain import (
    FLAT,
    Platform,
    RoughPatch,
    Slope,
    Stairs,
    SteppingStones,
    Terrain,
    TerrainReach,
)

#: The issue's terrain: 5 steps up from 0.6 m, 5 down from 2.4 m, a 10 deg ramp at 4.5 m.
ISSUE = Terrain([Stairs(0.6, 0.15, 0.30, 5), Stairs(2.4, -0.15, 0.30, 5), Slope(4.5, 1.5, 10.0)])
BIG_REACH = TerrainReach.for_leg(0.2, 0.1, 0.8)
#: A large robot's flat reach: its flat stride (0.25 m) is shorter than the stairs' run.
BIG_LIMITS = LegLimits(0.25, 0.15, 0.17, 0.4, 0.4, 0.09, 0.11)
BIG_TIMING = StepTiming(0.8, 0.2, 1.0, 1.0)
SMALL_REACH = TerrainReach.for_leg(0.10, 0.06, 0.2)
SMALL_STAIRS = Terrain([Stairs(0.3, 0.05, 0.15, 4), Stairs(1.2, -0.05, 0.15, 4)])


def big_plan(vx=0.1, nb_steps=50, terrain=ISSUE):
    planner = VelocityPlanner(BIG_LIMITS, BIG_TIMING)
    return planner.plan((vx, 0.0, 0.0), nb_steps, terrain=terrain, reach=BIG_REACH)


def small_plan(terrain, reach=SMALL_REACH, nb_steps=30, vx=0.1):
    return VelocityPlanner().plan((vx, 0.0, 0.0), nb_steps, terrain=terrain, reach=reach)


def assert_on_tops_within_reach(plan, terrain, reach):
    """Every landing: whole sole on one top with the tread margin, at the top's height,
    within the rise and the stride of its support foot."""
    for k, step in enumerate(plan.steps):
        support = terrain.sole_support(step.xy, step.yaw, reach.sole_length, reach.sole_width)
        assert support.margin >= reach.tread_margin - 1e-9, k
        assert step.position[2] == pytest.approx(support.height, abs=1e-12), k
        assert step.position[2] == pytest.approx(terrain.height(*step.xy), abs=1e-12), k
        foot = plan.support_foot(k)
        assert abs(step.position[2] - foot.position[2]) <= reach.max_rise + 1e-9, k
        assert foot.to_local(step.xy)[0] <= reach.max_stride + 1e-9, k


def stride_ahead(plan, k):
    return plan.support_foot(k).to_local(plan.steps[k].xy)[0]


def test_the_issue_stairs_and_ramp_are_climbed_two_feet_per_tread():
    """A 0.15 m rise is more than half the swing rise of a 0.8 m leg (0.2 m): stepping over
    a tread would lift the swing foot 0.30 m, so the feet meet on every tread."""
    assert 2 * 0.15 > BIG_REACH.max_swing_rise >= 0.15
    plan = big_plan(nb_steps=70)
    assert plan.nb_steps == 71  # the caller's count: 70 steps and the closing one
    assert_on_tops_within_reach(plan, ISSUE, BIG_REACH)
    heights = np.array([s.position[2] for s in plan.steps])
    for flight in ISSUE.features[:2]:
        on = [s for s in plan.steps if flight.start < s.xy[0] < flight.end]
        treads = sorted(math.floor((s.xy[0] - flight.start) / flight.run) for s in on)
        assert treads == sorted(2 * list(range(flight.count - 1)))  # both feet, every tread
    for k, step in enumerate(plan.steps):  # no swing climbs or drops more than it may
        lift = plan.stance(k)[step.side]
        assert abs(step.position[2] - lift.position[2]) <= BIG_REACH.max_swing_rise + 1e-9
    # the run (0.30 m) exceeds the flat stride (0.25 m): climbed with longer strides
    strides = [stride_ahead(plan, k) for k in range(plan.nb_steps)]
    climbing = [d for k, d in enumerate(strides) if plan.steps[k].xy[0] < 2.4]
    assert max(climbing) == pytest.approx(0.30, abs=1e-9)
    assert max(climbing) > BIG_LIMITS.max_step_forward
    # a step down lands up to half its heel room further, towards the front of its tread
    assert max(strides) <= 0.30 + 0.5 * DESCENT_HEEL_ROOM * BIG_REACH.sole_length + 1e-9
    # every height is a multiple of the rise on the stairs, the ramp's beyond
    stairs = [h for s, h in zip(plan.steps, heights) if s.xy[0] < 4.5]
    np.testing.assert_allclose(np.round(np.array(stairs) / 0.15) * 0.15, stairs, atol=1e-12)
    ramp = [s for s in plan.steps if 4.5 < s.xy[0] < 6.0]
    assert ramp and all(
        s.position[2] == pytest.approx((s.xy[0] - 4.5) * math.tan(math.radians(10.0))) for s in ramp
    )
    # soles tilted as the ramp (toes up), flat elsewhere
    assert all(s.pitch == pytest.approx(-math.radians(10.0)) and s.roll == 0.0 for s in ramp)
    assert all(s.is_flat for s in plan.steps if all(s is not r for r in ramp))
    final = plan.stance(plan.nb_steps)
    assert final[Side.LEFT].xy[0] == final[Side.RIGHT].xy[0] > 6.0  # side by side, on top
    assert heights[-1] == pytest.approx(ISSUE.level_after)


def test_low_stairs_are_climbed_one_foot_per_tread():
    low = Terrain([Stairs(0.6, 0.08, 0.30, 5), Stairs(2.4, -0.08, 0.30, 5)])
    plan = big_plan(terrain=low, nb_steps=30)
    assert_on_tops_within_reach(plan, low, BIG_REACH)
    for flight in low.features:
        on = [s for s in plan.steps if flight.start < s.xy[0] < flight.end]
        treads = sorted(math.floor((s.xy[0] - flight.start) / flight.run) for s in on)
        assert treads == list(range(flight.count - 1))  # one foot per tread, every tread


def test_a_faster_command_keeps_its_stride_off_the_stairs():
    plan = big_plan(vx=0.3, nb_steps=40)
    assert_on_tops_within_reach(plan, ISSUE, BIG_REACH)
    strides = np.array([stride_ahead(plan, k) for k in range(plan.nb_steps - 1)])
    on_stairs = np.array([0.6 < s.xy[0] < 4.1 for s in plan.steps[:-1]])
    flat = strides[~on_stairs & (np.abs(strides - 0.24) < 1e-9)]
    assert len(flat) >= 5  # the commanded 0.24 m stride where nothing is in the way


def test_small_stairs_with_a_small_robot():
    plan = small_plan(SMALL_STAIRS)
    assert_on_tops_within_reach(plan, SMALL_STAIRS, SMALL_REACH)
    assert max(stride_ahead(plan, k) for k in range(plan.nb_steps)) > LegLimits().max_step_forward
    climbed = sorted({round(s.position[2], 9) for s in plan.steps})
    assert climbed == pytest.approx([0.0, 0.05, 0.1, 0.15, 0.2])
    for flight in SMALL_STAIRS.features:
        treads = [math.floor((s.xy[0] - flight.start) / flight.run) for s in plan.steps]
        on = [t for s, t in zip(plan.steps, treads) if flight.start < s.xy[0] < flight.end]
        assert sorted(on) == sorted(2 * list(range(flight.count - 1)))  # both feet per tread


def test_treads_longer_than_a_stride_hold_both_feet():
    terrain = Terrain([Stairs(0.3, 0.05, 0.26, 4)])  # 0.26 m run, 0.16 m stride
    plan = small_plan(terrain)
    assert_on_tops_within_reach(plan, terrain, SMALL_REACH)
    for k in range(3):
        x0 = 0.3 + k * 0.26
        sides = {s.side for s in plan.steps if x0 < s.xy[0] < x0 + 0.26}
        assert sides == {Side.LEFT, Side.RIGHT}


def test_stepping_stones_are_the_only_ground_over_the_pit():
    stones = SteppingStones(0.3, count=5, length=0.15, gap=0.08, width=0.4)
    terrain = Terrain([stones])
    reach = TerrainReach.for_leg(0.10, 0.06, 0.3)
    plan = small_plan(terrain, reach)
    assert_on_tops_within_reach(plan, terrain, reach)
    used = set()
    for step in plan.steps:
        # the ground under the whole sole is at its height: no part of it over the pit
        u, v = np.meshgrid(np.linspace(-0.05, 0.05, 41), np.linspace(-0.03, 0.03, 7))
        ground = terrain.height(step.xy[0] + u.ravel(), step.xy[1] + v.ravel())
        np.testing.assert_allclose(ground, step.position[2], atol=1e-12)
        k = math.floor((step.xy[0] - stones.start) / stones.pitch)
        if 0 <= k < stones.count and step.xy[0] - stones.start - k * stones.pitch < stones.length:
            used.add(k)
    assert used == set(range(stones.count))


#: The robustness matrix's stones for the large humanoid (seed 137): 0.39 m stones, 0.118 m
#: gaps, a 0.26 m sole whose legs step 0.3 m on the flat and reach 0.725 m on a terrain.
ATLAS_STONES = Terrain([SteppingStones(0.5, count=4, length=0.39, gap=0.1182, width=0.483)])
ATLAS_REACH = TerrainReach.for_leg(0.26, 0.13, 0.906)
ATLAS_LIMITS = dataclasses.replace(LegLimits(), max_step_forward=0.3)


def test_a_crossing_beyond_the_flat_reach_is_made_from_the_front_of_the_top():
    """The first stone is entered from the floor with no gap: the foot on its back edge
    steps to its front before crossing the first gap (the crossing then 0.47 m, where it
    went 0.665 m from the back edge to the middle of the second stone); no stride is longer
    than a stone and its gap, and every crossing lands with the margin a landing prefers (to
    the search step)."""
    planner = VelocityPlanner(ATLAS_LIMITS, StepTiming(1.0, 0.2))
    plan = planner.plan((0.1, 0.0, 0.0), 32, terrain=ATLAS_STONES, reach=ATLAS_REACH)
    assert_on_tops_within_reach(plan, ATLAS_STONES, ATLAS_REACH)
    stones, sole = ATLAS_STONES.features[0], ATLAS_REACH.sole_length
    strides = [float(s.xy[0] - plan.support_foot(k).xy[0]) for k, s in enumerate(plan.steps)]
    assert max(strides) <= stones.pitch + terrain_tops.SEARCH_STEP
    first = next(k for k, stride in enumerate(strides) if stride > ATLAS_LIMITS.max_step_forward)
    support = plan.support_foot(first).xy[0]
    front = stones.start + stones.length
    toe_room = front - (support + 0.5 * sole)
    assert (
        stones.start < support and toe_room <= ATLAS_REACH.tread_margin + terrain_tops.SEARCH_STEP
    )
    preferred = terrain_steps.PREFERRED_MARGIN * sole
    for k in range(first, len(plan.steps)):
        step = plan.steps[k]
        if step.xy[0] < stones.start + stones.count * stones.pitch:  # on the stones
            margin = ATLAS_STONES.sole_support(step.xy, step.yaw, sole, 0.13).margin
            assert (
                margin >= preferred - terrain_tops.SEARCH_STEP
                or strides[k] <= ATLAS_LIMITS.max_step_forward
            )


def test_on_a_rough_patch_the_sole_rests_on_its_highest_block(monkeypatch):
    # blocks longer than the sole (0.15 m against 0.10 m): a sole fits wholly on one
    terrain = Terrain([RoughPatch(0.3, length=1.0, width=0.6, block=0.15, height=0.02, seed=1)])

    def wholly_on_blocks(plan) -> int:
        wholly = 0
        for step in plan.steps:
            u, v = np.meshgrid(np.linspace(-0.05, 0.05, 21), np.linspace(-0.03, 0.03, 7))
            ground = terrain.height(step.xy[0] + u.ravel(), step.xy[1] + v.ravel())
            assert step.position[2] == pytest.approx(ground.max(), abs=1e-12)
            on_patch = 0.3 < step.xy[0] < 1.3
            support = terrain.sole_support(step.xy, step.yaw, 0.10, 0.06)
            wholly += on_patch and support.margin >= -1e-9
        return wholly

    preferred = wholly_on_blocks(small_plan(terrain))
    monkeypatch.setattr(terrain_steps, "ROUGH_PREFERENCE", 0.0)
    indifferent = wholly_on_blocks(small_plan(terrain))
    assert preferred > indifferent  # the places wholly on one block are preferred


def test_a_rise_beyond_the_legs_reach_names_the_step_the_distance_and_the_feature():
    terrain = Terrain([Platform(0.4, length=0.5, height=0.15)])  # 0.15 m > 0.10 m rise
    with pytest.raises(InfeasibleStep, match=r"Platform at 0.4 m") as error:
        small_plan(terrain)
    assert "+0.150 m up" in str(error.value) and "0.100 m up or down" in str(error.value)
    wide = Terrain([SteppingStones(0.3, count=3, length=0.15, gap=0.2, width=0.4)])
    with pytest.raises(InfeasibleStep, match=r"m ahead .* SteppingStones at 0.3 m"):
        small_plan(wide)


def test_a_terrain_needs_its_reach():
    with pytest.raises(ConfigurationError, match="TerrainReach.for_leg"):
        VelocityPlanner().plan((0.1, 0.0, 0.0), 4, terrain=SMALL_STAIRS)


@pytest.mark.parametrize("command", [(0.1, 0.0, 0.0), (0.1, 0.02, 0.3), (-0.05, 0.0, 0.0)])
def test_flat_plans_are_unchanged_bit_for_bit(command):
    planner = VelocityPlanner()
    plain = planner.plan(command, 12)
    for terrain in (None, FLAT):
        same = planner.plan(command, 12, terrain=terrain, reach=SMALL_REACH)
        for a, b in zip(same.steps, plain.steps):
            assert a.side is b.side and a.yaw == b.yaw
            assert np.array_equal(a.position, b.position)
    # features far away: every landing stays where it was
    far = Terrain([Stairs(20.0, 0.05, 0.15, 3)])
    placed = place_on_terrain(plain, far, SMALL_REACH)
    for a, b in zip(placed.steps, plain.steps):
        assert np.array_equal(a.position, b.position) and a.yaw == b.yaw


def test_a_walk_s_footsteps_on_a_terrain(bioloid):
    from mpcwalk.walking.footstep_planning import plan_walk_footsteps

    plan = plan_walk_footsteps(
        bioloid, command=(0.1, 0.0, 0.0), nb_steps=16, terrain=SMALL_STAIRS, reach=SMALL_REACH
    )
    assert plan.nb_steps == 17
    assert_on_tops_within_reach(plan, SMALL_STAIRS, SMALL_REACH)
    assert max(s.position[2] for s in plan.steps) == pytest.approx(0.2)
    flat = plan_walk_footsteps(bioloid, command=(0.1, 0.0, 0.0), nb_steps=16)
    same = plan_walk_footsteps(bioloid, command=(0.1, 0.0, 0.0), nb_steps=16, terrain=None)
    assert all(np.array_equal(a.position, b.position) for a, b in zip(flat.steps, same.steps))
    with pytest.raises(ConfigurationError, match="reach"):
        plan_walk_footsteps(bioloid, command=(0.1, 0.0, 0.0), nb_steps=4, terrain=SMALL_STAIRS)


def test_beyond_the_laid_ground_the_floor_holds_the_soles():
    terrain = Terrain([Platform(0.3, length=0.5, height=0.05)])
    plan = small_plan(terrain, nb_steps=90)  # 4.5 m: past the terrain's 3.8 m
    assert plan.steps[-1].xy[0] > terrain.length
    assert max(s.position[2] for s in plan.steps) == pytest.approx(0.05)
    assert all(s.position[2] == 0.0 for s in plan.steps if s.xy[0] > 1.0)


def test_a_gentle_ramp_s_foot_and_brow_ask_no_long_stride():
    """On a 3 deg ramp the soles straddle its foot and its brow, resting on the ground's
    upper hull: no stride is longer than the flat walk's. Without the straddle
    (``max_kink_deg=0``) a sole must land wholly on one side, and the ramp's foot asks a
    stride of a sole length and two margins."""
    ramp = Terrain([Slope(0.5, 1.0, 3.0)])
    flat = small_plan(FLAT, nb_steps=40)
    longest_flat = max(stride_ahead(flat, k) for k in range(flat.nb_steps))
    plan = small_plan(ramp, nb_steps=40)
    strides = [stride_ahead(plan, k) for k in range(plan.nb_steps)]
    assert max(strides) <= longest_flat + 1e-9
    # the straddling landings: on the chord or the brow, never below the ground
    kinks = (0.5, 1.5)
    straddling = 0
    for step in plan.steps:
        half = 0.5 * SMALL_REACH.sole_length
        heel, toe = step.xy[0] - half, step.xy[0] + half
        if not any(heel < kink < toe for kink in kinks):
            continue
        straddling += 1
        slope = -math.tan(step.pitch) if step.pitch else 0.0  # the sole's rise along x
        for x in np.linspace(heel, toe, 21):
            sole = step.position[2] + slope * (x - step.xy[0])
            assert sole >= ramp.height(x, step.xy[1]) - 1e-9
    assert straddling >= 2
    whole = dataclasses.replace(SMALL_REACH, max_kink_deg=0.0)
    plan = small_plan(ramp, reach=whole, nb_steps=40)
    longest = max(stride_ahead(plan, k) for k in range(plan.nb_steps))
    assert longest >= SMALL_REACH.sole_length + 2 * SMALL_REACH.tread_margin - 1e-9


@pytest.mark.parametrize("start", [0.5, 0.52, 0.55, 0.57])
def test_no_sole_centre_lands_in_the_band_about_a_crest(start):
    """A sole straddling a crest pivots on it and rests on the side of its centre: no
    centre is placed within ``CREST_BAND`` of a crest (a landing falling short of a centre
    planned just past the crest rocks back, the bioloid's fall on its 4.3 deg ramp). The
    crests of a 4 deg ramp up, a landing and a ramp down are its brow and the landing's
    end; both hollows (the ramps' feet) still hold a straddling sole."""
    ramp = Terrain([Slope(start, 0.43, 4.0), Slope(start + 0.73, 0.43, -4.0)])
    crests = (start + 0.43, start + 0.73)
    plan = small_plan(ramp, nb_steps=40)
    back, front = (share * SMALL_REACH.sole_length for share in terrain_tops.CREST_BAND)
    half = 0.5 * SMALL_REACH.sole_length
    crossed = 0
    for step in plan.steps:
        for crest in crests:
            if step.xy[0] - half < crest < step.xy[0] + half:
                crossed += 1
                assert not crest - back < step.xy[0] < crest + front, (step.xy[0], crest)
    assert crossed >= 1  # the band leaves room to straddle a crest
    hollows = (start, start + 1.16)
    assert any(
        step.xy[0] - half < hollow < step.xy[0] + half for step in plan.steps for hollow in hollows
    )
