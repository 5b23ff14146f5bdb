"""Run a pattern generator over a whole schedule (open loop, on the LIPM)."""

from dataclasses import dataclass

import numpy as np

from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.pattern_generator import PatternGenerator, timed_step
from mpcwalk.models.com_state import ComState


@dataclass(frozen=True)
class Rollout:
    """Planned trajectory of a generator over a schedule.

    Attributes:
        generator: Generator name.
        times: Shape (n,), in [s].
        com: CoM ground projection, shape (n, 2), in [m].
        com_velocity: Shape (n, 2), in [m]/[s].
        com_acceleration: Shape (n, 2), in [m]/[s]^2.
        zmp: Shape (n, 2), in [m].
        tick_times: Wall time of each step() call, shape (n - 1,), in [s].
        nb_failures: Ticks whose QP failed (a fallback plan was used).
    """

    generator: str
    times: np.ndarray
    com: np.ndarray
    com_velocity: np.ndarray
    com_acceleration: np.ndarray
    zmp: np.ndarray
    tick_times: np.ndarray
    nb_failures: int = 0


def rollout(
    generator: PatternGenerator,
    schedule: ContactSchedule,
    initial_state: ComState | None = None,
    *,
    feedback: bool = False,
) -> Rollout:
    """Step a generator from reset to the end of the schedule.

    Args:
        generator: Any pattern generator.
        schedule: Footsteps and timing.
        initial_state: CoM state at time 0 (default: at rest between the feet).
        feedback: Pass each output back as the measured state of the next tick
            (exercises the closed-loop path on a perfect LIPM plant).

    Returns:
        The planned trajectory and per-tick wall times.
    """
    outs = [generator.reset(schedule, initial_state)]
    ticks = []
    failures = 0
    while not generator.done:
        measured = outs[-1].state if feedback else None
        out, dt = timed_step(generator, measured)
        outs.append(out)
        ticks.append(dt)
        if out.solve is not None and not out.solve.success:
            failures += 1
    return Rollout(
        generator=generator.name,
        times=np.array([o.time for o in outs]),
        com=np.array([o.com for o in outs]),
        com_velocity=np.array([o.com_velocity for o in outs]),
        com_acceleration=np.array([o.com_acceleration for o in outs]),
        zmp=np.array([o.zmp for o in outs]),
        tick_times=np.array(ticks),
        nb_failures=failures,
    )
