"""Footsteps and footstep plans."""

from dataclasses import dataclass, field
from enum import Enum
from typing import Union

import numpy as np

from mpcwalk.exceptions import ConfigurationError, InfeasibleStep


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


@dataclass(frozen=True)
class Footstep:
    """Pose of a flat foot on the ground.

    Attributes:
        side: Which foot.
        position: Sole centre in the world frame, shape (3,), in [m].
        yaw: Heading about the world z axis, in [rad].
    """

    side: Side
    position: np.ndarray
    yaw: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "side", Side.parse(self.side))
        pos = np.asarray(self.position, dtype=float).ravel()
        if pos.shape == (2,):
            pos = np.array([pos[0], pos[1], 0.0])
        if pos.shape != (3,) or not np.all(np.isfinite(pos)):
            raise ConfigurationError(
                f"Footstep position must be 2 or 3 finite numbers [m], got {self.position!r}."
            )
        if not np.isfinite(self.yaw):
            raise ConfigurationError(f"Footstep yaw must be finite, got {self.yaw!r}.")
        pos.setflags(write=False)
        object.__setattr__(self, "position", pos)
        object.__setattr__(self, "yaw", float(self.yaw))

    @property
    def xy(self) -> np.ndarray:
        """Horizontal position, shape (2,), in [m]."""
        return self.position[:2]

    @property
    def rotation(self) -> np.ndarray:
        """Planar rotation of the foot frame, shape (2, 2)."""
        return rotation_2d(self.yaw)

    def to_local(self, point: np.ndarray) -> np.ndarray:
        """Express a world point (2,) in this foot's planar frame, in [m]."""
        return self.rotation.T @ (np.asarray(point, dtype=float)[:2] - self.xy)

    def to_world(self, point: np.ndarray) -> np.ndarray:
        """Express a point (2,) of this foot's planar frame in the world, in [m]."""
        return self.xy + self.rotation @ np.asarray(point, dtype=float)[:2]

    def moved(self, position=None, yaw=None) -> "Footstep":
        """Copy with a new position and/or yaw."""
        return Footstep(
            self.side,
            self.position if position is None else position,
            self.yaw if yaw is None else yaw,
        )


@dataclass(frozen=True)
class StepTiming:
    """Timing of a walk (paper M sec. 3: each step starts and ends in double support).

    Attributes:
        step_duration: Duration ``T`` of one step (one foot moves), in [s].
        double_support_ratio: ``r_ds = T_ds / T`` in [0, 1); half of the double
            support opens the step, half closes it.
        initial_duration: Standing double support before the first step, in [s].
        final_duration: Double support after the last step, in [s].
    """

    step_duration: float = 0.5  # [s] (paper M, Table 1)
    double_support_ratio: float = 0.2  # [] (paper M, Table 1)
    initial_duration: float = 1.0  # [s]
    final_duration: float = 1.0  # [s]

    def __post_init__(self) -> None:
        T = self.step_duration
        if isinstance(T, (bool, str)) or not np.isfinite(T) or T <= 0.0 or T > 60.0:
            raise ConfigurationError(
                f"step_duration must be a number of seconds in (0, 60], got {T!r}; "
                "paper M uses 0.5 s, paper A 12 s."
            )
        r = self.double_support_ratio
        if not np.isfinite(r) or not 0.0 <= r < 1.0:
            raise ConfigurationError(
                f"double_support_ratio must lie in [0, 1), got {r!r}; it is the "
                "fraction of each step spent with both feet down (paper M: 0.2)."
            )
        for name in ("initial_duration", "final_duration"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0.0:
                raise ConfigurationError(
                    f"{name} must be a non-negative number of seconds, got {value!r}."
                )

    @property
    def single_support_begin(self) -> float:
        """``t_b = r_ds T / 2``: time in the step when single support begins, in [s]."""
        return 0.5 * self.double_support_ratio * self.step_duration

    @property
    def single_support_end(self) -> float:
        """``t_e = T - r_ds T / 2``: time in the step when single support ends, in [s]."""
        return self.step_duration - self.single_support_begin


@dataclass(frozen=True)
class FootGeometry:
    """Flat rectangular sole.

    Attributes:
        length: Along the foot x axis, in [m].
        width: Along the foot y axis, in [m].
    """

    length: float = 0.10  # [m] small servo humanoid
    width: float = 0.06  # [m]

    def __post_init__(self) -> None:
        if (
            not (np.isfinite(self.length) and np.isfinite(self.width))
            or min(self.length, self.width) <= 0.0
        ):
            raise ConfigurationError(
                f"Foot length and width must be positive, got {self.length!r} x {self.width!r} m."
            )


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
        feet = {Side.LEFT: self.initial_left, Side.RIGHT: self.initial_right}
        out = [dict(feet)]
        for step in self.steps:
            feet[step.side] = step
            out.append(dict(feet))
        return out

    def support_foot(self, k: int) -> Footstep:
        """Support foot during step ``k``."""
        return self.stance(k)[self.steps[k].side.other]
