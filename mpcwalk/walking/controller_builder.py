"""One way to build a controller: from a :class:`~mpcwalk.walking.specification.ControllerSpec`, a
robot and a contact schedule to a :class:`~mpcwalk.control.controller.WalkingController`.

Named controllers, the command line's parts by hand, the sweeps and the experiments all
describe their controller as a :class:`~mpcwalk.walking.specification.ControllerSpec`; this module
is the only place that turns one into objects. It also decides the timing of a walk whose
plan gives none (:func:`walk_timing`).

A generator that holds the CoM above the support foot in single support (paper A's static
gait, ``PatternGenerator.holds_com_over_support``) gets a whole-body IK with the Tikhonov
damping :data:`STATIC_IK_DAMPING` instead of the IK's default (1e-6). Such a gait lands each
step ahead of a CoM still above the other foot: at long steps the landing leg's knee is nearly
straight (about 10 deg on ``g1`` at 0.18 m, ``romeo`` at 0.144 m, ``atlas-like`` at 0.24 m),
where the undamped Gauss-Newton step of the IK overshoots: its joint velocities alternate
sign every tick and grow to several rad/s with the task errors below a millimetre (a period-2
to 3 oscillation of the kinematic reference alone, no simulator in the loop), the servos shake
the robot and it falls when the foot touches down. A damping equal to the posture task's own
weight squared (``IKWeights().posture ** 2``) removes it; along the tasks' null space it halves
the rate at which the posture returns to its reference, which a 12 s step does not notice.
"""

import inspect
from collections.abc import Sequence

from mpcwalk._checks import checked_number
from mpcwalk.control.controller import WalkingController
from mpcwalk.control.stabilizers import StabilizerChain, make_stabilizer
from mpcwalk.control.stabilizers.base import Stabilizer
from mpcwalk.control.torque_controller import TorqueController
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import StepTiming
from mpcwalk.footsteps.landing_bands import tread_bands
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.gait_defaults import GaitDefaults
from mpcwalk.generators import generator_class
from mpcwalk.generators.mpc_steps import TORQUE_DCM_STEP_GAIN, FootstepMpcGenerator
from mpcwalk.generators.registry import check_options
from mpcwalk.ik.dynamics_program import check_dynamics_solver
from mpcwalk.ik.targets import IKWeights
from mpcwalk.ik.upper_body import upper_body_flywheel
from mpcwalk.ik.whole_body_ik import WholeBodyIK
from mpcwalk.robot import Robot
from mpcwalk.terrain import Terrain, TerrainReach
from mpcwalk.walking.specification import ControllerSpec, PlanSpec

#: Options of :class:`~mpcwalk.control.torque_controller.TorqueController` a walk's
#: ``controller_options`` may give when its actuation is ``"torque"``: the back-end of the
#: inverse dynamics' QP and the rate at which a rocking sole narrows its CoP's support.
TORQUE_OPTIONS = ("dynamics_solver", "rocking_rate", "torque_loop")

#: Tikhonov damping of the whole-body IK [cost^2] under a gait that holds the CoM above the
#: support foot (see the module docstring): the posture task's weight squared.
STATIC_IK_DAMPING = IKWeights().posture ** 2


def build_stabilizer(names: Sequence[str]) -> Stabilizer | None:
    """The stabilizers called ``names``, chained in that order (None: no name).

    Raises:
        NotRegistered: An unknown stabilizer name.
    """
    parts = [make_stabilizer(name) for name in names]
    chain = [part for part in parts if part is not None]
    return StabilizerChain(chain) if chain else None


def check_controller(spec: ControllerSpec, actuation: str = "position") -> None:
    """The generator and the options of ``spec``, checked before anything is built; a
    torque-controlled walk (``actuation`` ``"torque"``) also takes the options of
    :data:`TORQUE_OPTIONS`.

    Raises:
        GeneratorNotFound: Unknown generator.
        ConfigurationError: An option the generator or the controller does not take (the
            message lists the ones it takes), a torque option on a position-servo walk, or
            an unknown ``dynamics_solver`` (the message lists the choices).
    """
    check_options(
        generator_class(spec.generator), spec.generator_options, f"generator '{spec.generator}'"
    )
    options = dict(spec.controller_options)
    torque = sorted(set(options) & set(TORQUE_OPTIONS))
    if torque and actuation != "torque":
        raise ConfigurationError(
            f"controller_options {', '.join(torque)} drive the inverse dynamics of a "
            f"torque-controlled robot, but the walk's actuation is {actuation!r}; set "
            "actuation = 'torque' (--actuation torque) or leave them out."
        )
    if "dynamics_solver" in options:
        check_dynamics_solver(options.pop("dynamics_solver"))
    if "rocking_rate" in options:
        checked_number("rocking_rate", options.pop("rocking_rate"), low=0.0, unit="rad/s")
    if not isinstance(options.pop("torque_loop", False), bool):
        raise ConfigurationError(
            f"controller_options torque_loop must be true or false, got "
            f"{spec.controller_options['torque_loop']!r}."
        )
    check_options(WalkingController, options, "controller")
    build_stabilizer(spec.stabilizers)  # the names, checked


def build_controller(
    robot: Robot,
    spec: ControllerSpec,
    schedule: ContactSchedule,
    *,
    control_period: float,
    step_height: float,
    terrain: Terrain | None = None,
    actuation: str = "position",
    state_delay: float | None = None,
) -> WalkingController:
    """The controller of ``spec`` on ``robot``, following ``schedule``.

    The robot preset's ``dcm_gain`` and ``observer_gain`` come first, the specification's
    controller options over them. A generator that holds the CoM above the support foot gets
    the IK damped by :data:`STATIC_IK_DAMPING`. A torque-controlled robot (``actuation``
    ``"torque"``) gets a :class:`~mpcwalk.control.torque_controller.TorqueController`
    whose posture gain is capped for ``state_delay`` [s], the age of its estimated state
    (:func:`~mpcwalk.control.torque_controller.state_delay`; None: one control period), on
    the back-end ``controller_options["dynamics_solver"]`` (default ``"daqp-direct"``).
    """
    check_controller(spec, actuation)
    gait = robot.gait
    options: dict = {
        key: value
        for key, value in (("dcm_gain", gait.dcm_gain), ("observer_gain", gait.observer_gain))
        if value is not None
    }
    options.update(spec.controller_options)
    options["swing_profile"] = spec.swing_profile
    generator_options = dict(spec.generator_options)
    if terrain is not None and not terrain.is_flat:
        options["terrain"] = terrain
        if issubclass(generator_class(spec.generator), FootstepMpcGenerator):
            # a footstep-adaptive generator takes the strides the terrain planner gave, and
            # keeps each landing on the tread it was placed on
            reach = TerrainReach.for_leg(*robot.sole_size, robot.leg_length)
            generator_options.setdefault("planned_strides", True)
            generator_options.setdefault(
                "landing_bands", tread_bands(schedule.plan, terrain, reach)
            )
    if actuation == "torque" and issubclass(generator_class(spec.generator), FootstepMpcGenerator):
        # torque control: the capture-point term off unless asked for (TORQUE_DCM_STEP_GAIN)
        generator_options.setdefault("dcm_step_gain", TORQUE_DCM_STEP_GAIN)
    if "flywheel_limits" in inspect.signature(generator_class(spec.generator)).parameters:
        # the hip strategy: the upper body's limits from the robot's model
        generator_options.setdefault("flywheel_limits", upper_body_flywheel(robot))
    if spec.arm_swing:
        options["arm_swing"] = spec.arm_swing
    if generator_class(spec.generator).holds_com_over_support:
        options["ik"] = WholeBodyIK(robot, damping=STATIC_IK_DAMPING)
    stabilizer = build_stabilizer(spec.stabilizers)
    if stabilizer is not None:
        options["stabilizer"] = stabilizer
    controller_class = TorqueController if actuation == "torque" else WalkingController
    if actuation == "torque":
        options["state_delay"] = state_delay
    return controller_class.for_robot(
        robot,
        spec.generator,
        schedule,
        control_period=control_period,
        feedback=spec.feedback,
        step_height=step_height,
        generator_options=generator_options,
        **options,
    )


def walk_timing(generator: str, gait: GaitDefaults, plan: PlanSpec) -> StepTiming:
    """The step timing of a walk: the plan's, else the generator's own timing
    (:attr:`PatternGenerator.default_timing`: paper A's 12 s for the static gaits), else the
    robot preset's ``[gait]`` table."""
    own = generator_class(generator).default_timing
    if own is not None and plan.step_duration is None and plan.double_support_ratio is None:
        return StepTiming(step_duration=own[0], double_support_ratio=own[1])
    step_duration = gait.step_duration if plan.step_duration is None else plan.step_duration
    ratio = plan.double_support_ratio
    return StepTiming(
        step_duration=float(step_duration),
        double_support_ratio=float(gait.double_support_ratio if ratio is None else ratio),
    )


__all__ = [
    "STATIC_IK_DAMPING",
    "TORQUE_OPTIONS",
    "build_controller",
    "build_stabilizer",
    "check_controller",
    "walk_timing",
]
