"""Convex support polygons as half-plane inequalities ``A p <= b``."""

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Vertices of the convex hull of 2D points, counter-clockwise.

    Andrew's monotone chain; collinear points are dropped.

    Args:
        points: Shape (n, 2).

    Returns:
        Hull vertices, shape (k, 2), counter-clockwise, k >= 3 for points in
        general position.
    """
    array = np.asarray(points, dtype=float).reshape(-1, 2)
    # the distinct points in lexicographic order (as np.unique(axis=0)), as Python floats:
    # the chain below runs on a handful of points, where numpy scalars cost more than the
    # arithmetic (the same IEEE operations, so the same hull)
    pts = sorted(set(map(tuple, array.tolist())))
    if len(pts) < 3:
        return np.array(pts, dtype=float).reshape(-1, 2)

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 1e-15:
            lower.pop()
        lower.append(p)
    upper: list = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 1e-15:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1])


def _next_rows(rows: np.ndarray) -> np.ndarray:
    """``np.roll(rows, -1, axis=0)``: row ``i + 1`` at ``i``, the first row last."""
    return np.concatenate((rows[1:], rows[:1]))


@dataclass(frozen=True)
class SupportPolygon:
    """Convex polygon on the ground.

    Attributes:
        vertices: Counter-clockwise vertices, shape (k, 2), in [m].
        A: Outward unit normals of the edges, shape (k, 2).
        b: Offsets, shape (k,), so that the polygon is ``{p : A p <= b}`` and
            ``b - A p`` is the distance of ``p`` to each edge line, in [m].
    """

    vertices: np.ndarray
    A: np.ndarray
    b: np.ndarray

    @staticmethod
    def from_vertices(vertices: np.ndarray) -> "SupportPolygon":
        """Build from the vertices of a convex polygon (any order)."""
        hull = convex_hull(vertices)
        if len(hull) < 3:
            raise ConfigurationError(
                f"A support polygon needs at least 3 non-collinear vertices, got "
                f"{len(hull)} distinct ones: {np.asarray(vertices).tolist()}."
            )
        edges = _next_rows(hull) - hull
        normals = np.stack([edges[:, 1], -edges[:, 0]], axis=1)
        normals /= np.sqrt(np.add.reduce(normals * normals, axis=1, keepdims=True))  # norm
        b = np.einsum("ij,ij->i", normals, hull)
        return SupportPolygon(vertices=hull, A=normals, b=b)

    @staticmethod
    def union_hull(polygons: Iterable["SupportPolygon"]) -> "SupportPolygon":
        """Convex hull of several polygons (double support: both feet)."""
        return SupportPolygon.from_vertices(np.vstack([poly.vertices for poly in polygons]))

    @property
    def centroid(self) -> np.ndarray:
        """Area centroid, shape (2,), in [m]."""
        v, w = self.vertices, _next_rows(self.vertices)
        cross = v[:, 0] * w[:, 1] - w[:, 0] * v[:, 1]
        area = 0.5 * cross.sum()
        return ((v + w) * cross[:, None]).sum(axis=0) / (6.0 * area)

    def shrink(self, margin: float) -> "SupportPolygon":
        """Polygon with every edge moved inwards by ``margin`` [m] (same normals)."""
        return SupportPolygon(vertices=self.vertices, A=self.A, b=self.b - margin)

    def contains(self, points: np.ndarray, margin: float = 0.0) -> bool | np.ndarray:
        """Whether points, shape (..., 2), lie inside with at least ``margin``."""
        return self.signed_distance(points) >= margin

    def signed_distance(self, points: np.ndarray) -> float | np.ndarray:
        """Signed Euclidean distance to the boundary, positive inside, in [m].

        Args:
            points: Shape (2,) or (n, 2).

        Returns:
            Scalar or shape (n,).
        """
        pts = np.asarray(points, dtype=float)
        single = pts.ndim == 1
        pts = pts.reshape(-1, 2)
        inner = (self.b[None, :] - pts @ self.A.T).min(axis=1)
        # Outside: exact distance to the nearest edge segment.
        a = self.vertices[None, :, :]
        ab = _next_rows(self.vertices)[None, :, :] - a
        ap = pts[:, None, :] - a
        s = np.clip((ap * ab).sum(-1) / (ab * ab).sum(-1), 0.0, 1.0)
        closest = a + s[..., None] * ab
        outer = np.linalg.norm(pts[:, None, :] - closest, axis=-1).min(axis=1)
        dist = np.where(inner >= 0.0, inner, -outer)
        return float(dist[0]) if single else dist

    def padded_halfplanes(self, nb_rows: int, slack: float = 10.0):
        """Half-planes padded to a fixed row count for fixed QP structure.

        Extra rows repeat the first normal with its offset raised by ``slack``
        [m], so they never bind and never duplicate an active constraint.

        Returns:
            ``(A, b)`` of shapes (nb_rows, 2) and (nb_rows,).
        """
        k = len(self.b)
        if k > nb_rows:
            raise ConfigurationError(
                f"Polygon has {k} edges, more than the {nb_rows} rows reserved."
            )
        A = np.vstack([self.A, np.repeat(self.A[:1], nb_rows - k, axis=0)])
        return A, self.padded_offsets(nb_rows, slack)

    def padded_offsets(self, nb_rows: int, slack: float = 10.0) -> np.ndarray:
        """The offsets ``b`` of :meth:`padded_halfplanes` alone, shape (nb_rows,) (its
        normals depend on the edges' directions only: a translated polygon shares them)."""
        k = len(self.b)
        return np.concatenate([self.b, np.repeat(self.b[:1] + slack, nb_rows - k)])


def foot_rectangle(
    center: Sequence[float] | np.ndarray, yaw: float, length: float, width: float
) -> SupportPolygon:
    """Rectangle of a flat foot sole.

    Args:
        center: Sole centre (x, y) in the world, in [m] (a z is ignored).
        yaw: Foot heading, in [rad].
        length: Sole length along the foot x axis, in [m].
        width: Sole width along the foot y axis, in [m].
    """
    if not (length > 0.0 and width > 0.0):
        raise ConfigurationError(
            f"Foot length and width must be positive, got {length!r} x {width!r} m."
        )
    c, s = np.cos(yaw), np.sin(yaw)
    R = np.array([[c, -s], [s, c]])
    half = 0.5 * np.array([[length, width], [-length, width], [-length, -width], [length, -width]])
    vertices = np.asarray(center, dtype=float)[:2] + half @ R.T
    return SupportPolygon.from_vertices(vertices)


def sole_footprint(
    center: Sequence[float] | np.ndarray, rotation: np.ndarray, length: float, width: float
) -> SupportPolygon:
    """Horizontal projection of a rectangular sole, flat or tilted.

    Args:
        center: Sole centre (x, y) in the world, in [m] (a z is ignored).
        rotation: Orientation of the sole in the world, shape (3, 3) (its x axis along the
            length, its z axis the sole's normal).
        length: Sole length along the sole's x axis, in [m].
        width: Sole width along the sole's y axis, in [m].
    """
    if not (length > 0.0 and width > 0.0):
        raise ConfigurationError(
            f"Foot length and width must be positive, got {length!r} x {width!r} m."
        )
    half = 0.5 * np.array([[length, width], [-length, width], [-length, -width], [length, -width]])
    planar = np.asarray(rotation, dtype=float)[:2, :2]  # sole x, y -> horizontal x, y
    vertices = np.asarray(center, dtype=float)[:2] + half @ planar.T
    return SupportPolygon.from_vertices(vertices)
