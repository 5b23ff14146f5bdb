"""Footstep plans for the tests, independent of the velocity planner: alternating
footsteps along an arc."""

import numpy as np

from mpcwalk.footsteps.footstep import (
    FootGeometry,
    Footstep,
    FootstepPlan,
    Side,
    StepTiming,
    rotation_2d,
)
from mpcwalk.gait.contact_schedule import ContactSchedule


def arc_schedule(
    step,
    nb_steps=20,
    *,
    step_duration=0.5,
    r_ds=0.2,
    half_width=0.04,
    offset=(0.0, 0.0),
    turn_first=False,
):
    """Schedule of a torso moving by ``step = (dx [m], dy [m], dyaw [rad])`` per step in
    its own frame; the swing foot lands ``half_width`` beside the torso, at least
    ``2 half_width`` from the support foot. ``turn_first`` applies the yaw of a step
    before its translation. The first swing foot is on the side of the motion."""
    dx, dy, dyaw = step
    feet = {
        Side.LEFT: Footstep(Side.LEFT, np.add(offset, [0.0, half_width])),
        Side.RIGHT: Footstep(Side.RIGHT, np.add(offset, [0.0, -half_width])),
    }
    initial = dict(feet)
    side = Side.LEFT if dy > 0 or (dy == 0 and dyaw > 0) else Side.RIGHT
    torso, yaw, steps = np.array(offset, dtype=float), 0.0, []
    for _ in range(nb_steps):
        if turn_first:
            yaw += dyaw
        torso = torso + rotation_2d(yaw) @ [dx, dy]
        if not turn_first:
            yaw += dyaw
        support = feet[side.other]
        local = support.to_local(torso + rotation_2d(yaw) @ [0.0, side.sign * half_width])
        local[1] = side.sign * max(side.sign * local[1], 2.0 * half_width)
        feet[side] = Footstep(side, support.to_world(local), yaw)
        steps.append(feet[side])
        side = side.other
    plan = FootstepPlan(
        initial[Side.LEFT], initial[Side.RIGHT], steps, StepTiming(step_duration, r_ds)
    )
    return ContactSchedule(plan, FootGeometry())


def velocity_schedule(velocity, nb_steps=20, *, step_duration=0.5, r_ds=0.2, half_width=0.04):
    """:func:`arc_schedule` for a torso velocity ``(vx [m/s], vy [m/s], yaw rate [rad/s])``."""
    step = tuple(step_duration * np.asarray(velocity, dtype=float))
    return arc_schedule(
        step,
        nb_steps,
        step_duration=step_duration,
        r_ds=r_ds,
        half_width=half_width,
        turn_first=True,
    )


def tail_moved(schedule, first, delta):
    """``schedule`` with the steps from ``first`` on moved by ``delta`` (x, y) [m], built
    from it (``with_steps``: the tail of a footstep MPC's publication)."""
    steps = list(schedule.plan.steps)
    for k in range(first, len(steps)):
        position = steps[k].position
        steps[k] = steps[k].moved(position=[*(position[:2] + delta), position[2]])
    return schedule.with_steps(steps)


def kicked_walk(name, schedule, kick=(0.0, 0.0), at=1.5, **options):
    """The generator ``name`` on the small humanoid's LIPM over ``schedule``, its CoM
    velocity kicked by ``kick`` [m/s] at ``at`` [s]: the generator and its outputs."""
    from mpcwalk import LIPM, make_generator
    from mpcwalk.models.com_state import ComState

    generator = make_generator(name, lipm=LIPM(com_height=0.23), control_period=0.01, **options)
    outputs = [generator.reset(schedule)]
    while not generator.done:
        measured = None
        if abs(generator.time - at) < 1e-6:
            state = outputs[-1].state
            measured = ComState(
                state.position, state.velocity + np.asarray(kick), state.acceleration
            )
        outputs.append(generator.step(measured))
    return generator, outputs
