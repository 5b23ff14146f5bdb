"""Stepping down stairs: the landing keeps room behind its heel for a swing foot that falls
short of its target, and the swing lowers only once its travel has ended, so that the heel
does not catch the nose it steps down from (what made the G1 fall on its first steps down:
its swing sole fell 4-5 cm short of a landing whose heel was 4.3 cm from the nose)."""

import numpy as np

from mpcwalk.footsteps import LegLimits, StepTiming, VelocityPlanner
from mpcwalk.footsteps.footstep import FootGeometry, Side
from mpcwalk.gait.swing_clearance import SwingClearance
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


def test_the_small_humanoid_walks_down_stairs_of_23_percent_of_its_leg():
    """Closed loop on the estimator: two steps up and two down of 5 cm (23 % of the leg),
    treads 1.5 soles; every step completed, every landing on its tread."""
    terrain = Terrain(
        [Stairs(0.15, rise=0.05, run=0.15, count=2), Stairs(0.6, rise=-0.05, run=0.15, count=2)]
    )
    spec = WalkSpec.build(
        "bioloid-like",
        controller="mpc",
        command=(0.05, 0.0, 0.0),
        nb_steps=16,
        step_duration=0.8,
        terrain=terrain,
        progress=False,
    )
    result = run_walk(spec)
    m = result.metrics
    assert not m.fell and m.steps_completed == m.steps_planned
    assert m.landing_height_error_cm_max < 1.0
    assert len(list(steps_down(result.schedule.plan))) == 4
    final = result.log.sole_positions[-1]
    assert final[:, 0].min() > 0.9 and abs(final[:, 2]).max() < 0.005  # past the stairs
