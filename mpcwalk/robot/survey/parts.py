"""What a drafted preset holds (:func:`~mpcwalk.robot.survey.draft.draft_preset` fills it,
:func:`~mpcwalk.robot.survey.writer.preset_toml` writes it)."""

from __future__ import annotations

from dataclasses import dataclass, field

from mpcwalk.robot.joint_roles import JointRoles
from mpcwalk.robot.survey.legs import LegSurvey
from mpcwalk.robot.survey.posture import Posture

#: Share of a joint's torque limit its servo may need to stand; beyond, the draft warns.
TORQUE_SHARE = 0.8


@dataclass(frozen=True)
class Servo:
    """The drafted servo of one joint, and the standing torque it must hold."""

    joint: str
    kp: float
    kv: float
    armature: float
    standing_torque: float
    torque_limit: float
    rule: str


@dataclass(frozen=True)
class Sole:
    """A sole in its foot link's frame: centre of its bottom face [m], length and width [m]
    along its axes, where they came from, and its orientation in the foot link's frame
    (roll, pitch, yaw [rad]; zero where the link's axes are the sole's)."""

    offset: tuple[float, float, float]
    size: tuple[float, float]
    source: str
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class PresetDraft:
    """Everything :func:`~mpcwalk.robot.survey.draft.draft_preset` found.

    ``base`` holds the description root's forward and up axes; ``legs`` and everything
    after it are in the loader's frame (the root re-expressed x forward, z up)."""

    name: str
    description: str
    base: tuple[str, str]
    legs: LegSurvey
    roles: JointRoles
    soles: tuple[Sole, Sole]
    torso: tuple[str, str]
    imu: tuple[str, str]
    posture: Posture
    leg_length: float
    mass: float
    servos: tuple[Servo, ...]
    gait: dict[str, float]
    repaired_links: tuple[str, ...]
    notes: tuple[str, ...] = field(default=())

    @property
    def warnings(self) -> tuple[str, ...]:
        """What the user should look at before walking (joints outside limits, servos
        that cannot hold the robot up)."""
        found = [
            f"joint {joint} of the walking posture at {angle:.3f} rad is outside its limits "
            f"[{low:.3f}, {high:.3f}]"
            for joint, angle, low, high in self.posture.outside_limits
        ]
        found += [
            f"joint {s.joint} needs {abs(s.standing_torque):.1f} N m to stand, "
            f"{abs(s.standing_torque) / s.torque_limit:.0%} of its limit {s.torque_limit:g} N m"
            for s in self.servos
            if s.torque_limit > 0 and abs(s.standing_torque) > TORQUE_SHARE * s.torque_limit
        ]
        return tuple(found)


__all__ = ["TORQUE_SHARE", "PresetDraft", "Servo", "Sole"]
