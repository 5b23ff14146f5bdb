"""Joint roles: which joint is the left knee, the right ankle roll, the left shoulder pitch.

The controllers that act on named joints (paper M's gyro stabilizer and arm swing, paper A's
ankle strategy) read a robot's :class:`JointRoles` instead of guessing from joint names.
:func:`~mpcwalk.robot.joint_role_detection.detect_joint_roles` finds them from the kinematics alone, the same way on every robot;
a preset's ``[joints]`` table names those it gets wrong or cannot find
(:func:`with_preset_table`).

The detection rules: :mod:`mpcwalk.robot.joint_role_detection`.
"""

from __future__ import annotations

import types
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from mpcwalk.exceptions import ConfigurationError

SIDES = ("left", "right")
"""The two sides, in the order of a robot's foot frames."""

LEG_ROLES = ("hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle_pitch", "ankle_roll")
"""The roles of a leg's joints, from the hip down."""

ARM_ROLES = ("shoulder_pitch", "shoulder_roll", "elbow")
"""The roles of an arm's joints."""

ROLES = LEG_ROLES + ARM_ROLES

ROLE_KEYS = tuple(f"{side}_{role}" for side in SIDES for role in ROLES)
"""The keys of a preset's ``[joints]`` table (``left_hip_yaw``...``right_elbow``)."""


@dataclass(frozen=True)
class JointRoles:
    """The joint of each role on each side (None where the robot has none).

    Attributes:
        names: Joint name (or None) by role key ``<side>_<role>`` (:data:`ROLE_KEYS`); a
            mapping given without some keys has None there.
        notes: What detection could not settle (ambiguous axes, missing arms), for the
            messages of the controllers that need a role it left empty.
    """

    names: Mapping[str, str | None] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        unknown = sorted(set(self.names) - set(ROLE_KEYS))
        if unknown:
            raise ConfigurationError(
                f"Unknown joint role(s) {', '.join(unknown)}; the roles are {', '.join(ROLE_KEYS)}."
            )
        names = {key: self.names.get(key) for key in ROLE_KEYS}
        object.__setattr__(self, "names", types.MappingProxyType(names))
        object.__setattr__(self, "notes", tuple(self.notes))

    def __reduce__(self) -> tuple:
        return JointRoles, (dict(self.names), self.notes)  # a mapping proxy does not pickle

    def joint(self, side: str, role: str) -> str | None:
        """The joint of ``role`` on ``side`` (``"left"`` or ``"right"``), or None."""
        key = f"{side}_{role}"
        if key not in self.names:
            raise ConfigurationError(
                f"Unknown joint role {side!r}, {role!r}: the sides are {', '.join(SIDES)}, "
                f"the roles {', '.join(ROLES)}."
            )
        return self.names[key]

    def leg(self, side: str) -> dict[str, str | None]:
        """The joints of the leg of ``side`` by role (:data:`LEG_ROLES`)."""
        return {role: self.joint(side, role) for role in LEG_ROLES}

    def arm(self, side: str) -> dict[str, str | None]:
        """The joints of the arm of ``side`` by role (:data:`ARM_ROLES`)."""
        return {role: self.joint(side, role) for role in ARM_ROLES}

    @property
    def has_arms(self) -> bool:
        """Whether both sides have an arm joint of some role."""
        return all(any(self.arm(side).values()) for side in SIDES)

    def require(self, roles: Iterable[str], *, user: str, robot: str) -> dict[str, str]:
        """The joints of ``roles`` on both sides, by role key (``left_knee``...).

        Args:
            roles: Roles needed (:data:`ROLES`).
            user: What needs them, for the message (``"The gyro stabilizer"``).
            robot: Robot name, for the message.

        Raises:
            ConfigurationError: A role without a joint (the message names the preset key
                that sets it).
        """
        found, missing = {}, []
        for side in SIDES:
            for role in roles:
                name = self.joint(side, role)
                if name is None:
                    missing.append(f"{side}_{role}")
                else:
                    found[f"{side}_{role}"] = name
        if missing:
            notes = f" ({'; '.join(self.notes)})" if self.notes else ""
            raise ConfigurationError(
                f"{user} needs the joints {', '.join(missing)}; robot '{robot}' has none found "
                f"from its kinematics{notes}. Name them in its preset's [joints] table, e.g. "
                f'{missing[0]} = "<joint name>".'
            )
        return found


def with_preset_table(
    roles: JointRoles,
    table: Mapping[str, str],
    *,
    arms: bool,
    joint_names: Sequence[str],
    source: str,
) -> JointRoles:
    """``roles`` with the entries of a preset's ``[joints]`` table over them; all arm roles
    None when ``arms`` is false (the table's arm entries then are refused).

    Raises:
        ConfigurationError: An unknown role key, a joint name the robot does not have, or an
            arm role named with ``arms = false``.
    """
    unknown = sorted(set(table) - set(ROLE_KEYS))
    if unknown:
        raise ConfigurationError(
            f"{source}: unknown [joints] key(s) {', '.join(unknown)}; the keys are "
            f"{', '.join(ROLE_KEYS)} and arms."
        )
    for key, name in table.items():
        if name not in joint_names:
            raise ConfigurationError(
                f"{source}: [joints] {key} = {name!r} is no joint of the robot; the joints are "
                f"{', '.join(joint_names)}."
            )
    names = dict(roles.names)
    notes = list(roles.notes)
    if not arms:
        named = sorted(k for k in table if k.split("_", 1)[1] in ARM_ROLES)
        if named:
            raise ConfigurationError(
                f"{source}: [joints] says arms = false and names the arm joint(s) "
                f"{', '.join(named)}; remove one or the other."
            )
        names.update({f"{side}_{role}": None for side in SIDES for role in ARM_ROLES})
        notes = [note for note in notes if "arm" not in note]
        notes.append("the preset says the robot has no arms")
    names.update(table)
    return JointRoles(names, tuple(notes))


__all__ = [
    "ARM_ROLES",
    "LEG_ROLES",
    "ROLES",
    "ROLE_KEYS",
    "SIDES",
    "JointRoles",
    "with_preset_table",
]
