"""What :func:`~mpcwalk.walking.runner.run_walk` returns: the walk's configuration, its
schedule, log, fall verdict and metrics."""

from dataclasses import asdict, dataclass, field
from typing import Any

from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.sim import FallStatus
from mpcwalk.walking.log import WalkLog
from mpcwalk.walking.metrics import WalkMetrics
from mpcwalk.walking.specification import WalkSpec


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
        balance: Whether the balance stabilizer ran (DCM integral action, ZMP distribution,
            foot damping, CoM-offset estimate; the controller's ``balance`` option).
        feedback: Closed loop on the measured CoM.
        dcm_gain: Gain of the DCM feedback.
        observer_gain: Share of the measured CoM error passed to the generator.
        pushes: ``(start [s], duration [s], fx, fy, fz [N])`` of each push.
        arm_swing: Paper M's arm swing factor s (0: arms still).
        state_source: Where the controller's state came from: ``"estimator"`` (the sensors)
            or ``"oracle"`` (the simulator's ground truth).
        ideal_sensors: Exact sensors without latency (``--ideal``).
        noise_scale: Factor on the noise and bias levels of the robot's sensor model.
        sensors: The figures of the sensor model the walk ran with
            (:meth:`~mpcwalk.sim.sensing.model.SensorModel.to_dict`, SI units, the latency
            in control periods).
        latency_s: Sensing-to-actuation latency of the controller's state [s] (0 on the
            oracle, the exact state of the current time).
        model_mismatch: How the simulated robot differed from the controller's model
            (``mass_scale``, ``com_offset_m``, ``friction``, ``servo_strength``,
            ``friction_cone``, ``impratio``; see
            :class:`~mpcwalk.sim.model_mismatch.ModelMismatch`).
        seed: Seed of the sensor noise.
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
    balance: bool
    feedback: bool
    dcm_gain: float
    observer_gain: float
    pushes: tuple[tuple[float, ...], ...]
    arm_swing: float
    state_source: str = "estimator"
    ideal_sensors: bool = False
    noise_scale: float = 1.0
    sensors: dict[str, Any] = field(default_factory=dict)
    latency_s: float = 0.0
    model_mismatch: dict[str, Any] = field(default_factory=dict)
    seed: int = 0

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the command as ``{"vx", "vy", "vyaw"}``, the pushes as lists."""
        values = asdict(self)
        if self.command is not None:
            values["command"] = dict(zip(("vx", "vy", "vyaw"), self.command))
        values["pushes"] = [list(push) for push in self.pushes]
        values["model_mismatch"] = dict(self.model_mismatch)
        values["sensors"] = dict(self.sensors)
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
        spec: The walk's specification, resolved (the defaults it left to the robot
            spelled out): :func:`~mpcwalk.walking.specification.write_spec` writes it, and it walks
            the same walk again.
    """

    robot: str
    generator: str
    schedule: ContactSchedule
    log: WalkLog
    fall: FallStatus
    metrics: WalkMetrics
    config: WalkConfig
    spec: WalkSpec

    def to_dict(self) -> dict[str, Any]:
        """The content of ``metrics.json``: the metrics, then the ``config`` block."""
        return {**self.metrics.to_dict(), "config": self.config.to_dict()}
