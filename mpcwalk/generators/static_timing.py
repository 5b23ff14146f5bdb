"""The fastest timing of a static gait, and the refusal of a timing under which it cannot walk.

Paper A's static gait moves the CoM only in double support, from above one support foot to
above the next, along a quintic of duration ``tau = r_ds T``. The ZMP of that motion is
``c - c_ddot / omega^2``: the quintic's acceleration of ``d s''(x) / tau^2`` (distance ``d``,
``s''`` peaking at ``10 / sqrt(3)``) puts the ZMP behind the shift's start and beyond its end
by up to about ``5.8 d / (tau omega)^2 - 0.07 d``. The plan is feasible when that stays on the
soles: within the distance from the foot centre to the sole's edge along the shift's direction.
This gives, for a plan, the shortest double support that works and so the fastest step
duration at a double-support ratio: the bound :func:`check_static_timing` refuses a timing
with, before anything is simulated. (The quasi-static QP, ``static-qp``, keeps the CoM over
the support polygon too and needs at least as long: the same check guards it.)
"""

import math

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.models.lipm import LIPM

_X = np.linspace(0.0, 1.0, 401)
_S = _X**3 * (10.0 - 15.0 * _X + 6.0 * _X**2)
_DDS = 60.0 * _X * (1.0 - _X) * (1.0 - 2.0 * _X)


def shift_overshoot(duration: float, omega: float) -> float:
    """How far behind its start the ZMP of a quintic CoM shift goes, as a share of the
    shift's length (by symmetry, also how far beyond its end), for a shift lasting
    ``duration`` [s] on a LIPM of natural frequency ``omega`` [1/s]."""
    return float(max(0.0, np.max(_DDS / (duration * omega) ** 2 - _S)))


def shortest_shift(share: float, omega: float) -> float:
    """Shortest duration [s] of a quintic shift whose ZMP overshoot is at most ``share`` of
    its length (bisection on :func:`shift_overshoot`, which decreases with the duration)."""
    low, high = 1e-3, 1e3
    for _ in range(60):
        mid = math.sqrt(low * high)
        if shift_overshoot(mid, omega) > share:
            low = mid
        else:
            high = mid
    return high


def _edge_distance(direction: np.ndarray, yaw: float, length: float, width: float) -> float:
    """Distance from a sole's centre to its edge along ``direction`` (unit, world frame)."""
    c, s = math.cos(yaw), math.sin(yaw)
    local = np.array([c * direction[0] + s * direction[1], -s * direction[0] + c * direction[1]])
    limits = [
        half / abs(v) for half, v in zip((0.5 * length, 0.5 * width), local) if abs(v) > 1e-12
    ]
    return min(limits)


def shortest_double_support(schedule: ContactSchedule, lipm: LIPM, margin: float = 0.0) -> float:
    """Shortest double support [s] in which every shift of the static gait between two
    support feet of ``schedule`` keeps its ZMP on the soles, ``margin`` [m] inside their
    edges (0 when the plan has fewer than two steps)."""
    plan, foot = schedule.plan, schedule.foot
    needed = 0.0
    for k in range(plan.nb_steps - 1):
        start, end = plan.support_foot(k), plan.support_foot(k + 1)
        delta = end.xy - start.xy
        distance = float(np.linalg.norm(delta))
        if distance < 1e-9:
            continue
        direction = delta / distance
        room = min(
            _edge_distance(-direction, start.yaw, foot.length, foot.width),
            _edge_distance(direction, end.yaw, foot.length, foot.width),
        )
        room -= margin
        if room <= 0.0:
            return math.inf
        needed = max(needed, shortest_shift(room / distance, lipm.omega))
    return needed


def check_static_timing(schedule: ContactSchedule, lipm: LIPM, generator: str) -> None:
    """Refuse a timing under which ``generator``'s static plan puts the ZMP off the soles.

    Raises:
        ConfigurationError: The double support ``r_ds T`` is shorter than the static gait
            needs; the message gives the fastest feasible step duration at this ``r_ds`` and
            the double-support ratio that works at this step duration.
    """
    needed = shortest_double_support(schedule, lipm)
    T, r_ds = schedule.step_duration, schedule.plan.timing.double_support_ratio
    if needed <= r_ds * T + 1e-9:
        return
    fastest = needed / r_ds if r_ds > 0.0 else math.inf
    ratio = needed / T
    other = f", or r_ds {math.ceil(ratio * 100) / 100:g} at T = {T:g} s" if ratio < 0.95 else ""
    raise ConfigurationError(
        f"The {generator} gait cannot walk this plan at T = {T:g} s, r_ds = {r_ds:g}: it "
        f"moves the CoM between the feet only in double support, and a shift lasting "
        f"{r_ds * T:.3g} s puts the ZMP off the soles (it needs {needed:.3g} s). The fastest "
        f"feasible timing is a step duration of {math.ceil(fastest * 100) / 100:g} s at "
        f"r_ds = {r_ds:g}{other}; paper A walks with 12 s steps."
    )
