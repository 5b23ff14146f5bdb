"""The pieces a terrain is made of: flat or sloped rectangular tops (:class:`Surface`).

A :class:`Surface` is the top face of one block of the terrain: a rectangle of the
horizontal plane (its footprint, axis-aligned in the world frame, whose x axis is the
robot's initial heading) carrying a plane that rises by ``slope`` [rad] along x. Each
surface is the top of a solid that reaches down to the terrain's floor, so the simulator
builds it as one box (:meth:`Surface.box`).
"""

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Box:
    """A solid box of the simulated scene.

    Attributes:
        center: Centre, shape (3,), in [m].
        half_size: Half extents along the box's own axes, shape (3,), in [m].
        pitch: Rotation about the world y axis [rad] (positive: the box's x axis tilts
            down, so a top that rises along x has ``pitch = -slope``).
    """

    center: tuple[float, float, float]
    half_size: tuple[float, float, float]
    pitch: float = 0.0

    @property
    def quaternion(self) -> tuple[float, float, float, float]:
        """Orientation ``(w, x, y, z)``."""
        return (math.cos(0.5 * self.pitch), 0.0, math.sin(0.5 * self.pitch), 0.0)


@dataclass(frozen=True)
class Surface:
    """Top face of one block of a terrain.

    Attributes:
        x_min: Footprint's back edge [m].
        x_max: Footprint's front edge [m].
        y_min: Footprint's right edge [m].
        y_max: Footprint's left edge [m].
        height: Height [m] of the top at ``x_min``.
        slope: Rise of the top along x [rad] (0: level).
        kind: What the block is (``"tread"``, ``"landing"``, ``"ramp"``, ``"stone"``,
            ``"block"``, ``"floor"``), for figures and reports.
    """

    x_min: float
    x_max: float
    y_min: float
    y_max: float
    height: float
    slope: float = 0.0
    kind: str = "floor"

    @property
    def length(self) -> float:
        """Footprint length along x [m]."""
        return self.x_max - self.x_min

    @property
    def width(self) -> float:
        """Footprint width along y [m]."""
        return self.y_max - self.y_min

    @property
    def end_height(self) -> float:
        """Height [m] of the top at ``x_max``."""
        return self.height + self.length * math.tan(self.slope)

    @property
    def top(self) -> float:
        """Highest point of the top [m]."""
        return max(self.height, self.end_height)

    @property
    def normal(self) -> np.ndarray:
        """Unit normal of the top, shape (3,)."""
        return np.array([-math.sin(self.slope), 0.0, math.cos(self.slope)])

    def contains(self, x, y, tolerance: float = 0.0):
        """Whether points lie over the footprint (grown by ``tolerance`` [m]), vectorised."""
        x, y = np.asarray(x), np.asarray(y)
        return (
            (x >= self.x_min - tolerance)
            & (x <= self.x_max + tolerance)
            & (y >= self.y_min - tolerance)
            & (y <= self.y_max + tolerance)
        )

    def height_at(self, x) -> np.ndarray:
        """Height [m] of the top's plane above ``x`` [m] (vectorised; not clipped)."""
        return self.height + (np.asarray(x, dtype=float) - self.x_min) * math.tan(self.slope)

    def inner_distance(self, x, y) -> np.ndarray:
        """Signed distance [m] of points to the footprint's edges, positive inside
        (vectorised): how far a sole corner is from falling off this block."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        inside = np.minimum.reduce([x - self.x_min, self.x_max - x, y - self.y_min, self.y_max - y])
        dx = np.maximum.reduce([self.x_min - x, np.zeros_like(x), x - self.x_max])
        dy = np.maximum.reduce([self.y_min - y, np.zeros_like(y), y - self.y_max])
        return np.where(inside >= 0.0, inside, -np.hypot(dx, dy))

    def box(self, floor: float) -> Box:
        """The solid under this top, down to ``floor`` [m], as one box (a sloped top: a
        tilted box whose top face is the ramp, deep enough to reach the floor)."""
        half_y = 0.5 * self.width
        center_y = 0.5 * (self.y_min + self.y_max)
        if self.slope == 0.0:
            half_z = 0.5 * (self.height - floor)
            return Box(
                (0.5 * (self.x_min + self.x_max), center_y, floor + half_z),
                (0.5 * self.length, half_y, half_z),
            )
        along = self.length / math.cos(self.slope)  # length of the ramp's top face
        depth = max(self.top - floor, 0.05)
        mid = np.array(
            [0.5 * (self.x_min + self.x_max), center_y, 0.5 * (self.height + self.end_height)]
        )
        center = mid - 0.5 * depth * self.normal
        return Box(
            (float(center[0]), float(center[1]), float(center[2])),
            (0.5 * along, half_y, 0.5 * depth),
            pitch=-self.slope,
        )


def sole_tilt(normal: np.ndarray, yaw: float) -> tuple[float, float]:
    """Roll and pitch [rad] of a sole with heading ``yaw`` [rad] lying on a plane of unit
    ``normal``: the angles of ``R = Rz(yaw) Ry(pitch) Rx(roll)`` whose z axis is the
    normal (the sole keeps its yaw exactly)."""
    c, s = math.cos(yaw), math.sin(yaw)
    n = np.asarray(normal, dtype=float)
    m = np.array([c * n[0] + s * n[1], -s * n[0] + c * n[1], n[2]])
    roll = -math.asin(float(np.clip(m[1], -1.0, 1.0)))
    pitch = math.atan2(float(m[0]), float(m[2]))
    return roll, pitch


__all__ = ["Box", "Surface", "sole_tilt"]
