"""Named controller configurations: the controllers the experiments compare, by name.

A configuration is what a controller is made of beyond the robot and the command: its
pattern generator, whether it closes the loop on the estimated state, its stabilizer, paper
M's arm swing, paper A's re-aiming state machine and swing profile, and its own timing when
it has one. ``mpcwalk walk --controller NAME`` and ``run_walk(controller=NAME)`` use them;
``mpcwalk controllers`` lists them. The parts still compose by hand (``--generator``,
``--stabilizer``, ...).

- ``paper-m``: paper M's whole engine: the closed form, open loop, with the gyro
  stabilizer (eq. 26-30, the paper's gains) and the arm swing (s = 0.8), at the robot's
  timing (bioloid-like: paper M's Table 1).
- ``paper-m-open``: the closed form alone, open loop, no stabilizer, arms still (paper M's
  turning walk of Fig. 1: "stabilization deactivated").
- ``paper-a``: paper A's static gait: CoM above the support foot, quintic shifts in double
  support, the ankle strategy with the IMU correction, the state machine that re-aims every
  step from the measured support foot, quintic Cartesian swing (ctraj), at paper A's 12 s
  per step.
- ``preview``, ``mpc``, ``mpc-steps``, ``static-qp``: the QP controllers, closed loop on the
  estimated state with the balance stabilizer and the heading hold (``static-qp`` at paper
  A's timing, re-aiming like paper A's gait).
"""

from dataclasses import dataclass, field
from typing import Any

from mpcwalk.exceptions import ConfigurationError


@dataclass(frozen=True)
class ControllerConfig:
    """One named controller: keyword arguments of :func:`mpcwalk.walking.runner.run_walk`.

    Attributes:
        name: The name (``--controller NAME``).
        summary: One line for ``mpcwalk controllers``.
        generator: Pattern generator name.
        feedback: Close the loop on the estimated state (DCM feedback, observer, balance).
        stabilizer: Stabilizer name (``"gyro"``, ``"ankle-imu"``) or None.
        arm_swing: Paper M's arm swing factor s (0: arms still).
        reaim: Paper A's state machine re-aiming every step from the measured support foot.
        swing_profile: ``"cosine"`` (paper M) or ``"ctraj"`` (paper A).
        generator_options: Keyword arguments of the generator.
    """

    name: str
    summary: str
    generator: str
    feedback: bool
    stabilizer: str | None = None
    arm_swing: float = 0.0
    reaim: bool = False
    swing_profile: str = "cosine"
    generator_options: dict[str, Any] = field(default_factory=dict)

    def walk_kwargs(self) -> dict[str, Any]:
        """The configuration as :func:`~mpcwalk.walking.runner.run_walk` arguments by hand
        (generator, feedback, stabilizer name, arm swing, options), for experiments that vary
        one part, e.g. the stabilizer (a re-aiming configuration passes ``controller=``)."""
        if self.reaim:
            raise ConfigurationError(
                f"Controller '{self.name}' re-aims its steps: walk it with controller='{self.name}'."
            )
        return {
            "generator": self.generator,
            "feedback": self.feedback,
            "stabilizer": self.stabilizer,
            "arm_swing": self.arm_swing,
            "generator_options": dict(self.generator_options),
            "controller_options": {"swing_profile": self.swing_profile},
        }


#: The controllers, by name.
CONTROLLERS: dict[str, ControllerConfig] = {
    c.name: c
    for c in (
        ControllerConfig(
            "paper-m",
            "paper M's engine: closed form, open loop, gyro stabilizer, arm swing s = 0.8",
            "analytic",
            feedback=False,
            stabilizer="gyro",
            arm_swing=0.8,
        ),
        ControllerConfig(
            "paper-m-open",
            "paper M's closed form alone, open loop, no stabilizer (paper M Fig. 1)",
            "analytic",
            feedback=False,
        ),
        ControllerConfig(
            "paper-a",
            "paper A's static gait: ankle strategy + IMU, re-aiming state machine, ctraj, 12 s",
            "static",
            feedback=False,
            stabilizer="ankle-imu",
            reaim=True,
            swing_profile="ctraj",
        ),
        ControllerConfig(
            "preview",
            "Kajita's ZMP preview control, closed loop, balance stabilizer, heading hold",
            "preview",
            feedback=True,
        ),
        ControllerConfig(
            "mpc",
            "linear MPC (Wieber), ZMP in the support polygons, closed loop, heading hold",
            "mpc",
            feedback=True,
        ),
        ControllerConfig(
            "mpc-steps",
            "footstep-adaptive MPC (Herdt) with capture-point stepping, closed loop",
            "mpc-steps",
            feedback=True,
        ),
        ControllerConfig(
            "mpc-timing",
            "mpc-steps with step-timing adaptation (a landing brought forward when the "
            "capture point would leave the leg's reach, a lift-off put off while the DCM error "
            "points to the lifting foot) and the capturability constraint",
            "mpc-steps",
            feedback=True,
            generator_options={"timing_adaptation": True, "capturability": True},
        ),
        ControllerConfig(
            "static-qp",
            "quasi-static QP (CoM over the support polygon), closed loop, re-aiming, 12 s",
            "static-qp",
            feedback=True,
            reaim=True,
        ),
    )
}


def controller_names() -> list[str]:
    """Names of the controller configurations, in the order of :data:`CONTROLLERS`."""
    return list(CONTROLLERS)


def controller_config(name: str) -> ControllerConfig:
    """The configuration called ``name``.

    Raises:
        ConfigurationError: Unknown name (the message lists the names).
    """
    if not isinstance(name, str) or name not in CONTROLLERS:
        raise ConfigurationError(
            f"Unknown controller {name!r}; the controllers are {', '.join(CONTROLLERS)} "
            "(mpcwalk controllers lists them)."
        )
    return CONTROLLERS[name]
