"""Reachability rectangle and paper A's path follower."""

import numpy as np
import pytest

from mpcwalk.exceptions import ConfigurationError, InfeasibleStep
from mpcwalk.footsteps.footstep import Footstep, Side
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.footsteps.path_follower import PathFollower
from mpcwalk.footsteps.reachability import (
    ATLAS_REACHABILITY,
    SMALL_HUMANOID_REACHABILITY,
    ReachabilityRectangle,
    opening_side,
)

RECT = ATLAS_REACHABILITY  # x [-0.15, 0.30], y [0.18, 0.40], yaw [-0.4, 0.4]
LEFT0 = Footstep(Side.LEFT, [0.0, 0.12, 0.0])
RIGHT0 = Footstep(Side.RIGHT, [0.0, -0.12, 0.0])


def test_target_inside_is_unchanged():
    result = RECT.clamp([0.1, 0.25], 0.1, Side.LEFT)
    np.testing.assert_array_equal(result.xy, [0.1, 0.25])
    assert result.yaw == 0.1 and not result.was_clamped
    np.testing.assert_array_equal(result.remainder, np.zeros(3))
    target = Footstep(Side.LEFT, [0.2, 0.1, 0.0], 0.2)
    assert RECT.clamp_footstep(RIGHT0, target).footstep is target


def test_outside_is_clamped_to_the_nearest_point_with_the_remainder():
    result = RECT.clamp([0.5, 0.25], 0.0, Side.LEFT)
    np.testing.assert_allclose(result.xy, [0.30, 0.25])
    np.testing.assert_allclose(result.remainder, [0.2, 0.0, 0.0], atol=1e-15)
    assert result.was_clamped
    # right swing foot: mirrored y, a crossing target is pushed back to its own side
    result = RECT.clamp([0.1, 0.05], 0.0, Side.RIGHT)
    np.testing.assert_allclose(result.xy, [0.1, -0.18])
    np.testing.assert_allclose(result.remainder, [0.0, 0.23, 0.0], atol=1e-15)
    # asymmetric yaw bounds are mirrored too: left [-0.2, 0.35], right [-0.35, 0.2]
    small = SMALL_HUMANOID_REACHABILITY
    assert small.clamp([0.0, 0.1], -0.3, Side.LEFT).yaw == pytest.approx(-0.2)
    assert small.clamp([0.0, -0.1], -0.3, Side.RIGHT).yaw == pytest.approx(-0.3)
    assert small.clamp([0.0, -0.1], 0.3, Side.RIGHT).yaw == pytest.approx(0.2)
    assert small == LegLimits().rectangle()


def test_clamp_is_the_nearest_point_of_the_rectangle():
    rng = np.random.default_rng(0)
    grid = np.stack(
        np.meshgrid(np.linspace(-0.15, 0.30, 46), np.linspace(-0.40, -0.18, 23)), -1
    ).reshape(-1, 2)
    for target in rng.uniform(-1.0, 1.0, size=(50, 2)):
        clamped = RECT.clamp(target, 0.0, Side.RIGHT).xy
        assert RECT.contains(clamped, 0.0, Side.RIGHT)
        best = np.min(np.linalg.norm(grid - target, axis=1))
        assert np.linalg.norm(clamped - target) <= best + 1e-12


def test_world_clamp_uses_the_support_foot_frame():
    support = Footstep(Side.RIGHT, [1.0, 2.0, 0.0], np.pi / 2)  # facing +y
    target = Footstep(Side.LEFT, [0.5, 2.6, 0.0], np.pi / 2)  # 0.6 ahead, 0.5 to the left
    clamped = RECT.clamp_footstep(support, target)
    np.testing.assert_allclose(clamped.local.xy, [0.30, 0.40])
    np.testing.assert_allclose(clamped.footstep.xy, [0.6, 2.3], atol=1e-12)
    np.testing.assert_allclose(clamped.local.remainder, [0.3, 0.1, 0.0], atol=1e-12)


def test_remainder_is_carried_so_the_next_step_of_that_foot_ends_on_target():
    # the right foot's step of 0.4 m exceeds x_max = 0.3 m; the closing step is fine
    targets = [Footstep(Side.RIGHT, [0.4, -0.12, 0.0]), Footstep(Side.LEFT, [0.4, 0.12, 0.0])]
    follower = PathFollower(LEFT0, RIGHT0, targets, RECT)
    plan = follower.plan()
    xs = [(s.side, round(float(s.xy[0]), 12)) for s in plan.steps]
    # R clamped at 0.30; L re-aims at its file pose 0.0, nearest safe point 0.30 - 0.15;
    # R re-aims at 0.4 from there (0.25 ahead: reached); L closes on target.
    assert xs == [(Side.RIGHT, 0.30), (Side.LEFT, 0.15), (Side.RIGHT, 0.4), (Side.LEFT, 0.4)]
    assert follower.nb_clamped_steps == 2 and follower.nb_extra_steps == 2


def test_measured_drift_does_not_accumulate():
    targets = [
        Footstep(
            Side.RIGHT if k % 2 == 0 else Side.LEFT,
            [0.2 * (k + 1), -0.12 if k % 2 == 0 else 0.12, 0.0],
        )
        for k in range(6)
    ]
    follower = PathFollower(LEFT0, RIGHT0, targets, RECT)
    feet = {Side.LEFT: LEFT0, Side.RIGHT: RIGHT0}
    rng = np.random.default_rng(1)
    for k in range(6):
        side = follower.next_swing_side
        # the measured support foot slipped by up to 3 cm and 3 deg
        measured = feet[side.other].moved(
            position=feet[side.other].position + [*rng.uniform(-0.03, 0.03, 2), 0.0],
            yaw=feet[side.other].yaw + rng.uniform(-0.05, 0.05),
        )
        landing = follower.next_step(measured, feet[side])
        np.testing.assert_allclose(landing.xy, targets[k].xy, atol=1e-12)  # aims at the file pose
        assert landing.yaw == pytest.approx(targets[k].yaw, abs=1e-12)
        feet[side] = landing
    assert follower.finished and follower.nb_extra_steps == 0
    assert follower.plan().steps == tuple(follower.steps_taken) and len(follower.steps_taken) == 6


def test_unreachable_target_raises_naming_the_step_and_the_limit():
    targets = [Footstep(Side.LEFT, [0.0, 1.12, 0.0])]  # 1.24 m lateral, limit 0.40 m
    follower = PathFollower(
        LEFT0, RIGHT0, targets, RECT, labels=["waypoint 1 (line 7)"], max_extra_steps=10
    )
    with pytest.raises(
        InfeasibleStep, match=r"waypoint 1 \(line 7\).*y = 1\.24 m above its limit 0\.4 m"
    ) as info:
        follower.plan()
    assert "after 10 extra steps" in str(info.value)
    # a far forward target is approached but not within the bound either
    far = PathFollower(
        LEFT0, RIGHT0, [Footstep(Side.RIGHT, [5.0, -0.12, 0.0])], RECT, max_extra_steps=6
    )
    with pytest.raises(InfeasibleStep, match=r"target 0.*x = .* above its limit 0\.3 m"):
        far.plan()


def test_bad_inputs():
    with pytest.raises(ConfigurationError, match="x_min <= x_max"):
        ReachabilityRectangle(0.3, -0.1, 0.1, 0.2, -0.1, 0.1)
    with pytest.raises(ConfigurationError, match="y_min must be positive"):
        ReachabilityRectangle(-0.1, 0.3, 0.0, 0.2, -0.1, 0.1)
    with pytest.raises(ConfigurationError, match="must be different feet"):
        PathFollower(LEFT0, RIGHT0, []).next_step(LEFT0, LEFT0)
    follower = PathFollower(LEFT0, RIGHT0, [])
    assert follower.finished
    with pytest.raises(ConfigurationError, match="finished"):
        follower.next_step(RIGHT0, LEFT0)


def test_opening_side():
    assert opening_side(0.05, -0.3) is Side.LEFT  # lateral decides first
    assert opening_side(0.0, -0.3) is Side.RIGHT
    assert opening_side(0.0, 0.3) is Side.LEFT
    assert opening_side(0.0, 0.0) is Side.RIGHT
