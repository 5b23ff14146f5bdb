"""What a walk's controller is made of: :class:`ControllerSpec`, and the named controllers.

A controller beyond the robot and the plan is its pattern generator (and the generator's
options), whether it closes the loop on the estimated state, its stabilizers (applied in
order), paper M's arm swing, the swing-foot profile and the options of the
:class:`~mpcwalk.control.controller.WalkingController` (``balance``, ``heading_hold``,
``dcm_gain``...). The named controllers the experiments compare are such specifications
(:data:`CONTROLLERS`, ``mpcwalk controllers``); one builder,
:func:`~mpcwalk.walking.controller_builder.build_controller`, makes a controller of any of
them.

- ``paper-m``: paper M's whole engine: the closed form, open loop, with the gyro
  stabilizer (eq. 26-30, the paper's gains) and the arm swing (s = 0.8), at the robot's
  timing (bioloid-like: paper M's Table 1); its IK keeps the trunk rigid and upright (the
  pelvis with the torso frame on a robot with a waist: paper M's robot has none).
- ``paper-m-open``: the closed form alone, open loop, no stabilizer, arms still (paper M's
  turning walk of Fig. 1: "stabilization deactivated").
- ``paper-a``: paper A's static gait: CoM above the support foot, quintic shifts in double
  support, the footstep re-aiming of its state machine, the ankle strategy with the IMU
  correction, quintic Cartesian swing (ctraj), at paper A's 12 s per step.
- ``preview``, ``mpc``, ``mpc-steps``, ``mpc-timing``, ``mpc-late``, ``mpc-timing-nlp``,
  ``mpc-hip``, ``static-qp``: the QP controllers (``mpc-hip``: ``mpc-timing`` with the hip
  strategy, the upper body as a flywheel), closed loop on the estimated state with the balance
  stabilizer and the heading hold (``static-qp`` at paper A's timing, re-aiming like paper
  A's gait).
"""

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.registry import Entry, Registry

#: Swing-foot profiles: paper M's raised cosine, paper A's quintic Cartesian lift (ctraj).
SWING_PROFILES = ("cosine", "ctraj")
#: Options of the controller that are fields of their own in a :class:`ControllerSpec`.
_OWN_FIELDS = ("feedback", "stabilizer", "arm_swing", "swing_profile")
#: Paper M's arm swing factor s: 0.8 in the paper; beyond this the hands fly.
MAX_ARM_SWING = 2.0
#: The name of a controller composed by hand.
CUSTOM = "custom"


def _check_plain(value: Any, where: str) -> None:
    """A value a TOML file holds: a string, a finite number, a boolean, or lists and tables
    of them."""
    if isinstance(value, (str, bool, int)):
        return
    if isinstance(value, float):
        if math.isfinite(value):
            return
    elif isinstance(value, (list, tuple)):
        for item in value:
            _check_plain(item, where)
        return
    elif isinstance(value, dict):
        for key, item in value.items():
            if not isinstance(key, str):
                break
            _check_plain(item, where)
        else:
            return
    raise ConfigurationError(
        f"{where} must hold strings, finite numbers, booleans, or lists and tables of them "
        f"(what a walk specification file holds), got {value!r}."
    )


def _options(value: Any, name: str) -> dict[str, Any]:
    if value is None:
        return {}
    if not isinstance(value, dict) or not all(isinstance(k, str) for k in value):
        raise ConfigurationError(
            f"{name} must be a dict of option names to values, got {value!r}; e.g. "
            '{"solver": "quadprog"}.'
        )
    for key, item in value.items():
        _check_plain(item, f"{name}[{key!r}]")
    return dict(value)


@dataclass(frozen=True)
class ControllerSpec:
    """A walk's controller (see the module docstring).

    Attributes:
        name: The named controller it is (``mpcwalk controllers``), or ``"custom"``.
        generator: Pattern generator name (``mpcwalk generators``).
        generator_options: Keyword arguments of the generator (over the robot preset's).
        feedback: Close the loop on the estimated state (DCM feedback, observer, balance).
        stabilizers: Stabilizer names, applied in this order (``mpcwalk stabilizers``:
            ``"reaim"``, ``"ankle-imu"``, ``"gyro"``).
        arm_swing: Paper M's arm movement factor s (eq. 24-25; 0: arms still).
        swing_profile: ``"cosine"`` (paper M) or ``"ctraj"`` (paper A).
        controller_options: Further keyword arguments of the
            :class:`~mpcwalk.control.controller.WalkingController` (``balance``,
            ``heading_hold``, ``dcm_gain``, ``observer_gain``, ``zmp_margin``...); a
            torque-controlled walk also takes ``dynamics_solver``, the back-end of its
            inverse dynamics, ``rocking_rate`` and ``torque_loop``
            (:class:`~mpcwalk.control.torque_controller.TorqueController`).

    Raises:
        ConfigurationError: A value of the wrong type or out of range, an unknown swing
            profile, or a controller option that is a field of its own.
    """

    name: str = CUSTOM
    generator: str = "mpc"
    generator_options: dict[str, Any] = field(default_factory=dict)
    feedback: bool = True
    stabilizers: tuple[str, ...] = ()
    arm_swing: float = 0.0
    swing_profile: str = "cosine"
    controller_options: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in ("name", "generator"):
            if not isinstance(getattr(self, name), str) or not getattr(self, name):
                raise ConfigurationError(
                    f"ControllerSpec.{name} must be a name, got {getattr(self, name)!r}."
                )
        if not isinstance(self.feedback, bool):
            raise ConfigurationError(
                f"ControllerSpec.feedback must be true or false, got {self.feedback!r}."
            )
        stabilizers = self.stabilizers
        if isinstance(stabilizers, str):
            stabilizers = () if stabilizers == "none" else (stabilizers,)
        if not all(isinstance(s, str) for s in stabilizers):
            raise ConfigurationError(
                f"ControllerSpec.stabilizers must be stabilizer names, got {stabilizers!r}; "
                'e.g. ("reaim", "ankle-imu").'
            )
        object.__setattr__(self, "stabilizers", tuple(s for s in stabilizers if s != "none"))
        swing = checked_number(
            "arm_swing", self.arm_swing, low=0.0, high=MAX_ARM_SWING, fix="paper M: 0.8"
        )
        object.__setattr__(self, "arm_swing", swing)
        if self.swing_profile not in SWING_PROFILES:
            raise ConfigurationError(
                f"swing_profile must be one of {', '.join(SWING_PROFILES)}, got "
                f"{self.swing_profile!r}."
            )
        generator_options = _options(self.generator_options, "generator_options")
        controller_options = _options(self.controller_options, "controller_options")
        own = sorted(set(controller_options) & set(_OWN_FIELDS))
        if own:
            raise ConfigurationError(
                f"controller_options {', '.join(own)} are fields of the controller "
                "specification of their own: set ControllerSpec."
                f"{own[0].replace('stabilizer', 'stabilizers')} instead."
            )
        object.__setattr__(self, "generator_options", generator_options)
        object.__setattr__(self, "controller_options", controller_options)

    @classmethod
    def named(cls, name: str) -> "ControllerSpec":
        """The named controller ``name`` (``mpcwalk controllers``).

        Raises:
            NotRegistered: Unknown name (the message lists the names).
        """
        spec: ControllerSpec = CONTROLLERS.load(name)
        return spec

    def replace(self, **changes: Any) -> "ControllerSpec":
        """A copy with ``changes``; its name becomes ``"custom"`` when a part differs from
        this controller's (unless ``name`` is given)."""
        new = dataclasses.replace(self, **changes)
        if "name" not in changes and dataclasses.replace(new, name=self.name) != self:
            new = dataclasses.replace(new, name=CUSTOM)
        return new

    @classmethod
    def from_fields(cls, fields: dict[str, Any]) -> "ControllerSpec":
        """The controller of a specification file's ``[controller]`` table: the named
        controller its ``name`` names, changed by the other fields given (none: ``mpc``)."""
        name = fields.get("name", CUSTOM if len(fields) else "mpc")
        if name != CUSTOM:  # an unknown name is refused (NotRegistered), not walked as mpc
            return cls.named(name).replace(**{k: v for k, v in fields.items() if k != "name"})
        return cls(**fields)


def _named(name: str, summary: str, **parts: Any) -> Entry[ControllerSpec]:
    spec = ControllerSpec(name=name, **parts)
    return Entry(name, summary, lambda: spec)


#: The named controllers (see the module docstring).
CONTROLLERS: Registry[ControllerSpec] = Registry(
    "controller",
    [
        _named(
            "paper-m",
            "paper M's engine: closed form, open loop, gyro stabilizer, arm swing s = 0.8",
            generator="analytic",
            feedback=False,
            stabilizers=("gyro",),
            arm_swing=0.8,
            controller_options={"upright_pelvis": True},
        ),
        _named(
            "paper-m-open",
            "paper M's closed form alone, open loop, no stabilizer (paper M Fig. 1)",
            generator="analytic",
            feedback=False,
            controller_options={"upright_pelvis": True},
        ),
        _named(
            "paper-a",
            "paper A's static gait: ankle strategy + IMU, re-aiming state machine, ctraj, 12 s",
            generator="static",
            feedback=False,
            stabilizers=("reaim", "ankle-imu"),
            swing_profile="ctraj",
        ),
        _named(
            "preview",
            "Kajita's ZMP preview control, closed loop, balance stabilizer, heading hold",
            generator="preview",
        ),
        _named(
            "mpc",
            "linear MPC (Wieber), ZMP in the support polygons, closed loop, heading hold",
            generator="mpc",
        ),
        _named(
            "mpc-steps",
            "footstep-adaptive MPC (Herdt) with capture-point stepping, closed loop",
            generator="mpc-steps",
        ),
        _named(
            "mpc-timing",
            "mpc-steps with step-timing adaptation (a landing brought forward when the "
            "capture point would leave the leg's reach, a lift-off put off while the DCM "
            "error points to the lifting foot) and the capturability constraint",
            generator="mpc-steps",
            generator_options={"timing_adaptation": True, "capturability": True},
        ),
        _named(
            "mpc-late",
            "mpc-steps with late step adjustment: landings free until two ticks before "
            "touch-down, each change boxed by the swing's time left, the swing re-planned as "
            "a quintic",
            generator="mpc-steps",
            generator_options={"late_adjustment": True},
        ),
        _named(
            "mpc-timing-nlp",
            "mpc-steps with optimal step timing: the next two landings and durations of a "
            "nonlinear program (CasADi, IPOPT, warm-started), late step adjustment and the "
            "capturability constraint",
            generator="mpc-nlp",
            generator_options={"capturability": True},
        ),
        _named(
            "mpc-hip",
            "mpc-timing with the hip strategy: the upper body as a flywheel (its torque, "
            "momentum and lean bounded by the robot's), the CMP beyond the support",
            generator="mpc-hip",
            generator_options={"timing_adaptation": True, "capturability": True},
        ),
        _named(
            "static-qp",
            "quasi-static QP (CoM over the support polygon), closed loop, re-aiming, 12 s",
            generator="static-qp",
            stabilizers=("reaim",),
        ),
    ],
    list_command="mpcwalk controllers",
)


def controller_names() -> list[str]:
    """Names of the named controllers, in the order of :data:`CONTROLLERS`."""
    return CONTROLLERS.names()


__all__ = ["CONTROLLERS", "CUSTOM", "SWING_PROFILES", "ControllerSpec", "controller_names"]
