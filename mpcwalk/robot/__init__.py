"""Robots: one description loaded into Pinocchio and MuJoCo, its preset and its sensors.

:func:`load_robot` builds a :class:`Robot` from its preset (:class:`RobotPreset`, with the
walking defaults of its ``[gait]`` table); :class:`SensorReadings` are what its sensors report
each tick. Importing this package loads no MuJoCo: :func:`load_robot` and
:func:`robot_names` import the loader on first use.
"""

from typing import Any

from mpcwalk.robot.preset import ActuatorGains, RobotPreset
from mpcwalk.robot.robot import Robot, ServoGains
from mpcwalk.robot.sensors import FootContact, ForceTorqueReading, ImuReading, SensorReadings

_LAZY = {"load_robot", "robot_names"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        from mpcwalk.robot import loading

        return getattr(loading, name)
    raise AttributeError(f"module 'mpcwalk.robot' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_LAZY])


__all__ = [
    "ActuatorGains",
    "FootContact",
    "ForceTorqueReading",
    "ImuReading",
    "Robot",
    "RobotPreset",
    "SensorReadings",
    "ServoGains",
    "load_robot",
    "robot_names",
]
