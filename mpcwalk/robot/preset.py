"""Robot presets: the small TOML file that turns a description into a walking robot.

A preset (``robots/presets/<name>.toml``) names the description file, the two foot frames,
the sole size, the nominal walking posture and its CoM height, the IMU site and, for URDF
models, the actuator gains; its optional ``[gait]`` table holds the robot's walking defaults,
read once, here, by :meth:`~mpcwalk.gait.gait_defaults.GaitDefaults.from_table` (an unknown
key is refused with the valid names). Its optional ``[joints]`` table names the joint of a role
(``left_knee = "..."``) where the detection from the kinematics
(:mod:`mpcwalk.robot.joint_roles`) is wrong or finds none, and ``arms = false`` declares a
robot without arms; its optional ``[base]`` table says which axes of the description's root
link point forward and up (``forward = "-x"`` for a description whose base x axis points
backward).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from typing import Protocol

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.gait_defaults import GaitDefaults
from mpcwalk.robot.base_orientation import BASE_AXES
from mpcwalk.robot.joint_roles import ROLE_KEYS

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib


class PresetFile(Protocol):
    """A preset file: a :class:`pathlib.Path` or an :mod:`importlib.resources` traversable."""

    @property
    def name(self) -> str:
        """File name."""

    def read_text(self, encoding: str | None = None) -> str:
        """Text of the file."""


@dataclass(frozen=True)
class ActuatorGains:
    """Position servo parameters applied to the joints whose name matches ``joints``.

    Attributes:
        joints: Shell-style pattern of joint names (``"*_knee_joint"``).
        kp: Stiffness [N m/rad].
        kv: Damping [N m s/rad].
        armature: Reflected rotor inertia [kg m^2], set in Pinocchio and MuJoCo.
        force_limit: Torque limit [N m]; None keeps the URDF effort limit.
    """

    joints: str
    kp: float
    kv: float
    armature: float = 0.0
    force_limit: float | None = None


@dataclass(frozen=True)
class RobotPreset:
    """The data that turns a description file into a walking robot (one TOML file).

    Attributes:
        name: Robot name (``bioloid-like``).
        format: ``"mjcf"`` (file in ``robots/``) or ``"urdf"`` (file in example-robot-data).
        description: Description file: relative to a user's preset file's folder, else to
            ``robots/`` (MJCF) or example-robot-data's ``robots/`` (URDF); or absolute.
        foot_frames: Left and right foot frames: sole sites (MJCF) or foot links (URDF).
        sole_size: Sole length and width [m].
        com_height: CoM height above the soles in the nominal posture [m].
        torso_frame: Frame to keep upright while walking.
        sole_offset: Sole centre in the foot link frame [m] (URDF only).
        sole_thickness: Height of the foot contact box the loader adds [m] (URDF only).
        sole_rpy: Orientation of the sole in the foot link frame, roll, pitch, yaw [rad]
            (URDF only): for a foot link whose axes are not x forward, z up when the sole
            is flat (iCub's); the sole frame, site and contact box follow it.
        imu_frame: Link carrying the IMU site (URDF only; MJCF files have a site ``imu``).
        imu_offset: Position of the IMU site in that link [m].
        nominal_posture: Joint angles of the walking posture [rad]; others are 0.
        actuators: Gains by joint-name pattern, first match wins (URDF only).
        timestep: Physics time step [s] (URDF only; MJCF files set their own).
        gait: Walking defaults of the ``[gait]`` table (step duration [s], double-support
            ratio, step height [m], leg limits [m] / [rad], MPC horizon, feedback gains);
            the defaults of :class:`GaitDefaults` where the preset has none.
        joints: Joint name by role key (``left_knee``...) of the ``[joints]`` table, over the
            roles found from the kinematics (checked against the joints at load).
        arms: False when the ``[joints]`` table says ``arms = false``: no arm roles.
        base_forward: Axis of the description's root link that points forward (``"x"``,
            ``"-x"``, ``"y"``, ``"-y"``, ``"z"``, ``"-z"``) from the ``[base]`` table.
        base_up: Axis of the description's root link that points up (same values).
    """

    name: str
    format: str
    description: str
    foot_frames: tuple[str, str]
    sole_size: tuple[float, float]
    com_height: float
    torso_frame: str
    sole_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    sole_thickness: float = 0.01
    sole_rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)
    imu_frame: str = ""
    imu_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    nominal_posture: dict[str, float] = field(default_factory=dict)
    actuators: tuple[ActuatorGains, ...] = ()
    timestep: float = 0.002
    gait: GaitDefaults = field(default_factory=GaitDefaults)
    joints: dict[str, str] = field(default_factory=dict)
    arms: bool = True
    base_forward: str = "x"
    base_up: str = "z"

    def __post_init__(self) -> None:
        axes = (self.base_forward, self.base_up)
        if any(axis not in BASE_AXES for axis in axes) or self.base_forward[-1] == self.base_up[-1]:
            raise ConfigurationError(
                f"Robot preset '{self.name}': [base] forward = {self.base_forward!r}, up = "
                f"{self.base_up!r}; each must be one of {', '.join(BASE_AXES)}, the two along "
                'different axes (the default: forward = "x", up = "z").'
            )

    @staticmethod
    def from_file(path: PresetFile) -> RobotPreset:
        """Read a preset from a TOML file (see ``robots/presets/``).

        Raises:
            ConfigurationError: A missing or malformed entry, or an unknown ``[gait]`` key
                (the message lists the valid ones).
        """
        try:
            raw = tomllib.loads(path.read_text())
            _check_keys(raw, path.name)
            feet, imu = raw.get("feet", {}), raw.get("imu", {})
            joints, base = dict(raw.get("joints", {})), raw.get("base", {})
            arms = joints.pop("arms", True)
            if not isinstance(arms, bool) or not all(isinstance(v, str) for v in joints.values()):
                raise ConfigurationError(
                    f"Robot preset {path.name}: [joints] maps roles to joint names (strings) "
                    f"and arms to true or false; got {raw.get('joints')}."
                )
            gait = GaitDefaults.from_table(raw.get("gait", {}), source=f"Robot preset {path.name}")
            return RobotPreset(
                name=raw["name"],
                format=raw["format"],
                description=raw["description"],
                foot_frames=(feet["left"], feet["right"]),
                sole_size=_floats(feet["sole_size"], 2),
                sole_offset=_floats(feet.get("sole_offset", (0.0, 0.0, 0.0)), 3),
                sole_thickness=float(feet.get("sole_thickness", 0.01)),
                sole_rpy=_floats(feet.get("sole_rpy", (0.0, 0.0, 0.0)), 3),
                com_height=float(raw["com_height"]),
                torso_frame=raw["torso_frame"],
                imu_frame=imu.get("frame", ""),
                imu_offset=_floats(imu.get("offset", (0.0, 0.0, 0.0)), 3),
                nominal_posture={k: float(v) for k, v in raw.get("nominal_posture", {}).items()},
                actuators=tuple(ActuatorGains(**a) for a in raw.get("actuators", [])),
                timestep=float(raw.get("timestep", 0.002)),
                gait=gait,
                joints=joints,
                arms=arms,
                base_forward=str(base.get("forward", "x")),
                base_up=str(base.get("up", "z")),
            )
        except ConfigurationError:
            raise
        except (KeyError, TypeError, ValueError, tomllib.TOMLDecodeError) as error:
            raise ConfigurationError(
                f"Robot preset {path.name} is malformed ({type(error).__name__}: {error}); "
                "compare it with robots/presets/bioloid_like.toml."
            ) from error


def _floats(values, size: int) -> tuple:
    """``values`` as a tuple of ``size`` floats (a TOML array of numbers)."""
    result = tuple(float(value) for value in values)
    if len(result) != size:
        raise ValueError(f"expected {size} numbers, got {len(result)}")
    return result


#: The keys a preset may have, per table ("" for the top level; [gait] is checked by
#: GaitDefaults, [nominal_posture] by the robot's joint names, [[actuators]] by ActuatorGains).
_PRESET_KEYS = {
    "": (
        "name",
        "format",
        "description",
        "torso_frame",
        "com_height",
        "timestep",
        "feet",
        "imu",
        "gait",
        "nominal_posture",
        "actuators",
        "joints",
        "base",
    ),
    "feet": ("left", "right", "sole_size", "sole_offset", "sole_thickness", "sole_rpy"),
    "imu": ("frame", "offset"),
    "joints": (*ROLE_KEYS, "arms"),
    "base": ("forward", "up"),
}


def _check_keys(raw: dict, source: str) -> None:
    """Refuse a misspelled key with the valid names."""
    for table, valid in _PRESET_KEYS.items():
        values = raw if not table else raw.get(table, {})
        if not isinstance(values, dict):
            raise ConfigurationError(f"Robot preset {source}: [{table}] must be a table.")
        unknown = sorted(set(values) - set(valid))
        if unknown:
            where = f"[{table}]" if table else "the top level"
            raise ConfigurationError(
                f"Robot preset {source}: unknown key(s) {', '.join(unknown)} in {where}; the "
                f"keys there are {', '.join(valid)}."
            )
