"""A terrain: the ground a walk crosses, as the planner, the controller and the scene see it.

A :class:`Terrain` lays its features (:mod:`mpcwalk.terrain.features`) one after the other
along the robot's initial heading (the world's x axis, from the start at x = 0), each on the
level the ones before it left, between level stretches of ground. It answers the planner's
and the controller's questions vectorised over points: the height and the normal under a
point, the block a sole rests on and how far its corners are from that block's edges
(:meth:`Terrain.sole_support`), the highest ground under a swing foot's way
(:meth:`Terrain.highest_along`); :meth:`Terrain.boxes` gives the solids the simulator
builds, down to the terrain's :attr:`Terrain.floor`.
"""

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import TerrainError
from mpcwalk.terrain.features import Feature
from mpcwalk.terrain.surface import Box, Surface, sole_tilt

#: Ground laid behind the start [m].
BEHIND = 1.0
#: Ground laid beyond the last feature [m].
BEYOND = 3.0


@dataclass(frozen=True)
class SoleSupport:
    """Where a sole rests on a terrain.

    Attributes:
        height: Height [m] of the sole's centre resting on the terrain.
        roll: Roll [rad] of the sole on the surface (``R = Rz(yaw) Ry(pitch) Rx(roll)``).
        pitch: Pitch [rad] of the sole on the surface.
        surface: Index of the surface it rests on in :attr:`Terrain.surfaces`, or -1 (the
            floor).
        margin: Smallest signed distance [m] of the sole's corners to that surface's edges
            (positive: the whole sole is on it).
    """

    height: float
    roll: float
    pitch: float
    surface: int
    margin: float


def _x_min(surface: Surface) -> float:
    return surface.x_min


class Terrain:
    """The ground of a walk.

    Args:
        features: Stairs, slopes, platforms, stepping stones and rough patches, in any
            order; they must not overlap.
        width: Width [m] of the terrain across the heading (centred on it).

    Raises:
        TerrainError: Overlapping features, or a width out of range.
    """

    def __init__(self, features: Sequence[Feature] = (), width: float = 3.0) -> None:
        self.width = checked_number(
            "Terrain.width",
            width,
            low=0.2,
            high=20.0,
            unit="m",
            error=lambda expected: TerrainError(
                f"Terrain.width must be {expected}, got {width!r}."
            ),
        )
        for feature in features:
            if not isinstance(feature, Feature):
                raise TerrainError(
                    f"A terrain holds Stairs, Slope, Platform, SteppingStones or RoughPatch "
                    f"features, got {type(feature).__name__} {feature!r}."
                )
        self.features: tuple[Feature, ...] = tuple(sorted(features, key=lambda f: f.start))
        for before, after in zip(self.features, self.features[1:]):
            if after.start < before.end - 1e-9:
                raise TerrainError(
                    f"Terrain features overlap: {type(after).__name__} at {after.start:g} m starts "
                    f"before {type(before).__name__} at {before.start:g} m ends ({before.end:g} "
                    "m); move it further."
                )
        self.surfaces: tuple[Surface, ...] = tuple(self._lay())
        self.floor = min(0.0, *(min(s.height, s.end_height) for s in self.surfaces))
        """Height [m] of the plane under everything (the lowest top; 0 or below)."""
        table = [
            (s.x_min, s.x_max, s.y_min, s.y_max, s.height, math.tan(s.slope)) for s in self.surfaces
        ]
        self._table = np.array(table).reshape(-1, 6)

    @property
    def is_flat(self) -> bool:
        """Whether the terrain is the level floor (no feature)."""
        return not self.features

    def _lay(self) -> list[Surface]:
        half = 0.5 * self.width
        level, cursor = 0.0, -BEHIND
        out: list[Surface] = []
        for feature in self.features:
            if feature.start > cursor:
                out.append(Surface(cursor, feature.start, -half, half, level, kind="landing"))
            out.extend(feature.surfaces(level, half))
            level += feature.level_change()
            cursor = feature.end
        out.append(Surface(cursor, cursor + BEYOND, -half, half, level, kind="landing"))
        return out

    @property
    def level_after(self) -> float:
        """Height [m] of the ground after the last feature."""
        return self.surfaces[-1].height

    @property
    def length(self) -> float:
        """Distance [m] from the start to the end of the laid ground."""
        return self.surfaces[-1].x_max

    # ------------------------------------------------------------------ queries
    def _heights(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Heights of every surface's plane above points (-inf outside its footprint),
        shape (points, surfaces), and the index of the highest (-1: the floor)."""
        t = self._table
        xs, ys = x[:, None], y[:, None]
        inside = (xs >= t[:, 0]) & (xs <= t[:, 1]) & (ys >= t[:, 2]) & (ys <= t[:, 3])
        planes = t[:, 4] + (xs - t[:, 0]) * t[:, 5]
        tops = np.where(inside, planes, -np.inf)
        best = np.argmax(tops, axis=1) if tops.shape[1] else np.zeros(len(x), dtype=int)
        found = inside.any(axis=1)
        return tops, np.where(found, best, -1)

    def height(self, x, y=0.0):
        """Ground height [m] under points (vectorised; a scalar for scalars)."""
        xs, ys = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        tops, index = self._heights(xs.ravel(), ys.ravel())
        heights = np.where(
            index >= 0, tops.max(axis=1) if tops.shape[1] else self.floor, self.floor
        )
        return float(heights[0]) if xs.ndim == 0 else heights.reshape(xs.shape)

    def surface_index(self, x: float, y: float) -> int:
        """Index in :attr:`surfaces` of the top under a point, -1 off the terrain."""
        return int(self._heights(np.array([float(x)]), np.array([float(y)]))[1][0])

    def normal(self, x: float, y: float) -> np.ndarray:
        """Unit normal of the ground under a point, shape (3,)."""
        index = self.surface_index(x, y)
        return self.surfaces[index].normal if index >= 0 else np.array([0.0, 0.0, 1.0])

    def surface_indices(self, x, y) -> np.ndarray:
        """Index in :attr:`surfaces` of the top under each point (-1: off the terrain), the
        shape of ``x`` (vectorised :meth:`surface_index`)."""
        xs, ys = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        return self._heights(xs.ravel(), ys.ravel())[1].reshape(xs.shape)

    def joined(self, first: int, second: int, max_kink: float) -> bool:
        """Whether surfaces ``first`` and ``second`` meet end to end along x, as wide and
        without a step, at an angle of at most ``max_kink`` [rad] (a sole may straddle
        their joint, :data:`~mpcwalk.terrain.fit.MAX_STRADDLED_KINK_DEG`)."""
        if not (0 <= first < len(self.surfaces) and 0 <= second < len(self.surfaces)):
            return False
        behind, ahead = sorted((self.surfaces[first], self.surfaces[second]), key=_x_min)
        return (
            first != second
            and abs(ahead.x_min - behind.x_max) <= 1e-9
            and abs(ahead.height - behind.end_height) <= 1e-9
            and (ahead.y_min, ahead.y_max) == (behind.y_min, behind.y_max)
            and abs(ahead.slope - behind.slope) <= max_kink + 1e-12
        )

    def sole_support(
        self,
        center,
        yaw: float,
        length: float,
        width: float,
        samples: int = 5,
        max_kink: float = 0.0,
    ) -> SoleSupport:
        """Where a sole of ``length`` x ``width`` [m], centred over ``center`` (x, y) [m] at
        heading ``yaw`` [rad], rests: on the highest top under it (sampled on a grid of
        ``samples`` x ``samples`` points), at its plane's height under the centre and tilted
        as that plane. Over the joint of that top and a neighbour :meth:`joined` to it
        within ``max_kink`` [rad], it rests on the ground's upper hull under it (both tops
        at a hollow, the brow and the top under its centre at a crest), and its margin counts
        the two tops as one."""
        c, s = math.cos(yaw), math.sin(yaw)
        u = np.linspace(-0.5, 0.5, samples)
        du, dv = np.meshgrid(u * length, u * width)
        px = center[0] + c * du.ravel() - s * dv.ravel()
        py = center[1] + s * du.ravel() + c * dv.ravel()
        tops, index = self._heights(px, py)
        if not tops.shape[1] or (index < 0).all():
            return SoleSupport(self.floor, 0.0, 0.0, -1, -math.inf)
        best = int(np.unravel_index(np.argmax(tops), tops.shape)[1])
        surface = self.surfaces[best]
        roll, pitch = sole_tilt(surface.normal, yaw)
        corners_x = (
            center[0]
            + c * 0.5 * length * np.array([1, 1, -1, -1])
            - s * 0.5 * width * np.array([1, -1, 1, -1])
        )
        corners_y = (
            center[1]
            + s * 0.5 * length * np.array([1, 1, -1, -1])
            + c * 0.5 * width * np.array([1, -1, 1, -1])
        )
        margin = float(self._coplanar_margin(best, corners_x, corners_y, max_kink))
        height = float(surface.height_at(center[0]))
        rest = self._straddled_rest(best, float(center[0]), corners_x, max_kink)
        if rest is not None:
            height, normal = rest
            roll, pitch = sole_tilt(normal, yaw)
        return SoleSupport(height, roll, pitch, best, margin)

    def _straddled_rest(
        self, index: int, x: float, corners_x: np.ndarray, max_kink: float
    ) -> tuple[float, np.ndarray] | None:
        """Height [m] at ``x`` and normal of a sole whose corners span ``corners_x`` [m]
        over the joint of surface ``index`` and a neighbour :meth:`joined` to it: the
        segment of the ground's upper hull (heel, joint, toe along x) under the centre.
        None when the sole lies over one top."""
        low, high = float(corners_x.min()), float(corners_x.max())
        for other in (index - 1, index + 1):
            if not self.joined(index, other, max_kink):
                continue
            behind, ahead = sorted((self.surfaces[index], self.surfaces[other]), key=_x_min)
            joint = behind.x_max
            if not low < joint < high:
                continue
            z_low, z_joint = float(behind.height_at(low)), float(behind.height_at(joint))
            z_high = float(ahead.height_at(high))
            chord = (z_high - z_low) / (high - low)
            if z_joint <= z_low + chord * (joint - low) + 1e-12:  # a hollow: on both tops
                rise, height = chord, z_low + chord * (x - low)
            else:  # a crest: on the brow and the top under the centre
                top = behind if x <= joint else ahead
                rise, height = math.tan(top.slope), float(top.height_at(x))
            angle = math.atan(rise)
            return height, np.array([-math.sin(angle), 0.0, math.cos(angle)])
        return None

    def _coplanar_margin(
        self, index: int, x: np.ndarray, y: np.ndarray, max_kink: float = 0.0
    ) -> float:
        """Smallest distance of the points to the edges of surface ``index``, counting as
        one surface the neighbours in its plane (a tread continued by a landing) and, with
        ``max_kink`` [rad], the neighbours :meth:`joined` to it."""
        surface = self.surfaces[index]
        # the neighbours joined within the kink extend its footprint along x (one box: a
        # point on the joint lies inside it, not on two edges)
        x_min, x_max = surface.x_min, surface.x_max
        for neighbour in (index - 1, index + 1):
            if max_kink > 0.0 and self.joined(index, neighbour, max_kink):
                x_min = min(x_min, self.surfaces[neighbour].x_min)
                x_max = max(x_max, self.surfaces[neighbour].x_max)
        distances = replace(surface, x_min=x_min, x_max=x_max).inner_distance(x, y)
        for other in self.surfaces:
            if other is surface or other.slope != surface.slope:
                continue
            if abs(other.height_at(surface.x_min) - surface.height) > 1e-9:
                continue
            distances = np.maximum(distances, other.inner_distance(x, y))
        return float(distances.min())

    def highest_along(self, start, end, half_width: float, step: float = 0.005) -> np.ndarray:
        """Ground heights [m] under the way from ``start`` to ``end`` (x, y) [m], swept by
        a sole ``2 half_width`` [m] wide across it, sampled every ``step`` [m]: shape (n,)
        for the n points of the way (the highest across its width)."""
        start, end = np.asarray(start, dtype=float)[:2], np.asarray(end, dtype=float)[:2]
        n = max(2, int(math.ceil(np.linalg.norm(end - start) / step)) + 1)
        points = start + np.linspace(0.0, 1.0, n)[:, None] * (end - start)
        direction = end - start
        norm = np.linalg.norm(direction)
        across = (
            np.array([-direction[1], direction[0]]) / norm if norm > 0 else np.array([0.0, 1.0])
        )
        offsets = np.linspace(-half_width, half_width, 5)
        swept = points[:, None, :] + offsets[None, :, None] * across
        return self.height(swept[..., 0], swept[..., 1]).max(axis=1)

    def profile(self, x) -> np.ndarray:
        """Ground heights [m] along the heading (y = 0) at ``x`` [m]."""
        return np.asarray(self.height(np.asarray(x, dtype=float), 0.0))

    def boxes(self) -> list[Box]:
        """The solids of the scene: one box per top above :attr:`floor`."""
        return [s.box(self.floor) for s in self.surfaces if s.top > self.floor + 1e-9]

    def __repr__(self) -> str:
        inner = ", ".join(repr(f) for f in self.features)
        return f"Terrain([{inner}], width={self.width:g})"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Terrain) and (self.features, self.width) == (
            other.features,
            other.width,
        )

    def __hash__(self) -> int:
        return hash((self.features, self.width))


FLAT = Terrain()
"""The level floor."""

__all__ = ["FLAT", "SoleSupport", "Terrain"]
