"""Stabilizers: corrections a :class:`~mpcwalk.control.controller.WalkingController` applies on
top of its kinematic references, from the estimated state.

A stabilizer receives a typed :class:`StabilizerInput` each tick, never the controller, and
has two hooks, both optional (identity by default):

- :meth:`Stabilizer.adjust_targets`: move the feet, CoM and torso-yaw targets of the IK
  (the re-aiming of each step from the measured support foot, paper A,
  :mod:`mpcwalk.control.stabilizers.footstep_reaiming`);
- :meth:`Stabilizer.adjust_joint_targets`: add offsets to the servo targets (the ankle
  strategy and IMU correction of paper A, :mod:`mpcwalk.control.stabilizers.ankle_imu`; the
  gyro feedback of paper M, :mod:`mpcwalk.control.stabilizers.gyro`).

:data:`STABILIZERS` is their :class:`~mpcwalk.registry.Registry` (``"none"``,
``"ankle-imu"``, ``"gyro"``, ``"reaim"``); :func:`make_stabilizer` builds one by name.

The balance stabilizer (:mod:`mpcwalk.control.stabilizers.balance`: DCM integral action, ZMP
distribution, foot damping, CoM offset estimate) has hooks of its own into the DCM feedback:
the controller's option ``balance`` (:class:`BalanceOptions`) sets it, not the stabilizer slot.
"""

from collections.abc import Callable
from typing import Any

from mpcwalk.control.stabilizers.balance import BalanceStabilizer
from mpcwalk.control.stabilizers.balance_options import BalanceOptions
from mpcwalk.control.stabilizers.base import (
    GaitTargets,
    Stabilizer,
    StabilizerChain,
    StabilizerInput,
)
from mpcwalk.exceptions import StabilizerNotFound
from mpcwalk.generators.registry import check_options
from mpcwalk.registry import Entry, Registry

#: What a stabilizer's name stands for: its factory, called with the stabilizer's options.
StabilizerFactory = Callable[..., Stabilizer | None]


def _no_stabilizer(**_options: Any) -> None:
    """No stabilizer: the IK's results go to the servos as they are."""
    return None


def _ankle_imu() -> StabilizerFactory:
    from mpcwalk.control.stabilizers.ankle_imu import AnkleImuStabilizer

    return AnkleImuStabilizer


def _gyro() -> StabilizerFactory:
    from mpcwalk.control.stabilizers.gyro import GyroStabilizer

    return GyroStabilizer


def _reaim() -> StabilizerFactory:
    from mpcwalk.control.stabilizers.footstep_reaiming import FootstepReaiming

    return FootstepReaiming  # its yaw from the IMU by default, as paper A


#: The stabilizers by name, in the order the command line lists them.
STABILIZERS: Registry[StabilizerFactory] = Registry(
    "stabilizer",
    [
        Entry(
            "none",
            "No stabilizer: the IK's joint targets go to the servos.",
            lambda: _no_stabilizer,
        ),
        Entry(
            "ankle-imu",
            "PID on the ankles keeping the support normal at the CoM, plus IMU correction "
            "(paper A).",
            _ankle_imu,
        ),
        Entry(
            "gyro",
            "Leg joint offsets proportional to the torso roll/pitch rates (paper M).",
            _gyro,
        ),
        Entry(
            "reaim",
            "Re-aims every step from the measured support foot, yaw from the IMU (paper A).",
            _reaim,
        ),
    ],
    list_command="mpcwalk stabilizers",
    not_found=StabilizerNotFound,
)


def make_stabilizer(name: str | None, **options: Any) -> Stabilizer | None:
    """Stabilizer called ``name`` with its ``options`` (None or ``"none"``: no stabilizer),
    e.g. ``make_stabilizer("gyro", max_offset=0.01)``.

    Raises:
        StabilizerNotFound: Unknown name (the message lists the known ones).
        ConfigurationError: An option the stabilizer does not take (the message lists the
            ones it takes), or a bad value.
    """
    if name is None:
        return None
    factory = STABILIZERS.load(name)
    check_options(factory, options, f"stabilizer '{name}'")
    return factory(**options)


__all__ = [
    "STABILIZERS",
    "BalanceOptions",
    "BalanceStabilizer",
    "GaitTargets",
    "Stabilizer",
    "StabilizerChain",
    "StabilizerInput",
    "make_stabilizer",
]
