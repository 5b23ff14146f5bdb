"""The LIPM's push-recovery map: the largest impulse a linear inverted pendulum with the
robot's soles, leg limits and timing recovers, per push direction and phase of the step,
with 0, 1 and 2 steps (:mod:`mpcwalk.footsteps.capturability`, Koolen 2012). It is the
reference the controllers' push maps are drawn against.

The walk is the robot's nominal one (straight, at its nominal speed, the linear MPC's plan on
the LIPM), its DCM at each phase taken relative to the foot the robot stands on. In single
support the first step is the swinging leg's, landing when the schedule says (``fixed``) or
as early as the swing allows (``earliest``: what a step-timing adaptation could do); in
double support the robot stands on the hull of both feet and the first step is the next
planned one's, from the rear foot.
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.footsteps.capturability import (
    Box,
    capture_regions,
    flywheel_regions,
    largest_impulse,
    sole_box,
)
from mpcwalk.footsteps.footstep import FootGeometry, StepTiming
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators import make_generator, rollout
from mpcwalk.ik.upper_body import upper_body_flywheel
from mpcwalk.models.flywheel import cmp_offset_bound
from mpcwalk.models.lipm import LIPM

#: Shortest swing [s] an adapted step keeps (lift-off, clearance, touch-down).
MIN_SWING = 0.15


@dataclass(frozen=True)
class CaptureCell:
    """One cell of the map: the push direction [deg] (robot frame, 0 forward, 90 left), the
    phase (share of the step, 0 at its start), and the largest impulse [N s] with at most
    0, 1 and 2 steps, the first landing at the schedule's time (``fixed``) or at the best
    time between the earliest the swing allows and the schedule's (``adaptive``), and with the
    robot's upper body as a flywheel at the schedule's time (``flywheel``: the LIPM with a
    flywheel of Pratt 2006, its limits :func:`~mpcwalk.ik.upper_body.upper_body_flywheel`'s)."""

    direction_deg: float
    phase: float
    single_support: bool
    fixed: tuple[float, float, float]
    adaptive: tuple[float, float, float]
    flywheel: tuple[float, float, float] = (0.0, 0.0, 0.0)


def capture_map(
    robot,
    *,
    nb_directions: int = 16,
    nb_phases: int = 6,
    speed_share: float = 1.0,
    push_step: int = 2,
    nb_steps: int = 6,
    delay: float = 0.0,
    flywheel_offset: tuple[float, float] | None = None,
) -> list[CaptureCell]:
    """The map of ``robot`` (a :class:`~mpcwalk.robot.Robot`) walking straight at
    ``speed_share`` of its nominal speed (the forward speed of a walk given no command,
    :meth:`~mpcwalk.footsteps.velocity_planner.VelocityPlanner.default_command`, as in the
    controllers' push map). ``delay`` [s]: the impulse acts that long after the phase's
    time (a push of duration ``2 delay`` starting at the phase acts, in the mean, at its
    middle; the cell keeps its phase, ``single_support`` says where the impulse acts).
    ``flywheel_offset`` [m]: how far the upper body moves the capture point along x and y
    (None: :func:`~mpcwalk.models.flywheel.cmp_offset_bound` of the robot's upper body)."""
    gait, limits = robot.gait, robot.leg_limits
    timing = StepTiming(gait.step_duration, gait.double_support_ratio)
    from mpcwalk.footsteps.velocity_planner import VelocityPlanner
    from mpcwalk.walking.footstep_planning import plan_walk_footsteps

    speed = speed_share * VelocityPlanner(limits, timing).default_command().vx
    plan = plan_walk_footsteps(robot, command=(speed, 0.0, 0.0), nb_steps=nb_steps, timing=timing)
    schedule = ContactSchedule(plan, FootGeometry(*robot.sole_size))
    lipm = LIPM(com_height=robot.com_height)
    walk = rollout(make_generator("mpc", lipm=lipm), schedule)
    omega, mass = lipm.omega, robot.total_mass
    if flywheel_offset is None:
        flywheel_offset = cmp_offset_bound(upper_body_flywheel(robot), omega)
    sole, reach = sole_box(*robot.sole_size), limits.rectangle()
    T, t_b, t_e = timing.step_duration, schedule.t_b, schedule.t_e
    cells = []
    for j in range(nb_phases):
        share = (j + 0.5) / nb_phases
        t = schedule.walk_start + (push_step + share) * T + delay
        i = min(int(np.searchsorted(walk.times, t)), len(walk.times) - 1)
        dcm_world = walk.com[i] + walk.com_velocity[i] / omega
        step_k, local = divmod(t - schedule.walk_start, T)  # the step the impulse acts in
        step_k = int(step_k)
        step = plan.steps[step_k]
        single = t_b <= local < t_e
        if single:  # on the support foot, the swing leg steps first
            stance = plan.support_foot(step_k)
            first_swing, support = step.side, sole
            remaining = t_e - local
            earliest = min(max(MIN_SWING - (local - t_b), 0.02), remaining)
        else:  # in double support: the hull of both feet, the next step from the rear foot
            k = step_k if local < t_b else step_k + 1
            k = min(k, plan.nb_steps - 1)
            nxt, feet = plan.steps[k], plan.stance(k)  # the feet on the ground before step k
            stance, other = feet[nxt.side.other], feet[nxt.side]
            offset = other.xy - stance.xy
            support = Box(
                min(sole.x_low, sole.x_low + offset[0]),
                max(sole.x_high, sole.x_high + offset[0]),
                min(sole.y_low, sole.y_low + offset[1]),
                max(sole.y_high, sole.y_high + offset[1]),
            )
            first_swing = nxt.side
            start = t_b if local < t_b else T + t_b
            remaining = start + (t_e - t_b) - local
            earliest = max(start - local, 0.0) + MIN_SWING
        dcm = dcm_world - stance.xy  # straight walking: the stance frame is the world's
        landings = np.linspace(min(earliest, remaining), remaining, 8)
        options = []
        for first in landings:
            regions = capture_regions(
                2,
                omega=omega,
                sole=sole,
                reach=reach,
                first_swing=first_swing,
                first_step_time=float(first),
                step_time=T,
            )
            regions[0] = support  # standing: on the support of the moment
            options.append(regions)
        for d in range(nb_directions):
            angle = 2.0 * math.pi * d / nb_directions

            def impulses(regions: list[Box], angle: float = angle, dcm=dcm) -> np.ndarray:
                return np.array(
                    [
                        largest_impulse(regions[: n + 1], dcm, angle, mass=mass, omega=omega)
                        for n in range(3)
                    ]
                )

            fixed = impulses(options[-1])
            adaptive = np.max([impulses(regions) for regions in options], axis=0)
            flywheel = impulses(flywheel_regions(options[-1], flywheel_offset))
            cells.append(
                CaptureCell(
                    round(math.degrees(angle), 3),
                    round(share, 4),
                    bool(single),
                    (float(fixed[0]), float(fixed[1]), float(fixed[2])),
                    (float(adaptive[0]), float(adaptive[1]), float(adaptive[2])),
                    (float(flywheel[0]), float(flywheel[1]), float(flywheel[2])),
                )
            )
    return cells


__all__ = ["MIN_SWING", "CaptureCell", "capture_map"]
