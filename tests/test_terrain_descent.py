"""Stepping down stairs: the landing keeps room behind its heel for a swing foot that falls
short of its target, and the swing lowers only once its travel has ended, so that the heel
does not catch the nose it steps down from (what made the G1 fall on its first steps down:
its swing sole fell 4-5 cm short of a landing whose heel was 4.3 cm from the nose)."""

import numpy as np
import pytest

from mpcwalk.footsteps import LegLimits, StepTiming, VelocityPlanner
from mpcwalk.footsteps.footstep import FootGeometry, Side
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.heel_off import heel_off_pitch
from mpcwalk.gait.swing_clearance import SwingClearance
from mpcwalk.gait.swing_foot import SwingFootTrajectory
from mpcwalk.terrain import Stairs, Terrain, TerrainReach
from mpcwalk.walking.runner import run_walk
from mpcwalk.walking.specification import WalkSpec

#: The G1's stairs of the measurements: 5 up and 5 down of 12 cm, treads 1.5 soles.
G1_STAIRS = Terrain([Stairs(0.4, 0.12, 0.30, 5), Stairs(2.2, -0.12, 0.30, 5)])
G1_REACH = TerrainReach.for_leg(0.20, 0.07, 0.661)
G1_LIMITS = LegLimits(0.2, 0.1, 0.08, 0.35, 0.2, 0.08, 0.1185)


def steps_down(plan):
    """The landings of ``plan`` below the height their foot lifted off from."""
    feet = {Side.LEFT: plan.initial_left, Side.RIGHT: plan.initial_right}
    for step in plan.steps:
        lift = feet[step.side]
        feet[step.side] = step
        if step.position[2] < lift.position[2] - 0.01:
            yield lift, step


def heel_room(terrain, x_heel: float, y: float, height: float) -> float:
    """Distance [m] from a heel at ``x_heel`` back to the nearest ground higher than
    ``height`` + 1 cm."""
    xs = x_heel - np.linspace(0.0, 0.3, 601)
    higher = np.asarray(terrain.height(xs, np.full_like(xs, y))) > height + 0.01
    return float(x_heel - xs[np.argmax(higher)])


def g1_walk(controller: str, terrain: Terrain, nb_steps: int):
    """The G1 walking ``terrain`` at 0.1 m/s, T = 1.5 s, in closed loop on its estimator."""
    spec = WalkSpec.build(
        "g1",
        controller=controller,
        command=(0.1, 0.0, 0.0),
        nb_steps=nb_steps,
        step_duration=1.5,
        terrain=terrain,
        progress=False,
    )
    return run_walk(spec)


def g1_plan():
    planner = VelocityPlanner(G1_LIMITS, StepTiming(1.5, 0.2, 1.0, 1.0))
    return planner.plan((0.1, 0.0, 0.0), 30, terrain=G1_STAIRS, reach=G1_REACH)


def test_a_step_down_lands_towards_the_front_of_the_lower_tread():
    """On the G1's stairs every step down onto a tread keeps 7 cm behind its heel (5 cm, the
    centred sole, without the room), and its toe the tread margin from the next nose."""
    downs = list(steps_down(g1_plan()))
    assert len(downs) == 10  # 5 rises, two feet per tread
    rooms = [heel_room(G1_STAIRS, s.xy[0] - 0.1, s.xy[1], s.position[2]) for _, s in downs]
    assert min(rooms[:-1]) >= 0.069, rooms  # the last one lands on the floor
    for _, step in downs:
        support = G1_STAIRS.sole_support(step.xy, step.yaw, 0.20, 0.07)
        assert support.margin >= G1_REACH.tread_margin - 1e-9


def test_a_step_down_swing_lowers_only_after_its_travel():
    """The shaped swing of a step down travels at its apex, then lowers straight onto the
    tread; a step up still overlaps its travel with the rise."""
    plan = g1_plan()
    clearance = SwingClearance(G1_STAIRS, FootGeometry(0.20, 0.07), 0.06)
    downs = list(steps_down(plan))
    for lift, landing in downs:
        shape = clearance.shape(lift, landing)
        assert shape is not None and shape.travel_end <= shape.lower_start + 1e-12
        _, _, z, _ = shape.at(shape.travel_end)
        assert z == shape.apex  # the sole is at its apex when it reaches the landing's x
    lift, landing = next((a, b) for a, b in zip(plan.steps, plan.steps[2:]) if b.position[2] > 0.2)
    up = clearance.shape(lift, landing)
    assert up is not None and up.travel_start < up.rise_end  # climbing overlaps as before


def test_a_step_down_swing_restarted_for_a_moved_landing_still_lowers_after_its_travel():
    """A footstep-adaptive generator moves a step down's landing in mid-swing: the swing goes
    on from where the foot is on the shaped swing's travel law, so it reaches the new
    landing's x before it lowers (on the whole swing's interpolant it travelled while it
    lowered and the G1's heel came down on the nose)."""
    schedule = ContactSchedule(g1_plan(), FootGeometry(0.20, 0.07))
    k, (_, landing) = next(
        (k, pair)
        for k, pair in enumerate(zip(schedule.plan.steps, schedule.plan.steps[2:]), start=2)
        if pair[1].position[2] < pair[0].position[2] - 0.01
    )
    landing_time = schedule.walk_start + k * schedule.step_duration + schedule.t_e
    lift_time = landing_time - (schedule.t_e - schedule.t_b)
    before = SwingFootTrajectory(schedule, 0.06, terrain=G1_STAIRS)
    t = lift_time + 0.35 * (landing_time - lift_time)  # travelling at the apex
    moved = list(schedule.plan.steps)
    moved[k] = landing.moved(position=[landing.xy[0] - 0.01, landing.xy[1], landing.position[2]])
    after = SwingFootTrajectory(schedule.with_steps(moved), 0.06, terrain=G1_STAIRS)
    after.restart_swing(t, before.foot_poses(t)[landing.side])
    times = np.linspace(t, landing_time - 1e-6, 200)
    poses = [after.foot_poses(x)[landing.side] for x in times]
    x = np.array([p.position[0] for p in poses])
    z = np.array([p.position[2] for p in poses])
    lowering = z < z.max() - 1e-6
    assert lowering.any() and not lowering[0]
    assert np.ptp(x[lowering]) < 1e-9  # measured: 0 (on the whole swing's law: 8.9 cm)
    assert x[-1] == pytest.approx(landing.xy[0] - 0.01)


def test_a_trailing_foot_heels_off_about_its_toe_before_it_steps_down():
    """Through the double support before a step down the trailing sole turns toe down
    about its toe (the toe stays where it rests), keeps that pitch while it rises and
    travels, and lands flat; a step onto the same height keeps its sole flat."""
    plan = g1_plan()
    schedule = ContactSchedule(plan, FootGeometry(0.20, 0.07))
    trajectory = SwingFootTrajectory(schedule, 0.06, terrain=G1_STAIRS)
    k, (lift, landing) = next(
        (k, (plan.stance(k)[s.side], s))
        for k, s in enumerate(plan.steps)
        if s.position[2] < plan.stance(k)[s.side].position[2] - 0.01
    )
    pitch = heel_off_pitch(lift, landing, 0.20)
    assert pitch == pytest.approx(0.42 * 0.12 / 0.20)  # per sole length of drop
    start = schedule.walk_start + k * schedule.step_duration
    lift_off, touch_down = start + schedule.t_b, start + schedule.t_e
    for t in np.linspace(start, lift_off, 7)[1:]:
        foot = trajectory.foot_poses(t)[landing.side]
        toe = foot.position[:2] + 0.1 * np.cos(foot.pitch) * np.array([1.0, 0.0])
        np.testing.assert_allclose(toe, lift.xy + [0.1, 0.0], atol=1e-9)
        assert foot.position[2] == pytest.approx(lift.position[2] + 0.1 * np.sin(foot.pitch))
    assert trajectory.foot_poses(lift_off)[landing.side].pitch == pytest.approx(pitch)
    middle = trajectory.foot_poses(0.5 * (lift_off + touch_down))[landing.side]
    assert middle.pitch == pytest.approx(pitch)
    landed = trajectory.foot_poses(touch_down)[landing.side]
    assert landed.pitch == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(landed.position, landing.position, atol=1e-9)
    level = next(k for k, s in enumerate(plan.steps) if k > 2 and s.position[2] == 0.6)
    t = schedule.walk_start + (level + 0.05) * schedule.step_duration
    assert trajectory.foot_poses(t)[plan.steps[level].side].pitch == 0.0


def test_the_g1_steps_down_a_quarter_of_its_leg():
    """Closed loop on the estimator, the G1 with ``mpc``: two stairs down of 16.5 cm (25 %
    of its leg), treads 1.5 soles. Without the heel-off its trailing ankle stops at 50 deg
    of dorsiflexion in the double support between the two heights, the IK turns the pelvis
    and the robot falls at 6.2 s, in its first step down."""
    result = g1_walk("mpc", Terrain([Stairs(0.4, rise=-0.165, run=0.30, count=2)]), 4)
    m = result.metrics
    assert not m.fell and m.steps_completed == m.steps_planned == 5
    heights = [round(float(s.position[2]), 6) for s in result.schedule.plan.steps]
    assert heights[-2:] == [-0.165, -0.165]  # both feet on the first lower tread
    assert m.toe_stubs == 0 and m.landing_height_error_cm_max < 1.0


def test_the_g1_with_mpc_steps_goes_down_stairs_without_turning():
    """Closed loop on the estimator, the G1 with ``mpc-steps``: two stairs of 10 cm up and
    two down, T = 1.5 s. With the capture-point term on (the default before, on a terrain
    too) the DCM errors of the steps grew by up to e^(omega T) into landings that jumped
    between their lateral bounds from one tick to the next; the swing leg whipped the stance
    foot round and the walk stopped after 7 of 15 steps, turned by 20.3 deg. On a terrain
    the term is now off unless asked for: 15/15, turned by 0.3 deg."""
    terrain = Terrain([Stairs(0.4, 0.10, 0.30, 2), Stairs(1.3, -0.10, 0.30, 2)])
    result = g1_walk("mpc-steps", terrain, 14)
    m = result.metrics
    assert m.outcome == "walked" and m.steps_completed == m.steps_planned == 15
    heights = {round(float(s.position[2]), 6) for s in result.schedule.plan.steps}
    assert heights == {0.0, 0.1, 0.2}  # up two treads, down again
    final_yaw = np.degrees(result.log.base_rpy[-1, 2])
    assert abs(final_yaw) < 2.0  # measured 0.3 deg (before: 20.3 deg, stopped)
    assert m.landing_error_3d_cm_max < 8.0  # measured 5.08 cm
