"""The inputs of a walk checked at the boundary, before anything runs: types (a string where a
number is expected is refused, not coerced), physical ranges, bounded sizes. Every refusal is
a :class:`~mpcwalk.exceptions.ConfigurationError` that says what was expected, what came and
the fix.
"""

from collections.abc import Sequence
from typing import Any

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot import Robot
from mpcwalk.sim import ExternalForce

#: Longest walk [s] and most steps a run takes (beyond: hours of simulation and GiB of log).
MAX_DURATION = 3600.0
MAX_STEPS = 10_000
#: Longest step duration [s] (paper A's gait: 12 s).
MAX_STEP_DURATION = 60.0
#: A step lasts at least this many control periods.
MIN_TICKS_PER_STEP = 10
#: Paper M's arm swing factor s: 0.8 in the paper; beyond this the hands fly.
MAX_ARM_SWING = 2.0
#: Largest push force, in multiples of the robot's weight.
MAX_PUSH_WEIGHTS = 100.0


def check_walk_numbers(
    robot: Robot,
    *,
    nb_steps: Any,
    duration: Any,
    step_duration: Any,
    double_support_ratio: Any,
    step_height: Any,
    control_period: Any,
    arm_swing: Any,
) -> None:
    """Types and ranges of a walk's numbers (None: the default)."""
    if nb_steps is not None and (
        isinstance(nb_steps, bool) or not isinstance(nb_steps, int) or not 1 <= nb_steps
    ):
        raise ConfigurationError(
            f"nb_steps must be a positive integer, got {nb_steps!r}; e.g. nb_steps=10."
        )
    if nb_steps is not None and nb_steps > MAX_STEPS:
        raise ConfigurationError(
            f"nb_steps must be at most {MAX_STEPS} (the limit of one run), got {nb_steps}; "
            "split the walk."
        )
    if duration is not None:
        checked_number(
            "duration", duration, low=0.0, high=MAX_DURATION, low_inclusive=False, unit="s"
        )
    period = checked_number(
        "control_period", control_period, low=1e-3, high=0.05, unit="s", fix="e.g. 0.01"
    )
    if step_duration is not None:
        checked_number(
            "step_duration",
            step_duration,
            low=MIN_TICKS_PER_STEP * period,
            high=MAX_STEP_DURATION,
            unit="s",
            fix=f"a step lasts at least {MIN_TICKS_PER_STEP} control periods",
        )
    if double_support_ratio is not None:
        checked_number("double_support_ratio", double_support_ratio, low=0.0, high=0.95)
    if step_height is not None:
        checked_number(
            "step_height",
            step_height,
            low=0.0,
            high=0.5 * robot.com_height,
            low_inclusive=False,
            unit="m",
            fix=f"the swing foot must lift (> 0) and stay below half the CoM height of "
            f"{robot.name}",
        )
    if arm_swing is not None:
        checked_number("arm_swing", arm_swing, low=0.0, high=MAX_ARM_SWING, fix="paper M: 0.8")


def check_pushes(pushes: Any, robot: Robot, walk_end: float) -> list[ExternalForce]:
    """Pushes as :class:`ExternalForce`, within the walk and of a physical size."""
    if isinstance(pushes, (str, bytes)) or not isinstance(pushes, Sequence):
        raise ConfigurationError(
            f"pushes must be a list of ExternalForce, got {pushes!r}; e.g. "
            "pushes=[parse_push('3.0,0.1,10,0,0')]."
        )
    limit = MAX_PUSH_WEIGHTS * robot.total_mass * 9.81
    checked = []
    for push in pushes:
        if not isinstance(push, ExternalForce):
            raise ConfigurationError(
                f"Each push must be an ExternalForce, got {push!r}; build it with "
                f"mpcwalk.sim.parse_push({str(push)!r}) or ExternalForce(start, duration, force)."
            )
        force = float((push.force**2).sum() ** 0.5)
        if force > limit:
            raise ConfigurationError(
                f"A push of {force:.3g} N is beyond {MAX_PUSH_WEIGHTS:g} times the weight of "
                f"{robot.name} ({limit:.3g} N): no robot survives it and the simulation only "
                "diverges; use a smaller force."
            )
        if push.start >= walk_end:
            raise ConfigurationError(
                f"A push starts at {push.start:g} s, after the walk's end at {walk_end:g} s: it "
                "would never act; start it earlier or walk longer."
            )
        checked.append(push)
    return checked


def check_options(cls: type, options: dict[str, Any] | None, what: str) -> None:
    """Refuse keywords that ``cls``'s constructor does not take, naming the valid ones."""
    if options is None:
        return
    if not isinstance(options, dict):
        raise ConfigurationError(f"The {what} must be a dict, got {options!r}.")
    from mpcwalk.generators.registry import check_options as check

    check(cls, options, what)
