"""The heading a footstep plan turns through."""

import itertools

from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.gait.contact_schedule import ContactSchedule


def planned_yaw_change(schedule: ContactSchedule, nb_stances: int) -> float:
    yaws, total = [], 0.0
    for stance in schedule.plan.stances()[:nb_stances]:
        left, right = stance[Side.LEFT].yaw, stance[Side.RIGHT].yaw
        yaws.append(left + 0.5 * float(wrap_angle(right - left)))
    for a, b in itertools.pairwise(yaws):
        total += float(wrap_angle(b - a))
    return total
