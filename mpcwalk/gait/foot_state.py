"""States of the feet along a walk: pose and velocity of each sole (re-exported by
:mod:`~mpcwalk.gait.swing_foot`)."""

from dataclasses import dataclass

import numpy as np

from mpcwalk.footsteps.footstep import Side
from mpcwalk.footsteps.rotations import rpy_matrix


@dataclass(frozen=True)
class FootState:
    """Pose and velocity of one foot (sole centre, world frame).

    The sole's orientation is ``Rz(yaw) Ry(pitch) Rx(roll)``, as a
    :class:`~mpcwalk.footsteps.footstep.Footstep`'s.

    Attributes:
        position: Sole centre, shape (3,), in [m].
        yaw: Heading about the world z axis, in [rad]. It equals the
            footstep's yaw while the foot is on the ground and is continuous
            during a swing (not wrapped).
        linear_velocity: Time derivative of ``position``, shape (3,), in [m/s].
        yaw_rate: Time derivative of ``yaw``, in [rad/s].
        in_contact: True when the foot is on the ground.
        roll: Tilt about the sole's x axis, in [rad] (the footstep's on the ground).
        pitch: Tilt about the turned y axis, in [rad] (the footstep's on the ground).
        roll_rate: Time derivative of ``roll``, in [rad/s].
        pitch_rate: Time derivative of ``pitch``, in [rad/s].
    """

    position: np.ndarray
    yaw: float
    linear_velocity: np.ndarray
    yaw_rate: float
    in_contact: bool
    roll: float = 0.0
    pitch: float = 0.0
    roll_rate: float = 0.0
    pitch_rate: float = 0.0

    @property
    def is_flat(self) -> bool:
        """True when the sole is level (roll and pitch exactly 0)."""
        return self.roll == 0.0 and self.pitch == 0.0

    @property
    def rotation(self) -> np.ndarray:
        """Orientation of the sole, ``Rz(yaw) Ry(pitch) Rx(roll)``, shape (3, 3) (exactly the
        yaw's rotation when flat)."""
        return rpy_matrix(self.roll, self.pitch, self.yaw)

    @property
    def transform(self) -> np.ndarray:
        """Homogeneous transform of the foot in the world, shape (4, 4)."""
        out = np.eye(4)
        if self.is_flat:
            c, s = np.cos(self.yaw), np.sin(self.yaw)
            out[:2, :2] = [[c, -s], [s, c]]
        else:
            out[:3, :3] = self.rotation
        out[:3, 3] = self.position
        return out

    @property
    def angular_velocity(self) -> np.ndarray:
        """Angular velocity of the sole in the world, shape (3,), in [rad/s]: ``yaw_rate``
        about z, ``pitch_rate`` about the turned y axis, ``roll_rate`` about the sole's x."""
        if self.roll_rate == 0.0 and self.pitch_rate == 0.0:
            return np.array([0.0, 0.0, self.yaw_rate])
        cy, sy = np.cos(self.yaw), np.sin(self.yaw)
        cp, sp = np.cos(self.pitch), np.sin(self.pitch)
        return np.array(
            [
                -sy * self.pitch_rate + cy * cp * self.roll_rate,
                cy * self.pitch_rate + sy * cp * self.roll_rate,
                self.yaw_rate - sp * self.roll_rate,
            ]
        )


@dataclass(frozen=True)
class FeetState:
    """State of both feet at one time.

    Attributes:
        time: Time of the query, in [s].
        step_index: Step active at ``time``: -1 before the walk, ``nb_steps``
            after it.
        left: Left foot.
        right: Right foot.
    """

    time: float
    step_index: int
    left: FootState
    right: FootState

    def __getitem__(self, side: Side | str) -> FootState:
        """State of the foot ``side`` (a :class:`Side` or ``"left"``/``"right"``)."""
        return self.left if Side.parse(side) is Side.LEFT else self.right

    @property
    def contact_sides(self) -> tuple[Side, ...]:
        """Feet on the ground (one in single support, two otherwise)."""
        return tuple(side for side in Side if self[side].in_contact)

    @property
    def swing_side(self) -> Side | None:
        """The foot in the air, or None in double support."""
        airborne = [side for side in Side if not self[side].in_contact]
        return airborne[0] if airborne else None
