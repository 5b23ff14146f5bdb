"""What one tick of the walking controller hands out."""

from dataclasses import dataclass, field

import numpy as np

from mpcwalk.gait.swing_foot import FeetState
from mpcwalk.generators.pattern_generator import GeneratorOutput
from mpcwalk.ik.dynamics_targets import DynamicsResult
from mpcwalk.ik.targets import IKResult


@dataclass(frozen=True)
class ControlOutput:
    """What one control tick produced.

    Attributes:
        time: Time of the references [s] (one control period after the measurement).
        q_ref: Reference configuration after this tick (the IK's, with the arm swing when
            on), shape (nq,).
        joint_targets: Position-servo targets, shape (nq - 7,), in [rad]
            (``robot.joint_names`` order): ``q_ref[7:]`` plus the servo feed-forward and the
            stabilizer's corrections.
        com_target: CoM target of the IK, shape (3,), in [m].
        zmp_command: Desired ZMP realised by the feed-forward (the generator's ZMP plus the
            DCM feedback), shape (2,), in [m].
        dcm_error: Estimated minus reference DCM, shape (2,), in [m] (zero in open loop).
        generator: CoM/ZMP reference of the pattern generator.
        feet: Feet poses and velocities at ``time``.
        torso_yaw: Torso yaw target [rad].
        ik: Result of the IK step (task errors: those of the previous ``q_ref``; its
            ``q_next`` is before the arm swing).
        generator_tick: Wall time of the generator step [s].
        ik_tick: Wall time of the IK step [s].
        generator_failed: The generator reported a failed solve this tick (its fallback, or
            the controller's, was used).
        com_offset: The balance stabilizer's estimate of the robot's CoM offset from the
            model's, shape (2,), in [m] (zero without it).
        zmp_integral: The balance stabilizer's integral term in ``zmp_command``, shape (2,),
            in [m] (zero without it).
        joint_torques: Motor torques, shape (nq - 7,), in [N m] (``robot.joint_names``
            order), of a torque-controlled robot
            (:class:`~mpcwalk.control.torque_controller.TorqueController`); None for
            position servos.
        dynamics: The inverse dynamics' result of the tick (torque control), or None.
    """

    time: float
    q_ref: np.ndarray
    joint_targets: np.ndarray
    com_target: np.ndarray
    zmp_command: np.ndarray
    dcm_error: np.ndarray
    generator: GeneratorOutput
    feet: FeetState
    torso_yaw: float
    ik: IKResult
    generator_tick: float
    ik_tick: float
    generator_failed: bool = False
    com_offset: np.ndarray = field(default_factory=lambda: np.zeros(2))
    zmp_integral: np.ndarray = field(default_factory=lambda: np.zeros(2))
    joint_torques: np.ndarray | None = None
    dynamics: DynamicsResult | None = None
