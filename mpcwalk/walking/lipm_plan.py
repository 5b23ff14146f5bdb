"""Plan a walk on the LIPM alone: footsteps from a velocity command, CoM/ZMP from a
pattern generator, and the metrics of the plan (the ``mpcwalk plan`` job)."""

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from mpcwalk.footsteps.footstep import FootGeometry, StepTiming
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.footsteps.velocity_planner import VelocityCommand, VelocityPlanner
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.support_margins import support_margins
from mpcwalk.generators import generator_class, make_generator, rollout
from mpcwalk.generators.rollout import Rollout
from mpcwalk.models.lipm import LIPM


@dataclass(frozen=True)
class WalkPlan:
    """A planned walk and its metrics.

    Attributes:
        schedule: Footsteps and contact phases.
        rollout: CoM/ZMP trajectory of the generator.
        zmp_reference: Paper M's polygonal ZMP reference at the rollout times, shape (n, 2).
        zmp_margins: Signed ZMP distance to the support polygon, shape (n,), in [m].
        com_margins: Same for the CoM ground projection, shape (n,), in [m].
        metrics: JSON-ready summary: ``nb_steps`` (the steps asked for), ``closing_steps``,
            ``steps_planned`` (both), ``duration_s`` [s], planned ZMP and CoM margins
            (``zmp_margin_min_m``, ``com_margin_min_m`` [m]), tick times [us]...
    """

    schedule: ContactSchedule
    rollout: Rollout
    zmp_reference: np.ndarray
    zmp_margins: np.ndarray
    com_margins: np.ndarray
    metrics: dict[str, Any] = field(default_factory=dict)


def plan_walk(
    generator: str,
    command: VelocityCommand | None,
    nb_steps: int,
    *,
    lipm: LIPM = LIPM(),
    timing: StepTiming | None = None,
    foot: FootGeometry = FootGeometry(),
    limits: LegLimits | None = None,
    control_period: float = 0.01,
    generator_options: dict[str, Any] | None = None,
) -> WalkPlan:
    """Plan footsteps from a velocity command and run a generator over them.

    Args:
        generator: Generator name (see :func:`mpcwalk.generators.generator_names`).
        command: Velocity command (vx, vy, vyaw) in the robot frame (None: the planner's
            default, 0.1 m/s forward or the legs' reach per step at slow timings).
        nb_steps: Steps that follow the command; the planner adds a closing step that puts
            the feet side by side (``metrics["closing_steps"]``, counted in
            ``metrics["steps_planned"]``).
        lipm: Pendulum model.
        timing: Step timing (default: the generator's own, e.g. paper A's 12 s for the static
            gaits, else paper M's 0.5 s and r_ds 0.2).
        foot: Sole size (support polygons).
        limits: Leg reach limits of the footstep planner (default: small humanoid).
        control_period: Generator tick, in [s].
        generator_options: Extra keyword arguments of the generator (e.g. ``solver``).

    Returns:
        The plan, trajectory and metrics.
    """
    if timing is None:
        own = generator_class(generator).default_timing
        timing = StepTiming() if own is None else StepTiming(own[0], own[1])
    planner = VelocityPlanner(limits if limits is not None else LegLimits(), timing)
    if command is None:
        command = planner.default_command()
    plan = planner.plan(command, nb_steps)
    schedule = ContactSchedule(plan, foot)
    generator_class(generator).check_timing(schedule, lipm)
    gen = make_generator(
        generator, lipm=lipm, control_period=control_period, **(generator_options or {})
    )
    traj = rollout(gen, schedule)
    zmp_ref = schedule.zmp_reference(traj.times)
    zmp_margins = support_margins(schedule, traj.times, traj.zmp)
    com_margins = support_margins(schedule, traj.times, traj.com)
    ticks_us = traj.tick_times * 1e6
    metrics = {
        "generator": generator,
        "nb_steps": nb_steps,
        "closing_steps": plan.nb_steps - nb_steps,
        "steps_planned": plan.nb_steps,
        "command": {"vx": command.vx, "vy": command.vy, "vyaw": command.vyaw},
        "step_duration_s": timing.step_duration,
        "double_support_ratio": timing.double_support_ratio,
        "com_height_m": lipm.com_height,
        "duration_s": float(traj.times[-1]),
        "zmp_margin_min_m": float(zmp_margins.min()),
        "com_margin_min_m": float(com_margins.min()),
        "zmp_tracking_error_max_m": float(np.abs(traj.zmp - zmp_ref).max()),
        "distance_m": float(np.linalg.norm(traj.com[-1] - traj.com[0])),
        "tick_us_median": float(np.median(ticks_us)),
        "tick_us_p99": float(np.percentile(ticks_us, 99)),
        "nb_ticks": len(ticks_us),
        "qp_failures": int(traj.nb_failures),
    }
    return WalkPlan(schedule, traj, zmp_ref, zmp_margins, com_margins, metrics)
