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

#: Paper M's arm swing factor s: 0.8 in the paper; beyond this the hands fly.
MAX_ARM_SWING = 2.0
#: Largest push force, in multiples of the robot's weight.
MAX_PUSH_WEIGHTS = 100.0


def check_step_height(robot: Robot, step_height: Any) -> None:
    """The swing height (None: the preset's) lifts the foot and stays below half the CoM
    height of ``robot`` (the plan checked its type and sign)."""
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
