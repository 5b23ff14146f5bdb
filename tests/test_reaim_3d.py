"""Paper A's re-aiming in 3D: a landing moved horizontally keeps its height, roll and pitch (or
takes the ground's from a height map), never flattened."""

import math

import numpy as np
import pytest
from conftest import get_robot
from stabilizer_inputs import estimated_state, stabilizer_input

from mpcwalk.control.heading_hold import _turned
from mpcwalk.control.stabilizers.footstep_reaiming import FootstepReaiming
from mpcwalk.footsteps.footstep import Footstep, FootstepPlan, Side, StepTiming
from mpcwalk.footsteps.mdat import PathWaypoint, plan_from_path
from mpcwalk.footsteps.path_follower import PathFollower
from mpcwalk.footsteps.reachability import ATLAS_REACHABILITY
from mpcwalk.gait.contact_schedule import ContactSchedule

LEFT = Footstep(Side.LEFT, [0.0, 0.12, 0.0])
RIGHT = Footstep(Side.RIGHT, [0.0, -0.12, 0.0])
#: A tread 10 cm up, pitched 10 deg and rolled 3 deg, 0.5 m ahead: beyond x_max = 0.30 m.
FAR_TREAD = Footstep(Side.LEFT, [0.5, 0.12, 0.1], 0.05, math.radians(3.0), math.radians(10.0))


def _ground(x: float, y: float) -> tuple[float, float, float]:
    """A ramp rising 0.2 m per metre along x (world pitch -atan(0.2)), level across."""
    return 0.2 * x, 0.0, -math.atan(0.2)


def test_a_clamped_landing_keeps_its_height_and_tilt():
    result = ATLAS_REACHABILITY.clamp_footstep(RIGHT, FAR_TREAD)
    landing = result.footstep
    assert result.local.was_clamped and landing.xy == pytest.approx([0.30, 0.12])
    assert landing.position[2] == 0.1
    assert (landing.roll, landing.pitch) == (FAR_TREAD.roll, FAR_TREAD.pitch)
    # with a height map the clamped landing stands on the ground where it lands
    landing = ATLAS_REACHABILITY.clamp_footstep(RIGHT, FAR_TREAD, _ground).footstep
    assert landing.position[2] == pytest.approx(0.06)
    expected = Footstep(Side.LEFT, [0.3, 0.12], landing.yaw).on_ground(*_ground(0.3, 0.12))
    np.testing.assert_allclose(landing.normal, expected.normal, atol=1e-15)
    # a reachable target is returned as it is, height map or not
    near = FAR_TREAD.moved(position=[0.2, 0.12, 0.1])
    assert ATLAS_REACHABILITY.clamp_footstep(RIGHT, near, _ground).footstep is near


def test_the_path_follower_keeps_the_tilt_of_every_landing():
    right_tread = Footstep(Side.RIGHT, [0.5, -0.12, 0.1], -0.05, -0.05, math.radians(10.0))
    follower = PathFollower(LEFT, RIGHT, [FAR_TREAD, right_tread], ATLAS_REACHABILITY)
    plan = follower.plan()
    assert follower.nb_clamped_steps >= 2 and plan.nb_steps > 2
    assert plan.steps[-2] is FAR_TREAD and plan.steps[-1] is right_tread
    for step in plan.steps:  # clamped on the way: moved, never flattened
        goal = FAR_TREAD if step.side is Side.LEFT else right_tread
        if step.position[2] == 0.0:  # a right foot's extra step towards its starting pose
            assert step.side is Side.RIGHT and step.is_flat
        else:
            assert step.position[2] == 0.1 and (step.roll, step.pitch) == (goal.roll, goal.pitch)
    assert plan.steps[0].xy == pytest.approx([0.30, 0.12])
    on_ramp = PathFollower(LEFT, RIGHT, [FAR_TREAD, right_tread], height_map=_ground).plan()
    assert on_ramp.steps[0].position[2] == pytest.approx(0.06)
    assert on_ramp.steps[0].pitch == pytest.approx(-math.atan(0.2), abs=0.01)
    waypoints = [PathWaypoint(LEFT, RIGHT), PathWaypoint(FAR_TREAD, right_tread)]
    from_path = plan_from_path(waypoints, height_map=_ground)
    assert from_path.steps[0].position[2] == pytest.approx(0.06)


def test_turning_a_step_about_the_support_keeps_its_tilt():
    turned = _turned(FAR_TREAD, RIGHT, 0.1)
    assert (turned.roll, turned.pitch, turned.position[2]) == (
        FAR_TREAD.roll,
        FAR_TREAD.pitch,
        0.1,
    )
    assert turned.yaw == pytest.approx(FAR_TREAD.yaw + 0.1)


def _tilted_schedule() -> ContactSchedule:
    steps = (
        RIGHT.moved(position=[0.5, -0.12, 0.1], roll=-0.05, pitch=math.radians(10.0)),
        LEFT.moved(position=[0.5, 0.12, 0.1], roll=0.05, pitch=math.radians(10.0)),
    )
    return ContactSchedule(FootstepPlan(LEFT, RIGHT, steps, StepTiming(step_duration=1.0)))


@pytest.mark.parametrize("height_map", [None, _ground])
def test_the_reaiming_stabilizer_keeps_or_takes_the_landings_height_and_tilt(height_map):
    robot, schedule = get_robot("atlas-like"), _tilted_schedule()
    machine = FootstepReaiming(yaw_source="sole", height_map=height_map)
    goal = schedule.plan.steps[0]
    state = estimated_state(sole_positions=(LEFT.position + [0.02, 0.0, 0.0], RIGHT.position))
    start = schedule.walk_start + 0.3  # step 0: the right foot swings
    machine.reset(stabilizer_input(robot, schedule, t=start, state=state))
    for t in (start, schedule.walk_start + 0.95):  # in the air, then landed
        inputs = stabilizer_input(robot, schedule, t=t, state=state)
        targets = machine.adjust_targets(inputs)
    landing = machine.landings[0]
    assert landing.xy == pytest.approx([0.32, -0.12]) and machine.nb_clamped == 1
    foot, before = targets.feet[Side.RIGHT], inputs.targets.feet[Side.RIGHT]
    assert before.in_contact and foot.in_contact
    if height_map is None:
        assert landing.position[2] == 0.1
        assert (landing.roll, landing.pitch) == (goal.roll, goal.pitch)
        np.testing.assert_array_equal(machine.surface_offsets[Side.RIGHT], np.zeros(3))
        assert foot.position[2] == 0.1 and (foot.roll, foot.pitch) == (goal.roll, goal.pitch)
    else:
        z, roll, pitch = landing.position[2], landing.roll, landing.pitch
        assert z == pytest.approx(0.2 * 0.32) and pitch == pytest.approx(-math.atan(0.2))
        assert foot.position[2] == pytest.approx(z, abs=1e-15)
        assert (foot.roll, foot.pitch) == pytest.approx((roll, pitch), abs=1e-15)
    # the support foot is not touched
    left = targets.feet[Side.LEFT]
    assert (left.roll, left.pitch, left.position[2]) == (0.0, 0.0, 0.0)


def test_a_path_moved_onto_the_robots_feet_keeps_its_tilts():
    from mpcwalk.walking.footstep_planning import _path_in_robot_frame

    waypoints = [PathWaypoint(LEFT, RIGHT), PathWaypoint(FAR_TREAD, RIGHT)]
    robot_left, robot_right = LEFT.moved(yaw=0.3), RIGHT.moved(yaw=0.3)
    moved = _path_in_robot_frame(waypoints, robot_left, robot_right)[1].left
    assert (moved.roll, moved.pitch) == (FAR_TREAD.roll, FAR_TREAD.pitch)
    assert moved.yaw == pytest.approx(FAR_TREAD.yaw + 0.3)
    assert moved.position[2] == pytest.approx(0.1)


def test_a_terrains_height_map_puts_a_clamped_landing_on_its_slope():
    from mpcwalk.footsteps.footstep import terrain_height_map
    from mpcwalk.terrain import Slope, Terrain

    terrain = Terrain([Slope(0.1, length=1.0, angle=10.0)])
    target = FAR_TREAD.moved(yaw=0.3)  # a turned sole: its own roll and pitch on the slope
    landing = ATLAS_REACHABILITY.clamp_footstep(RIGHT, target, terrain_height_map(terrain))
    foot = landing.footstep
    support = terrain.sole_support(foot.xy, foot.yaw, 0.2, 0.1)
    assert foot.position[2] == pytest.approx(terrain.height(*foot.xy), abs=1e-15)
    assert (foot.roll, foot.pitch) == pytest.approx((support.roll, support.pitch), abs=1e-12)
    np.testing.assert_allclose(foot.normal, terrain.normal(*foot.xy), atol=1e-12)
    assert foot.roll != 0.0 and foot.pitch < 0.0  # toes up the ramp
