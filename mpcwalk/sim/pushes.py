"""External forces on the robot over a time window (pushes, for the disturbance experiments).

Paper M pushes its robot's torso with F1 = (0, 5, 0) N for 0.1 s at rest and F2 = (10, 5, 0) N
for 0.05 s while walking. Here a push is an :class:`ExternalForce`; from the command line it
is the string ``"T,DURATION,FX,FY,FZ"`` read by :func:`parse_push`.
"""

import math
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from mpcwalk.exceptions import ConfigurationError, PushFormatError

TORSO = "torso"
"""Body name meaning the robot's torso frame (``robot.torso_frame``)."""

BASE = "base"
"""Body name meaning the robot's floating base (the body of the free joint)."""

_PUSH_FIELDS = ("T", "DURATION", "FX", "FY", "FZ")
_TIME_TOLERANCE = 1e-9  # [s] so that windows on the time-step grid are half-open exactly


def _vector3(value, name: str) -> np.ndarray:
    array = np.asarray(value, dtype=float)
    if array.shape != (3,) or not np.all(np.isfinite(array)):
        raise ConfigurationError(f"ExternalForce.{name} must be 3 finite numbers, got {value!r}.")
    array = array.copy()
    array.setflags(write=False)
    return array


@dataclass(frozen=True)
class ExternalForce:
    """A force (and optional torque) on one body of the robot during ``[start, start+duration)``.

    Attributes:
        start: Start time [s], simulated time.
        duration: Duration [s].
        force: Force in the world frame, shape (3,), in [N].
        body: MuJoCo body it acts on; ``"torso"`` means the robot's torso frame and
            ``"base"`` its floating base, any other string is a body name.
        point: Application point in the body frame, shape (3,), in [m]; None applies the
            force at the body's centre of mass.
        torque: Extra torque in the world frame, shape (3,), in [N m]; None for none.
    """

    start: float
    duration: float
    force: np.ndarray
    body: str = TORSO
    point: np.ndarray | None = None
    torque: np.ndarray | None = None

    def __post_init__(self) -> None:
        if not (math.isfinite(self.start) and self.start >= 0.0):
            raise ConfigurationError(f"ExternalForce.start must be >= 0 s, got {self.start!r}.")
        if not (math.isfinite(self.duration) and self.duration > 0.0):
            raise ConfigurationError(
                f"ExternalForce.duration must be > 0 s, got {self.duration!r}."
            )
        object.__setattr__(self, "force", _vector3(self.force, "force"))
        if self.point is not None:
            object.__setattr__(self, "point", _vector3(self.point, "point"))
        if self.torque is not None:
            object.__setattr__(self, "torque", _vector3(self.torque, "torque"))

    @property
    def end(self) -> float:
        """End time [s] (excluded from the window)."""
        return self.start + self.duration

    def is_active(self, time: float) -> bool:
        """Whether the force acts at simulated ``time`` [s]."""
        return self.start - _TIME_TOLERANCE <= time < self.end - _TIME_TOLERANCE

    def apply(self, data: mujoco.MjData, body_id: int) -> None:
        """Add this force to ``data.xfrc_applied`` of body ``body_id`` (the caller zeroes it)."""
        torque = np.zeros(3) if self.torque is None else self.torque
        if self.point is not None:  # moment of the force about the body's CoM
            rotation = data.xmat[body_id].reshape(3, 3)
            point = data.xpos[body_id] + rotation @ self.point
            torque = torque + np.cross(point - data.xipos[body_id], self.force)
        data.xfrc_applied[body_id, 0:3] += self.force
        data.xfrc_applied[body_id, 3:6] += torque


def parse_push(text: str, *, body: str = TORSO) -> ExternalForce:
    """Read a push ``"T,DURATION,FX,FY,FZ"`` (start [s], duration [s], world force [N]).

    Args:
        text: The push, e.g. ``"3.0,0.05,10,5,0"``.
        body: Body pushed (``"torso"`` by default).

    Raises:
        PushFormatError: Not five numbers, a negative start or a non-positive duration.
    """
    fields = [field.strip() for field in str(text).split(",")]
    if len(fields) != len(_PUSH_FIELDS):
        raise PushFormatError(text, f"{len(fields)} comma-separated fields instead of 5")
    values = []
    for name, field in zip(_PUSH_FIELDS, fields):
        try:
            value = float(field)
        except ValueError:
            raise PushFormatError(text, f"field {name} is '{field}', not a number") from None
        if not math.isfinite(value):
            raise PushFormatError(text, f"field {name} is '{field}', not a finite number")
        values.append(value)
    start, duration = values[0], values[1]
    if start < 0.0:
        raise PushFormatError(text, f"start time T = {start:g} s is negative")
    if duration <= 0.0:
        raise PushFormatError(text, f"DURATION = {duration:g} s is not positive")
    return ExternalForce(start=start, duration=duration, force=np.array(values[2:]), body=body)


def resolve_body(model: mujoco.MjModel, body: str, torso_frame: str) -> int:
    """MuJoCo body index of an :attr:`ExternalForce.body` name.

    Raises:
        ConfigurationError: No such body; the message lists the bodies that exist.
    """
    if body == BASE:
        return int(model.jnt_bodyid[0])
    name = torso_frame if body == TORSO else body
    body_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name)
    if body_id < 0:
        names: Sequence[str] = [model.body(i).name for i in range(1, model.nbody)]
        raise ConfigurationError(
            f"External force on body '{name}', which the robot does not have; use 'torso', "
            f"'base' or one of: {', '.join(names)}."
        )
    return int(body_id)
