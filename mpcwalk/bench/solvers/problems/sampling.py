"""Problems sampled from walks: each family's generator walks a plan once on the LIPM
(:func:`reference_walk`), then :func:`sample_problems` takes the family's QP at ticks of that
walk (:func:`snapshot_ticks`), at given horizons, some with a push."""

from dataclasses import dataclass

import numpy as np

from mpcwalk.bench.solvers.problems.families import (
    WALKS,
    WalkingProblem,
    families,
    get_family,
    walk_schedule,
)
from mpcwalk.gait.contact_schedule import ContactSchedule


@dataclass(frozen=True)
class ReferenceWalk:
    """States of a family's generator along a walk (open loop, on the LIPM).

    Attributes:
        family: Family name.
        walk: Walk name.
        nb_steps: Steps.
        times: Tick times, shape (n,), in [s].
        states: Cart-table states, shape (n, 3, 2).
        nb_failures: Ticks whose QP failed during the walk.
    """

    family: str
    walk: str
    nb_steps: int
    times: np.ndarray
    states: np.ndarray
    nb_failures: int


def reference_walk(
    family: str, walk: str, nb_steps: int, control_period: float = 0.01
) -> ReferenceWalk:
    """Walk the family's generator over ``walk`` (its default horizon and solver)."""
    from mpcwalk.generators import make_generator, rollout

    fam = get_family(family)
    schedule = walk_schedule(fam.timing, walk, nb_steps)
    generator = make_generator(
        fam.generator, control_period=control_period, **fam.generator_options()
    )
    traj = rollout(generator, schedule)
    states = np.stack([traj.com, traj.com_velocity, traj.com_acceleration], axis=1)
    return ReferenceWalk(family, walk, nb_steps, traj.times, states, traj.nb_failures)


def snapshot_ticks(
    schedule: ContactSchedule, control_period: float, nb_snapshots: int, phase_offset: float = 0.5
) -> list[int]:
    """Ticks spread over the walking part of ``schedule``, at varied step phases.

    Snapshot ``j`` lies in step ``round((j + 0.5) / S * nb_steps)`` at phase
    ``(j + phase_offset) / S`` of it, so the snapshots meet double and single
    support at different points.
    """
    nb_steps = schedule.plan.nb_steps
    T = schedule.step_duration
    ticks = []
    for j in range(nb_snapshots):
        step = min(int(round((j + 0.5) / nb_snapshots * (nb_steps - 1))), nb_steps - 1)
        phase = ((j + phase_offset) / nb_snapshots) % 1.0
        ticks.append(int(round((schedule.walk_start + (step + phase) * T) / control_period)))
    return ticks


def sample_problems(
    ref: ReferenceWalk,
    horizons,
    *,
    nb_nominal: int,
    nb_pushed: int,
    push_speed: float = 0.1,
    warmup_ticks: int = 3,
    control_period: float = 0.01,
    seed: int = 0,
) -> list[WalkingProblem]:
    """Problems at ticks of a reference walk, at each horizon.

    Args:
        ref: The family's reference walk.
        horizons: Horizons (numbers of samples) of each snapshot.
        nb_nominal: Snapshots at the walk's own states.
        nb_pushed: Snapshots with a push: the CoM velocity gets ``push_speed``
            in a random direction (drawn from ``seed``, the family and the walk).
        push_speed: In [m/s].
        warmup_ticks: Preceding ticks kept for warm starts.
        control_period: Tick of ``ref``, in [s].
        seed: Random seed of the push directions.
    """
    fam = get_family(ref.family)
    schedule = walk_schedule(fam.timing, ref.walk, ref.nb_steps)
    names = sorted(families())
    rng = np.random.default_rng([seed, names.index(ref.family), list(WALKS).index(ref.walk)])
    snapshots = [(t, False) for t in snapshot_ticks(schedule, control_period, nb_nominal, 0.5)]
    snapshots += [(t, True) for t in snapshot_ticks(schedule, control_period, nb_pushed, 0.25)]
    out = []
    for tick, pushed in snapshots:
        tick = int(np.clip(tick, warmup_ticks, len(ref.times) - 1))
        state = ref.states[tick].copy()
        if pushed:
            angle = rng.uniform(0.0, 2.0 * np.pi)
            state[1] += push_speed * np.array([np.cos(angle), np.sin(angle)])
        warm = slice(tick - warmup_ticks, tick)
        for horizon in horizons:
            params = fam.parameters_for(horizon)
            name = f"{ref.family}-{ref.walk}-n{int(horizon)}-k{tick}" + ("-push" if pushed else "")
            out.append(
                WalkingProblem(
                    name=name,
                    family=ref.family,
                    walk=ref.walk,
                    nb_steps=ref.nb_steps,
                    horizon=int(horizon),
                    sampling_period=params.sampling_period,
                    control_period=control_period,
                    tick=tick,
                    time=float(ref.times[tick]),
                    state=state,
                    pushed=pushed,
                    warmup_times=ref.times[warm].copy(),
                    warmup_states=ref.states[warm].copy(),
                )
            )
    return out
