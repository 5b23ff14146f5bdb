"""The support polygons of a contact schedule, built once per pose and shape.

:class:`~mpcwalk.gait.contact_schedule.ContactSchedule` asks :class:`SupportPolygons` for the
polygon of each foot (a sole) and each pair of feet (the hull of two soles) of its phases,
and their half-planes padded to :data:`MAX_POLYGON_EDGES` rows. Each is built once:

- by pose (:func:`pose_key`): a schedule built with ``reuse`` takes the polygons of the
  poses the reused schedule had (a publication of the footstep MPC moves a few landings);
- by shape: a polygon is its shape (the angles of the feet, and the offset between the two
  feet of a hull) built at the origin and translated, so a footstep moved without turning
  costs a translation; the shapes, and the padded normals of a shape, are shared along a
  chain of reuses.
"""

from typing import Optional

import numpy as np

from mpcwalk.footsteps.footstep import FootGeometry, Footstep, Side
from mpcwalk.models.support_polygon import SupportPolygon, foot_rectangle, sole_footprint

#: Half-plane rows reserved per sample: a double-support hull of two
#: rectangles has at most 8 edges.
MAX_POLYGON_EDGES = 8


def pose_key(foot: Footstep) -> tuple:
    """What a foot's polygon depends on: (x, y, yaw), and the roll and pitch of a tilted
    foot (its polygon is the sole's horizontal projection; the height does not count)."""
    key = (float(foot.position[0]), float(foot.position[1]), float(foot.yaw))
    return key if foot.is_flat else (*key, foot.roll, foot.pitch)


def shape_key(foot: Footstep) -> tuple:
    """What a foot's polygon at the origin depends on: its yaw, roll and pitch."""
    yaw = float(foot.yaw)
    return (yaw,) if foot.is_flat else (yaw, foot.roll, foot.pitch)


class SupportPolygons:
    """The polygons of a schedule's feet and pairs of feet, and their padded half-planes.

    Args:
        foot: The sole's size.
        reuse: The polygons of another schedule with the same sole, taken for the poses it
            had (see the module's documentation); None: none.
    """

    def __init__(self, foot: FootGeometry, reuse: Optional["SupportPolygons"] = None) -> None:
        self.foot = foot
        # polygons by foot pose (and pair of poses for a hull), and their padded half-planes
        self.polygons: dict[tuple, SupportPolygon] = {}
        self.padded: dict[tuple, tuple] = {}
        reused = reuse if reuse is not None and reuse.foot == foot else None
        self._reused_polygons = reused.polygons if reused is not None else {}
        self._reused_padded = reused.padded if reused is not None else {}
        # polygons at the origin by shape (yaws, and the second foot's offset)
        self._shapes: dict[tuple, SupportPolygon] = reused._shapes if reused is not None else {}
        # padded normals by normals array (its id, and the array kept so that the id stays
        # its own): the polygons of a shape share them
        self._padded_normals: dict[int, tuple[np.ndarray, np.ndarray]] = (
            reused._padded_normals if reused is not None else {}
        )

    def forget_reused(self) -> None:
        """Drop the reused schedule's polygons by pose (the schedule is built: a chain of
        reuses keeps only the shapes)."""
        self._reused_polygons, self._reused_padded = {}, {}

    def keep(self, key: tuple, polygon: SupportPolygon) -> None:
        """Hold ``polygon`` (of a phase kept from the reused schedule) for the pose ``key``,
        and its padded half-planes when the reused schedule had them."""
        self.polygons.setdefault(key, polygon)
        padded = self._reused_padded.get(key)
        if padded is not None:
            self.padded.setdefault(key, padded)

    def footprint(self, offset, foot: Footstep) -> SupportPolygon:
        """The sole of ``foot`` centred at ``offset`` (x, y) [m], projected on the ground."""
        length, width = self.foot.length, self.foot.width
        if foot.is_flat:
            return foot_rectangle(offset, float(foot.yaw), length, width)
        return sole_footprint(offset, foot.rotation_matrix, length, width)

    def polygon(self, key: tuple, build) -> SupportPolygon:
        """The polygon of the pose ``key``: held, the reused schedule's, or ``build()``."""
        poly = self.polygons.get(key)
        if poly is None:
            poly = self._reused_polygons.get(key)
            self.polygons[key] = poly = build() if poly is None else poly
        return poly

    def padded_halfplanes(self, key: tuple, polygon: SupportPolygon):
        """``polygon.padded_halfplanes(MAX_POLYGON_EDGES)`` of the pose ``key``, made once."""
        padded = self.padded.get(key)
        if padded is None:
            padded = self._reused_padded.get(key)
            if padded is None:
                padded = self._pad(polygon)
            self.padded[key] = padded
        return padded

    def _pad(self, polygon: SupportPolygon) -> tuple[np.ndarray, np.ndarray]:
        """``polygon.padded_halfplanes(MAX_POLYGON_EDGES)``, its padded normals made once
        per normals array: the polygons of a shape translated share their shape's."""
        entry = self._padded_normals.get(id(polygon.A))
        if entry is None or entry[0] is not polygon.A:
            A, b = polygon.padded_halfplanes(MAX_POLYGON_EDGES)
            self._padded_normals[id(polygon.A)] = (polygon.A, A)
            return A, b
        return entry[1], polygon.padded_offsets(MAX_POLYGON_EDGES)

    def rect(self, foot: Footstep) -> SupportPolygon:
        """The sole of ``foot``."""
        return self.polygon(
            pose_key(foot),
            lambda: self._translated(
                shape_key(foot), foot.xy, lambda: self.footprint((0.0, 0.0), foot)
            ),
        )

    def hull(self, feet: dict[Side, Footstep]) -> SupportPolygon:
        """Support polygon of both feet: the hull of their footprints, built at the origin
        once per shape (the angles of the feet and the offset between them, to 1e-12 m)."""
        first, second = feet.values()
        offset = second.xy - first.xy
        shape = (
            shape_key(first),
            shape_key(second),
            round(float(offset[0]), 12),
            round(float(offset[1]), 12),
        )

        def local() -> SupportPolygon:
            # each sole at the origin is its shape's (rect), when made already; the second
            # one's corners moved by the offset are the corners of its footprint there (the
            # same sums), and the hull depends on the set of corners only
            sole, other = self._shapes.get(shape_key(first)), self._shapes.get(shape_key(second))
            if sole is None:
                sole = self.footprint((0.0, 0.0), first)
            if other is None:
                other = self.footprint((0.0, 0.0), second)
            corners = np.vstack((sole.vertices, other.vertices + offset))
            return SupportPolygon.from_vertices(corners)

        return self._translated(shape, first.xy, local)

    def _translated(self, shape: tuple, position: np.ndarray, build) -> SupportPolygon:
        """The polygon of ``shape`` (built at the origin by ``build`` the first time) moved to
        ``position`` (x, y) [m]."""
        polygon = self._shapes.get(shape)
        if polygon is None:
            polygon = self._shapes[shape] = build()
        xy = np.asarray(position, dtype=float)[:2]
        return SupportPolygon(polygon.vertices + xy, polygon.A, polygon.b + polygon.A @ xy)


__all__ = ["MAX_POLYGON_EDGES", "SupportPolygons", "pose_key", "shape_key"]
