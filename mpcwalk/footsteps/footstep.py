"""Footsteps and footstep plans."""

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum
from typing import Union

import numpy as np

from mpcwalk.exceptions import ConfigurationError, InfeasibleStep
from mpcwalk.footsteps.rotations import (
    MAX_FOOTSTEP_TILT,
    matrix_rpy,
    quaternion_rpy,
    rpy_matrix,
    rpy_quaternion,
    tilt_in_heading,
    unit_quaternion,
)
from mpcwalk.footsteps.timing import FootGeometry, StepTiming
from mpcwalk.terrain.surface import sole_tilt

__all__ = [
    "FootGeometry",
    "Footstep",
    "FootstepPlan",
    "HeightMap",
    "Side",
    "StepTiming",
    "rotation_2d",
    "terrain_height_map",
    "wrap_angle",
]


class Side(str, Enum):
    """Which foot."""

    LEFT = "left"
    RIGHT = "right"

    @property
    def other(self) -> "Side":
        """The opposite foot."""
        return Side.RIGHT if self is Side.LEFT else Side.LEFT

    @property
    def sign(self) -> float:
        """+1 for the left foot, -1 for the right one (lateral direction)."""
        return 1.0 if self is Side.LEFT else -1.0

    @staticmethod
    def parse(value: Union[str, "Side"]) -> "Side":
        """Side from ``"left"``/``"right"`` (case-insensitive) or a Side."""
        if isinstance(value, Side):
            return value
        try:
            return Side(str(value).lower())
        except ValueError:
            raise ConfigurationError(
                f"Foot side must be 'left' or 'right', got {value!r}."
            ) from None


def wrap_angle(angle):
    """Angle(s) wrapped to [-pi, pi), in [rad]."""
    return (np.asarray(angle) + np.pi) % (2.0 * np.pi) - np.pi


def rotation_2d(yaw: float) -> np.ndarray:
    """Planar rotation matrix, shape (2, 2)."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s], [s, c]])


#: Height of the ground and its world roll and pitch at a point: ``(x [m], y [m]) -> (z [m],
#: roll [rad], pitch [rad])``, the ground's normal being ``Ry(pitch) Rx(roll) e_z`` (see
#: :meth:`Footstep.on_ground`).
HeightMap = Callable[[float, float], tuple[float, float, float]]


def terrain_height_map(terrain) -> HeightMap:
    """The height map of a terrain: anything with ``height(x, y)`` [m] and ``normal(x, y)``
    (a unit vector), as :class:`~mpcwalk.terrain.Terrain`; its roll and pitch are the world
    angles of the normal (those of a sole of yaw 0, :func:`~mpcwalk.terrain.sole_tilt`)."""

    def height_map(x: float, y: float) -> tuple[float, float, float]:
        roll, pitch = sole_tilt(terrain.normal(x, y), 0.0)
        return float(terrain.height(x, y)), roll, pitch

    return height_map


def _angle(name: str, value, bound: float | None = None) -> float:
    """``value`` as a float angle [rad], checked finite (and within ``+-bound``)."""
    try:
        angle = float(value)
    except (TypeError, ValueError):
        angle = math.nan
    if isinstance(value, (bool, str)) or not math.isfinite(angle):
        raise ConfigurationError(f"Footstep {name} must be a finite angle [rad], got {value!r}.")
    if bound is not None and abs(angle) > bound:
        raise ConfigurationError(
            f"Footstep {name} must lie within +-{math.degrees(bound):g} deg "
            f"({bound:.4f} rad), got {angle:.4g} rad ({math.degrees(angle):.2f} deg); a sole "
            "tilted more is a wall, not a foothold: lower the tilt or step elsewhere."
        )
    return angle + 0.0  # no negative zero


def _checked_position(value) -> np.ndarray:
    """A footstep's position: 2 or 3 finite numbers [m] as a read-only (3,) array (a
    missing height is 0)."""
    pos = np.asarray(value, dtype=float).ravel()
    if pos.shape == (2,):
        pos = np.array([pos[0], pos[1], 0.0])
    # three numbers checked as Python floats (np.all(np.isfinite(...)) costs more than its
    # arithmetic: a publication of the footstep MPC moves every later footstep of the plan)
    if pos.shape != (3,) or not all(map(math.isfinite, pos.tolist())):
        raise ConfigurationError(
            f"Footstep position must be 2 or 3 finite numbers [m], got {value!r}."
        )
    pos.setflags(write=False)
    return pos


@dataclass(frozen=True)
class Footstep:
    """Pose of a foot sole on the ground, flat or tilted.

    The sole's orientation is ``Rz(yaw) Ry(pitch) Rx(roll)`` (Z-Y-X intrinsic angles, see
    :mod:`~mpcwalk.footsteps.rotations`); ``yaw`` is the heading of the sole's x axis
    projected on the horizontal plane, so the planar helpers (:attr:`xy`, :attr:`rotation`,
    :meth:`to_local`, :meth:`to_world`) work on the horizontal projection of any footstep.

    Attributes:
        side: Which foot.
        position: Sole centre in the world frame, shape (3,), in [m].
        yaw: Heading about the world z axis, in [rad].
        roll: Tilt about the sole's own x axis, in [rad], within +-45 deg (0: flat).
        pitch: Tilt about the turned y axis (positive: toes down), in [rad], within
            +-45 deg (0: flat).
    """

    side: Side
    position: np.ndarray
    yaw: float = 0.0
    roll: float = 0.0
    pitch: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "side", Side.parse(self.side))
        object.__setattr__(self, "position", _checked_position(self.position))
        if not np.isfinite(self.yaw):
            raise ConfigurationError(f"Footstep yaw must be finite, got {self.yaw!r}.")
        object.__setattr__(self, "yaw", float(self.yaw))
        object.__setattr__(self, "roll", _angle("roll", self.roll, MAX_FOOTSTEP_TILT))
        object.__setattr__(self, "pitch", _angle("pitch", self.pitch, MAX_FOOTSTEP_TILT))

    @classmethod
    def from_quaternion(cls, side, position, quaternion) -> "Footstep":
        """Footstep of a sole at ``position`` [m] turned by ``quaternion`` (w, x, y, z),
        normalised here (any non-zero norm).

        Raises:
            ConfigurationError: A zero or non-finite quaternion, or a tilt beyond 45 deg.
        """
        roll, pitch, yaw = quaternion_rpy(*unit_quaternion(quaternion))
        return cls(side, position, yaw, roll, pitch)

    @classmethod
    def from_pose(cls, side, position, rotation) -> "Footstep":
        """Footstep of a sole at ``position`` [m] with the rotation matrix ``rotation``
        (3, 3), orthonormal to 1e-6.

        Raises:
            ConfigurationError: Not a rotation matrix, or a tilt beyond 45 deg.
        """
        R = np.asarray(rotation, dtype=float)
        if (
            R.shape != (3, 3)
            or not np.all(np.isfinite(R))
            or not np.allclose(R.T @ R, np.eye(3), atol=1e-6)
            or np.linalg.det(R) < 0.0
        ):
            raise ConfigurationError(
                f"Footstep rotation must be a 3x3 rotation matrix (orthonormal, det +1), got "
                f"{rotation!r}; build one with Footstep(side, position, yaw, roll, pitch)."
            )
        roll, pitch, yaw = matrix_rpy(R)
        return cls(side, position, yaw, roll, pitch)

    @property
    def is_flat(self) -> bool:
        """True when the sole is level (roll and pitch exactly 0)."""
        return self.roll == 0.0 and self.pitch == 0.0

    @property
    def rotation_matrix(self) -> np.ndarray:
        """Orientation of the sole in the world, ``Rz(yaw) Ry(pitch) Rx(roll)``, shape (3, 3)."""
        return rpy_matrix(self.roll, self.pitch, self.yaw)

    @property
    def quaternion(self) -> np.ndarray:
        """Orientation of the sole as a unit quaternion ``(w, x, y, z)``, shape (4,)."""
        return np.array(rpy_quaternion(self.roll, self.pitch, self.yaw))

    @property
    def normal(self) -> np.ndarray:
        """The sole's z axis in the world (unit), shape (3,): ``(0, 0, 1)`` when flat."""
        return self.rotation_matrix[:, 2].copy()

    @property
    def transform(self) -> np.ndarray:
        """Homogeneous transform of the sole in the world, shape (4, 4)."""
        out = np.eye(4)
        out[:3, :3] = self.rotation_matrix
        out[:3, 3] = self.position
        return out

    @property
    def xy(self) -> np.ndarray:
        """Horizontal position, shape (2,), in [m]."""
        return self.position[:2]

    @property
    def rotation(self) -> np.ndarray:
        """Planar rotation of the foot frame (the heading), shape (2, 2)."""
        return rotation_2d(self.yaw)

    def to_local(self, point: np.ndarray) -> np.ndarray:
        """Express a world point (2,) in this foot's planar frame, in [m]."""
        return self.rotation.T @ (np.asarray(point, dtype=float)[:2] - self.xy)

    def to_world(self, point: np.ndarray) -> np.ndarray:
        """Express a point (2,) of this foot's planar frame in the world, in [m]."""
        return self.xy + self.rotation @ np.asarray(point, dtype=float)[:2]

    def moved(self, position=None, yaw=None, roll=None, pitch=None) -> "Footstep":
        """Copy with a new position, yaw, roll and/or pitch (the others kept)."""
        if yaw is None and roll is None and pitch is None and position is not None:
            # only the position is new: the side and angles are this footstep's, checked
            # already (a publication of the footstep MPC moves a dozen landings so)
            moved = object.__new__(Footstep)
            for name, value in (
                ("side", self.side),
                ("position", _checked_position(position)),
                ("yaw", self.yaw),
                ("roll", self.roll),
                ("pitch", self.pitch),
            ):
                object.__setattr__(moved, name, value)
            return moved
        return Footstep(
            self.side,
            self.position if position is None else position,
            self.yaw if yaw is None else yaw,
            self.roll if roll is None else roll,
            self.pitch if pitch is None else pitch,
        )

    def on_ground(self, z: float, roll: float, pitch: float) -> "Footstep":
        """This footstep put on a ground plane: at the height ``z`` [m], its heading kept,
        tilted so that its sole lies on a plane of world roll and pitch [rad] (the plane's
        normal is ``Ry(pitch) Rx(roll) e_z``; a sole of yaw 0 takes these angles)."""
        foot_roll, foot_pitch = tilt_in_heading(float(roll), float(pitch), self.yaw)
        return self.moved(
            position=(self.position[0], self.position[1], z), roll=foot_roll, pitch=foot_pitch
        )

    def on_height_map(self, height_map: HeightMap | None) -> "Footstep":
        """This footstep put on the ground of ``height_map`` at its (x, y) (see
        :meth:`on_ground`); itself, its height and tilt kept, when ``height_map`` is None."""
        if height_map is None:
            return self
        z, roll, pitch = height_map(float(self.position[0]), float(self.position[1]))
        return self.on_ground(z, roll, pitch)


@dataclass(frozen=True)
class FootstepPlan:
    """Initial stance and the sequence of swing-foot landings.

    Step ``k`` lifts the foot ``steps[k].side`` and puts it down at
    ``steps[k]``; the other foot supports. Sides alternate.

    Attributes:
        initial_left: Left foot before the first step.
        initial_right: Right foot before the first step.
        steps: Landing poses, one per step, alternating sides.
        timing: Step duration, double support ratio, start and stop phases.
    """

    initial_left: Footstep
    initial_right: Footstep
    steps: tuple[Footstep, ...] = ()
    timing: StepTiming = field(default_factory=StepTiming)

    def __post_init__(self) -> None:
        object.__setattr__(self, "steps", tuple(self.steps))
        for name in ("initial_left", "initial_right"):
            if not isinstance(getattr(self, name), Footstep):
                raise ConfigurationError(
                    f"FootstepPlan.{name} must be a Footstep, got {getattr(self, name)!r}; e.g. "
                    "Footstep(Side.LEFT, (0.0, 0.04, 0.0))."
                )
        if any(not isinstance(step, Footstep) for step in self.steps):
            raise ConfigurationError("FootstepPlan.steps must be Footsteps.")
        if self.initial_left.side is not Side.LEFT or self.initial_right.side is not Side.RIGHT:
            raise ConfigurationError(
                "FootstepPlan needs initial_left on the left side and initial_right on "
                f"the right, got {self.initial_left.side.value} and "
                f"{self.initial_right.side.value}."
            )
        for k in range(1, len(self.steps)):
            if self.steps[k].side is self.steps[k - 1].side:
                raise InfeasibleStep(
                    f"Footsteps must alternate sides: steps {k - 1} and {k} both move "
                    f"the {self.steps[k].side.value} foot. Insert a step of the other foot."
                )

    @property
    def nb_steps(self) -> int:
        """Number of steps (swing phases)."""
        return len(self.steps)

    def stance(self, k: int) -> dict[Side, Footstep]:
        """Feet on the ground before step ``k`` (k = nb_steps: after the last)."""
        if not 0 <= k <= self.nb_steps:
            raise IndexError(f"step index {k} outside [0, {self.nb_steps}]")
        feet = {Side.LEFT: self.initial_left, Side.RIGHT: self.initial_right}
        for step in self.steps[:k]:
            feet[step.side] = step
        return feet

    def stances(self):
        """All stances: list of ``nb_steps + 1`` dicts side -> Footstep."""
        left, right = self.initial_left, self.initial_right
        out = [{Side.LEFT: left, Side.RIGHT: right}]
        for step in self.steps:  # (a schedule is made with them at every publication)
            if step.side is Side.LEFT:
                left = step
            else:
                right = step
            out.append({Side.LEFT: left, Side.RIGHT: right})
        return out

    def support_foot(self, k: int) -> Footstep:
        """Support foot during step ``k``."""
        return self.stance(k)[self.steps[k].side.other]
