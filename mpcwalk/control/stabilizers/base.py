"""The stabilizer hook of the control tick: a typed input in, corrections out.

A stabilizer never sees the controller. Each tick the controller hands it a frozen
:class:`StabilizerInput` (time, control period, the robot's kinematics, the schedule, the
gait targets of this tick, the references the estimate is compared with, the reference
configuration and the robot's estimated state with the raw sensor readings it came from) and
takes back its corrections:

- :meth:`Stabilizer.adjust_targets` returns the feet, CoM and torso-yaw targets of the IK
  (paper A's re-aiming of each step from the measured support foot);
- :meth:`Stabilizer.adjust_joint_targets` returns the servo targets (paper A's ankle
  strategy and IMU correction, paper M's gyro feedback).

Both are the identity by default.
"""

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from mpcwalk.control.dcm_feedback import support_weights
from mpcwalk.control.gait_reference import GaitTargets
from mpcwalk.estimation.estimated_state import EstimatedState
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.robot.robot import Robot


@dataclass(frozen=True)
class StabilizerInput:
    """What a stabilizer sees of one control tick.

    The state was estimated from readings taken at ``time - control_period`` (plus the
    sensing latency), the time of the references of the previous tick (``com_reference``,
    ``zmp_reference``); ``targets`` are this tick's, at ``time``.

    Attributes:
        time: Time of the references this tick computes [s].
        control_period: Duration of one tick [s].
        robot: The robot (joint names, Pinocchio model and frames: its kinematics).
        schedule: Footsteps and contact phases the controller follows.
        targets: Gait targets at ``time``: those going to the IK in
            :meth:`Stabilizer.adjust_targets` (after the previous stabilizers of a chain),
            those the IK was given in :meth:`Stabilizer.adjust_joint_targets`.
        q_ref: Reference configuration, shape (nq,): the IK's starting point (the previous
            tick's) in :meth:`Stabilizer.adjust_targets`, this tick's IK result in
            :meth:`Stabilizer.adjust_joint_targets`.
        com_reference: CoM target of the IK at the measurement time, shape (3,), in [m].
        zmp_reference: Desired ZMP at the measurement time, shape (2,), in [m].
        zmp_planned: The pattern generator's ZMP at the measurement time (the plan, before
            the DCM feedback), shape (2,), in [m]; None: ``zmp_reference``.
        state: The robot's estimated state (base, CoM, DCM, contacts, soles) with the raw
            readings it came from in ``state.sensors`` (gyro, accelerometer, encoders, foot
            force/torque in the sole frames), or None (a kinematic robot, or a bare CoM
            state was measured).
        dcm_error: Estimated minus reference DCM at the estimate's time, shape (2,), in [m]
            (zero without an estimate).
    """

    time: float
    control_period: float
    robot: Robot
    schedule: ContactSchedule
    targets: GaitTargets
    q_ref: np.ndarray
    com_reference: np.ndarray
    zmp_reference: np.ndarray
    zmp_planned: np.ndarray | None = None
    state: EstimatedState | None = None
    dcm_error: np.ndarray = field(default_factory=lambda: np.zeros(2))

    @property
    def support_weights(self) -> tuple[float, float]:
        """Share of the weight on the left and right feet: the reference ZMP over the feet
        targets (all on the support foot in single support)."""
        return support_weights(self.zmp_reference, self.targets.feet)


class Stabilizer:
    """Base class of the controller's stabilizer hook (identity corrections)."""

    name = "none"
    #: Whether it re-aims the footsteps at the plan's headings itself (then the controller's
    #: heading hold stays off).
    holds_heading = False

    def reset(self, inputs: StabilizerInput) -> None:
        """Forget the state of a previous walk; ``inputs`` are the references at the start
        of the new one (no estimated state)."""

    def adjust_targets(self, inputs: StabilizerInput) -> GaitTargets:
        """Feet, CoM and torso-yaw targets of the IK at ``inputs.time``."""
        return inputs.targets

    def adjust_joint_targets(
        self, inputs: StabilizerInput, joint_targets: np.ndarray
    ) -> np.ndarray:
        """Servo targets [rad] (``robot.joint_names`` order) after the correction."""
        return joint_targets


class StabilizerChain(Stabilizer):
    """Several stabilizers applied in order.

    Args:
        stabilizers: The stabilizers; each one's output is the next one's input.
    """

    def __init__(self, stabilizers: Sequence[Stabilizer]) -> None:
        self.stabilizers = tuple(stabilizers)
        self.name = "+".join(s.name for s in self.stabilizers) or "none"
        self.holds_heading = any(s.holds_heading for s in self.stabilizers)

    def reset(self, inputs: StabilizerInput) -> None:
        for stabilizer in self.stabilizers:
            stabilizer.reset(inputs)

    def adjust_targets(self, inputs: StabilizerInput) -> GaitTargets:
        for stabilizer in self.stabilizers:
            inputs = replace(inputs, targets=stabilizer.adjust_targets(inputs))
        return inputs.targets

    def adjust_joint_targets(
        self, inputs: StabilizerInput, joint_targets: np.ndarray
    ) -> np.ndarray:
        for stabilizer in self.stabilizers:
            joint_targets = stabilizer.adjust_joint_targets(inputs, joint_targets)
        return joint_targets


__all__ = ["GaitTargets", "Stabilizer", "StabilizerChain", "StabilizerInput"]
