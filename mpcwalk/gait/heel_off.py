"""Heel-off of a trailing foot that steps down: the sole turns about its toe before it lifts.

In the double support before a step down the trailing foot rests on the higher tread while
the CoM moves over the lower one: with the sole flat its ankle must bend further than it can
(the G1's ankle pitch stops at 50 deg of dorsiflexion; on 0.30 m treads a flat trailing foot
needs 52.6 deg for a rise of 14 cm), and the IK then rolls and turns the pelvis to reach it.
A human lifts the heel first. Here the trailing sole pitches toe down about its toe edge over
that double support, by :data:`HEEL_OFF_PER_SOLE` per sole length of drop and at most
:data:`HEEL_OFF_PITCH` (:func:`heel_off_pitch`) (the toe stays on the tread), keeps that pitch
while it rises and travels, and returns to the landing's pitch while it lowers onto the lower
tread. Other steps are unchanged.
"""

import math

import numpy as np

from mpcwalk._checks import frozen_array
from mpcwalk.footsteps.footstep import Footstep
from mpcwalk.gait.foot_state import FootState
from mpcwalk.gait.swing_clearance import rest_to_rest, steps_down

#: Pitch [rad] (toe down) the trailing sole reaches about its toe before it steps down,
#: at most.
HEEL_OFF_PITCH = 0.35
#: Pitch [rad] per drop of one sole length (a drop of 0.83 sole reaches the most).
HEEL_OFF_PER_SOLE = 0.42


def heel_off_pitch(lift: Footstep, landing: Footstep, sole_length: float) -> float:
    """Pitch [rad] the trailing sole reaches before stepping from ``lift`` down to
    ``landing``: :data:`HEEL_OFF_PER_SOLE` per sole length of drop, at most
    :data:`HEEL_OFF_PITCH` (0 for a step that does not go down)."""
    if not steps_down(lift, landing):
        return 0.0
    drop = float(lift.position[2] - landing.position[2])
    return min(HEEL_OFF_PITCH, HEEL_OFF_PER_SOLE * drop / sole_length)


def heel_off_angle(
    share: float, duration: float, rising: bool, pitch: float = HEEL_OFF_PITCH
) -> tuple[float, float]:
    """Pitch [rad] about the toe and its rate [rad/s] a ``share`` into a motion lasting
    ``duration`` [s]: rising to ``pitch`` [rad] (``rising``) or returning from it to 0."""
    r, dr = rest_to_rest(share)
    if rising:
        return pitch * r, pitch * dr / duration
    return pitch * (1.0 - r), -pitch * dr / duration


def about_toe(state: FootState, angle: float, rate: float, length: float) -> FootState:
    """``state`` turned toe down by ``angle`` [rad] (rate ``rate`` [rad/s]) about the toe
    edge of its sole ``length`` [m] long: the centre moves forward and up."""
    if angle == 0.0 and rate == 0.0:
        return state
    half = 0.5 * length
    heading = np.array([math.cos(state.yaw), math.sin(state.yaw)])
    forward, up = half * (1.0 - math.cos(angle)), half * math.sin(angle)
    d_forward, d_up = half * math.sin(angle) * rate, half * math.cos(angle) * rate
    position = np.array(state.position, dtype=float)
    velocity = np.array(state.linear_velocity, dtype=float)
    position[:2] += forward * heading
    position[2] += up
    velocity[:2] += d_forward * heading
    velocity[2] += d_up
    return FootState(
        frozen_array(position),
        state.yaw,
        frozen_array(velocity),
        state.yaw_rate,
        state.in_contact,
        state.roll,
        state.pitch + angle,
        state.roll_rate,
        state.pitch_rate + rate,
    )


def before_lift(trajectory, state: FootState, lift: Footstep, landing: Footstep, t: float):
    """The trailing foot ``state`` resting on ``lift`` at ``t`` [s], in the double support
    before its swing to ``landing`` of ``trajectory`` (a
    :class:`~mpcwalk.gait.swing_foot.SwingFootTrajectory`): heeled off when the swing steps
    down, else unchanged."""
    length = trajectory.schedule.foot.length
    pitch = heel_off_pitch(lift, landing, length)
    if pitch == 0.0:
        return state
    phase = trajectory.schedule.phase(t)
    share = (t - phase.start) / phase.duration
    return about_toe(state, *heel_off_angle(share, phase.duration, True, pitch), length)


def in_swing(trajectory, state: FootState, lift: Footstep, landing: Footstep, phi: float):
    """The swinging foot ``state`` at the step phase ``phi`` of its shaped swing from
    ``lift`` to ``landing`` of ``trajectory``: still heeled off, then returning to the
    landing's pitch while it lowers, when it steps down; else unchanged."""
    length = trajectory.schedule.foot.length
    pitch = heel_off_pitch(lift, landing, length)
    if pitch == 0.0:
        return state
    span = trajectory.phi_e - trajectory.phi_b
    lower = trajectory.terrain_clearance.shape(lift, landing).lower_start
    width = max(1.0 - lower, 1e-9)
    share = ((phi - trajectory.phi_b) / span - lower) / width
    angle = heel_off_angle(share, width * span * trajectory.step_duration, False, pitch)
    return about_toe(state, *angle, length)


__all__ = [
    "HEEL_OFF_PER_SOLE",
    "HEEL_OFF_PITCH",
    "about_toe",
    "before_lift",
    "heel_off_angle",
    "heel_off_pitch",
    "in_swing",
]
