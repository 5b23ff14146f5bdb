"""What :func:`~mpcwalk.walking.runner.run_walk` returns: the walk's configuration, its
schedule, log, fall verdict and metrics."""

from dataclasses import asdict, dataclass
from typing import Any

from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.sim import FallStatus
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics import WalkMetrics


@dataclass(frozen=True)
class WalkConfig:
    """How a walk was set up; the ``config`` block of ``metrics.json``.

    Attributes:
        robot: Robot name.
        generator: Pattern generator name.
        command: Velocity command ``(vx [m/s], vy [m/s], vyaw [rad/s])``, None for a path.
        path: The ``.mdat`` path file, None for a velocity command.
        duration_s: Walking time asked for [s] (None: ``nb_steps`` was given).
        nb_steps: Steps that follow the command (the closing step not counted), or path steps
            kept (None: all of them).
        step_duration_s: Step duration T [s].
        double_support_ratio: Share r_ds of a step in double support.
        step_height_m: Swing-foot height [m].
        com_height_m: CoM height of the LIPM [m].
        control_period_s: Controller tick [s].
        stabilizer: Stabilizer name ("none" without one).
        feedback: Closed loop on the measured CoM.
        dcm_gain: Gain of the DCM feedback.
        observer_gain: Share of the measured CoM error passed to the generator.
        pushes: ``(start [s], duration [s], fx, fy, fz [N])`` of each push.
        arm_swing: Paper M's arm swing factor s (0: arms still).
    """

    robot: str
    generator: str
    command: tuple[float, float, float] | None
    path: str | None
    duration_s: float | None
    nb_steps: int | None
    step_duration_s: float
    double_support_ratio: float
    step_height_m: float
    com_height_m: float
    control_period_s: float
    stabilizer: str
    feedback: bool
    dcm_gain: float
    observer_gain: float
    pushes: tuple[tuple[float, ...], ...]
    arm_swing: float

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the command as ``{"vx", "vy", "vyaw"}``, the pushes as lists."""
        values = asdict(self)
        if self.command is not None:
            values["command"] = dict(zip(("vx", "vy", "vyaw"), self.command))
        values["pushes"] = [list(push) for push in self.pushes]
        return values


@dataclass(frozen=True)
class WalkResult:
    """A simulated walk.

    Attributes:
        robot: Robot name.
        generator: Pattern generator name.
        schedule: Footsteps and contact phases that were followed.
        log: Per-tick log.
        fall: Verdict of the fall detector at the end (``fall.fell`` True: ended early).
        metrics: What the walk measured.
        config: How it was set up.
    """

    robot: str
    generator: str
    schedule: ContactSchedule
    log: WalkLog
    fall: FallStatus
    metrics: WalkMetrics
    config: WalkConfig

    def to_dict(self) -> dict[str, Any]:
        """The content of ``metrics.json``: the metrics, then the ``config`` block."""
        return {**self.metrics.to_dict(), "config": self.config.to_dict()}
