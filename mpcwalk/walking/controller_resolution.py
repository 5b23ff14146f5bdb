"""From what the caller gave (a controller name, or the parts by hand) to the parts of a walk,
and the timing a walk uses when the caller gives none."""

from dataclasses import dataclass
from typing import Any

from mpcwalk.control.stabilizers import StabilizerChain, make_stabilizer
from mpcwalk.control.stabilizers.base import Stabilizer
from mpcwalk.control.stabilizers.paper_a import PaperAStateMachine
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import StepTiming
from mpcwalk.gait.gait_defaults import GaitDefaults
from mpcwalk.generators import generator_class
from mpcwalk.walking.controllers import controller_config

#: The generator of a walk when neither a generator nor a controller is named.
DEFAULT_GENERATOR = "mpc"


@dataclass(frozen=True)
class WalkParts:
    """The parts of a walk's controller (see :func:`resolve_controller`)."""

    generator: str
    feedback: bool
    stabilizer: Stabilizer | None
    arm_swing: float
    generator_options: dict[str, Any] | None
    controller_options: dict[str, Any] | None


def resolve_controller(
    controller: str | None,
    *,
    generator: str | None,
    feedback: bool | None,
    stabilizer: Any,
    arm_swing: float | None,
    generator_options: dict[str, Any] | None,
    controller_options: dict[str, Any] | None,
) -> WalkParts:
    """The parts of the named controller, or those given by hand.

    Raises:
        ConfigurationError: Unknown controller, or a controller together with a part it sets
            (generator, feedback, stabilizer, arm swing).
    """
    if controller is None:
        if isinstance(stabilizer, str):
            stabilizer = make_stabilizer(stabilizer)
        return WalkParts(
            DEFAULT_GENERATOR if generator is None else generator,
            True if feedback is None else bool(feedback),
            stabilizer,
            0.0 if arm_swing is None else float(arm_swing),
            generator_options,
            controller_options,
        )
    config = controller_config(controller)
    given = [
        name
        for name, value in (
            ("generator", generator),
            ("feedback", feedback),
            ("stabilizer", stabilizer),
            ("arm_swing", arm_swing),
        )
        if value is not None
    ]
    if given:
        raise ConfigurationError(
            f"Controller '{controller}' sets its own {', '.join(given)}; give either "
            "controller=NAME or the parts by hand (generator=, feedback=, stabilizer=, "
            "arm_swing=), not both."
        )
    parts: list[Stabilizer] = []
    if config.reaim:
        parts.append(PaperAStateMachine(yaw_source="imu"))
    named = make_stabilizer(config.stabilizer)
    if named is not None:
        parts.append(named)
    return WalkParts(
        config.generator,
        config.feedback,
        StabilizerChain(parts) if parts else None,
        config.arm_swing,
        {**config.generator_options, **(generator_options or {})},
        {"swing_profile": config.swing_profile, **(controller_options or {})},
    )


def default_timing(
    generator: str,
    gait: GaitDefaults,
    step_duration: float | None,
    double_support_ratio: float | None,
) -> StepTiming:
    """The step timing of a walk: what the caller gave, else the generator's own timing
    (:attr:`PatternGenerator.default_timing`: paper A's 12 s for the static gaits), else the
    robot preset's ``[gait]`` table."""
    own = generator_class(generator).default_timing
    if own is not None and step_duration is None and double_support_ratio is None:
        return StepTiming(step_duration=own[0], double_support_ratio=own[1])
    return StepTiming(
        step_duration=float(gait.step_duration if step_duration is None else step_duration),
        double_support_ratio=float(
            gait.double_support_ratio if double_support_ratio is None else double_support_ratio
        ),
    )
