"""Where a walk goes and at what pace: :class:`PlanSpec`."""

from dataclasses import dataclass
from typing import Any

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError

#: Longest walk [s] and most steps a run takes (beyond: hours of simulation and GiB of log).
MAX_DURATION = 3600.0
MAX_STEPS = 10_000
#: Longest step duration [s] (paper A's gait: 12 s).
MAX_STEP_DURATION = 60.0
#: A step lasts at least this many control periods.
MIN_TICKS_PER_STEP = 10


@dataclass(frozen=True)
class PlanSpec:
    """The plan of a walk: a velocity command or a path file, how long, at what timing.

    A walk from a command takes ``nb_steps`` steps (a closing step is added) or walks for
    ``duration`` [s] (``round(duration / T)`` steps); a path file walks its steps (the first
    ``nb_steps`` of them when given). Every walk also stands still for 1 s before and after.
    None is the default: the generator's own timing where it has one (paper A's 12 s for the
    static gaits), else the robot preset's ``[gait]`` table.

    Attributes:
        command: Velocity command ``(vx [m/s], vy [m/s], vyaw [rad/s])``; None with a path,
            or the planner's default (0.1 m/s, or the legs' reach at slow steps).
        path: ``.mdat`` path file (paper A's format) instead of a command.
        nb_steps: Number of steps.
        duration: Walking time [s] instead of ``nb_steps``.
        step_duration: Step duration T [s].
        double_support_ratio: Share r_ds of a step in double support, in [0, 0.95].
        step_height: Swing-foot height [m] (checked against the robot when it walks).
        control_period: Controller tick [s], a multiple of the physics step.
        terrain_cadence: On a terrain, every step lengthened by the factor that keeps its
            advance within 75 % of the flat legs' top speed, the command divided by it (the
            same footsteps, :func:`~mpcwalk.footsteps.cadence.cadence_stretch`): stairs and
            stones lengthen the steps, and at the preset's step duration the walk would
            climb several times faster than commanded. Nothing changes on the flat floor or
            where the steps stay within that speed; the pushes keep their times.

    Raises:
        ConfigurationError: Both a command and a path, both ``nb_steps`` and ``duration``,
            or a number of the wrong type or out of range.
    """

    command: tuple[float, float, float] | None = None
    path: str | None = None
    nb_steps: int | None = None
    duration: float | None = None
    step_duration: float | None = None
    double_support_ratio: float | None = None
    step_height: float | None = None
    control_period: float = 0.01
    terrain_cadence: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.terrain_cadence, bool):
            raise ConfigurationError(
                f"terrain_cadence must be true or false, got {self.terrain_cadence!r}."
            )
        if self.command is not None:
            object.__setattr__(self, "command", _command(self.command))
        if self.path is not None:
            if not isinstance(self.path, str) and not hasattr(self.path, "__fspath__"):
                raise ConfigurationError(
                    f"path must be the name of a .mdat file, got {self.path!r}."
                )
            object.__setattr__(self, "path", str(self.path))
        if self.command is not None and self.path is not None:
            raise ConfigurationError(
                "Give either a velocity command or a path file, not both "
                "(--vx/--vy/--vyaw or --path FILE.mdat)."
            )
        if self.nb_steps is not None and self.duration is not None:
            raise ConfigurationError("Give either nb_steps or duration, not both.")
        nb_steps = self.nb_steps
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
        if self.duration is not None:
            duration = checked_number(
                "duration", self.duration, low=0.0, high=MAX_DURATION, low_inclusive=False, unit="s"
            )
            object.__setattr__(self, "duration", duration)
        period = checked_number(
            "control_period", self.control_period, low=1e-3, high=0.05, unit="s", fix="e.g. 0.01"
        )
        object.__setattr__(self, "control_period", period)
        if self.step_duration is not None:
            value = checked_number(
                "step_duration",
                self.step_duration,
                low=MIN_TICKS_PER_STEP * period,
                high=MAX_STEP_DURATION,
                unit="s",
                fix=f"a step lasts at least {MIN_TICKS_PER_STEP} control periods",
            )
            object.__setattr__(self, "step_duration", value)
        if self.double_support_ratio is not None:
            value = checked_number(
                "double_support_ratio", self.double_support_ratio, low=0.0, high=0.95
            )
            object.__setattr__(self, "double_support_ratio", value)
        if self.step_height is not None:
            value = checked_number(
                "step_height", self.step_height, low=0.0, low_inclusive=False, unit="m"
            )
            object.__setattr__(self, "step_height", value)


def _command(value: Any) -> tuple[float, float, float]:
    """Three finite numbers ``(vx, vy, vyaw)``."""
    if hasattr(value, "vx") and hasattr(value, "vyaw"):
        value = (value.vx, value.vy, value.vyaw)
    try:
        numbers = tuple(value)
    except TypeError:
        numbers = ()
    if len(numbers) != 3:
        raise ConfigurationError(
            f"A velocity command is three numbers (vx [m/s], vy [m/s], vyaw [rad/s]), got "
            f"{value!r}; e.g. (0.1, 0.0, 0.0)."
        )
    vx, vy, vyaw = (
        checked_number(name, number, unit=unit)
        for name, number, unit in zip(("vx", "vy", "vyaw"), numbers, ("m/s", "m/s", "rad/s"))
    )
    return vx, vy, vyaw


__all__ = ["MAX_DURATION", "MAX_STEPS", "MAX_STEP_DURATION", "MIN_TICKS_PER_STEP", "PlanSpec"]
