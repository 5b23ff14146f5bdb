"""Stabilizers: corrections a :class:`~mpcwalk.control.controller.WalkingController` applies on top of
its kinematic references, from the measured state.

A stabilizer has two hooks, both optional (identity by default):

- :meth:`Stabilizer.adjust_targets`: move the feet, CoM and torso-yaw targets of the IK
  (paper A's re-aiming of each step from the measured support foot);
- :meth:`Stabilizer.adjust_joint_targets`: add offsets to the servo targets (paper A's ankle
  strategy and IMU correction, paper M's gyro feedback).

:func:`make_stabilizer` builds one by name (``"ankle-imu"``, ``"gyro"`` (paper M's gyro
feedback, :mod:`mpcwalk.control.stabilizers.gyro`), ``"none"``).
"""

from collections.abc import Sequence

import numpy as np

from mpcwalk.exceptions import ConfigurationError


class Stabilizer:
    """Base class of the controller's stabilizer hook (identity corrections)."""

    name = "none"

    def reset(self, controller) -> None:
        """Forget the state of a previous walk (called by ``controller.reset``)."""

    def adjust_targets(
        self, controller, t: float, feet, com_xy: np.ndarray, torso_yaw: float, measurement
    ) -> tuple[object, np.ndarray, float]:
        """Feet (FeetState), CoM ``(2,)`` [m] and torso yaw [rad] targets of the IK at ``t``."""
        return feet, com_xy, torso_yaw

    def adjust_joint_targets(
        self, controller, t: float, joint_targets: np.ndarray, feet, measurement
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

    def reset(self, controller) -> None:
        for stabilizer in self.stabilizers:
            stabilizer.reset(controller)

    def adjust_targets(self, controller, t, feet, com_xy, torso_yaw, measurement):
        for stabilizer in self.stabilizers:
            feet, com_xy, torso_yaw = stabilizer.adjust_targets(
                controller, t, feet, com_xy, torso_yaw, measurement
            )
        return feet, com_xy, torso_yaw

    def adjust_joint_targets(self, controller, t, joint_targets, feet, measurement):
        for stabilizer in self.stabilizers:
            joint_targets = stabilizer.adjust_joint_targets(
                controller, t, joint_targets, feet, measurement
            )
        return joint_targets


STABILIZER_NAMES = ("none", "ankle-imu", "gyro")


def make_stabilizer(name: str | None, **options) -> Stabilizer | None:
    """Stabilizer called ``name`` (None or ``"none"``: no stabilizer).

    Raises:
        ConfigurationError: Unknown name.
    """
    if name is None or name == "none":
        return None
    if name == "ankle-imu":
        from mpcwalk.control.stabilizers.ankle_imu import AnkleImuStabilizer

        return AnkleImuStabilizer(**options)
    if name == "gyro":
        from mpcwalk.control.stabilizers.gyro import GyroStabilizer

        return GyroStabilizer(**options)
    raise ConfigurationError(
        f"Unknown stabilizer '{name}'; the stabilizers are {', '.join(STABILIZER_NAMES)}."
    )


__all__ = ["STABILIZER_NAMES", "Stabilizer", "StabilizerChain", "make_stabilizer"]
