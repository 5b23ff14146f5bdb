"""Stabilizers: corrections a :class:`~mpcwalk.control.controller.WalkingController` applies on
top of its kinematic references, from the estimated state.

A stabilizer receives a typed :class:`StabilizerInput` each tick, never the controller, and
has two hooks, both optional (identity by default):

- :meth:`Stabilizer.adjust_targets`: move the feet, CoM and torso-yaw targets of the IK
  (paper A's re-aiming of each step from the measured support foot,
  :mod:`mpcwalk.control.stabilizers.footstep_reaiming`);
- :meth:`Stabilizer.adjust_joint_targets`: add offsets to the servo targets (paper A's ankle
  strategy and IMU correction, :mod:`mpcwalk.control.stabilizers.ankle_imu`; paper M's gyro
  feedback, :mod:`mpcwalk.control.stabilizers.gyro`).

:func:`make_stabilizer` builds one by name (``"ankle-imu"``, ``"gyro"``, ``"none"``).

The balance stabilizer (:mod:`mpcwalk.control.stabilizers.balance`: DCM integral action, ZMP
distribution, foot damping, CoM offset estimate) has hooks of its own into the DCM feedback:
the controller's option ``balance`` (:class:`BalanceOptions`) sets it, not the stabilizer slot.
"""

from typing import Any

from mpcwalk.control.stabilizers.balance import BalanceStabilizer
from mpcwalk.control.stabilizers.balance_options import BalanceOptions
from mpcwalk.control.stabilizers.base import (
    GaitTargets,
    Stabilizer,
    StabilizerChain,
    StabilizerInput,
)
from mpcwalk.exceptions import ConfigurationError

STABILIZER_NAMES = ("none", "ankle-imu", "gyro")


def make_stabilizer(name: str | None, **options: Any) -> Stabilizer | None:
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


__all__ = [
    "STABILIZER_NAMES",
    "BalanceOptions",
    "BalanceStabilizer",
    "GaitTargets",
    "Stabilizer",
    "StabilizerChain",
    "StabilizerInput",
    "make_stabilizer",
]
