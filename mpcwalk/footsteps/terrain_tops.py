"""Where a sole can rest on a terrain: the places along a landing's heading that the footstep
planner tries (:class:`Place`), the top each rests on, and the feature that top belongs to.

A place *holds* the sole when the whole sole lies on one top with at least the reach's
tread margin from that top's edges (:meth:`~mpcwalk.terrain.Terrain.sole_support`'s
margin), on ground that is that top's plane everywhere under the sole and its margins (no
gap between two stones of the same height under it), neither in a pit nor on a slope
steeper than the soles stand on; or when the sole and its margins lie over two tops it
stands on that meet without a step at an angle the reach's ``max_kink_deg`` straddles (a
ramp's foot or brow), where it rests on the ground's upper hull, its centre out of
:data:`CREST_BAND` about a crest. On a rough patch the sole rests on the highest block under
it: every place there holds, and the ones wholly on one block are preferred
(:attr:`Place.wholly`). Beyond the laid ground, the floor (at
:attr:`~mpcwalk.terrain.Terrain.floor`) holds the sole where it is level under it.
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.terrain import RoughPatch, SoleSupport, Terrain, TerrainReach

#: Spacing [m] of the places tried along a landing's heading.
SEARCH_STEP = 0.005
#: Kinds of tops that hold one or two soles (a stair's tread, a stepping stone): the planner
#: puts one foot on each when the next one is within a stride.
NARROW_KINDS = ("tread", "stone")
#: Band [share of the sole length] about a crest's joint line where no sole centre is placed,
#: (behind, ahead) of the joint along x. A sole straddling a crest rests on the top under its
#: centre, pivoting on the crest, and its centre picks the side: a landing that falls short
#: of a centre planned just past the crest rests on the top behind it, pitched the other way
#: than planned, with the planned support beyond the crest in the air. Landings fall short
#: (compliant servos), so the band reaches further ahead than behind.
CREST_BAND = (0.05, 0.3)
#: Largest spacing [m] of the points a sole is checked at.
_SPACING = 0.01
_TOLERANCE = 1e-9

#: A top: ``("top", surface index)``, ``("rough", feature index)`` for all the blocks and
#: the ground of one rough patch, or ``("floor", -1)`` for the floor beyond the laid ground.
Top = tuple[str, int]


@dataclass(frozen=True)
class Place:
    """A place for a sole along a landing's heading.

    Attributes:
        offset: Distance [m] along the landing's heading from the nominal landing.
        center: Sole centre (x, y) [m].
        stride: Distance [m] of the sole centre ahead of the support foot's, in its frame.
        height: Height [m] of the sole centre resting there.
        top: The top it rests on (see :data:`Top`).
        holds: Whether the sole may land there (see the module's documentation).
        wholly: Whether the sole lies wholly on one top (on a rough patch: one block).
    """

    offset: float
    center: tuple[float, float]
    stride: float
    height: float
    top: Top
    holds: bool
    wholly: bool


class TerrainTops:
    """The places a sole of ``reach`` can rest on ``terrain``.

    Args:
        terrain: The ground.
        reach: The sole's size, its tread margin and the steepest slope it stands on.
    """

    def __init__(self, terrain: Terrain, reach: TerrainReach) -> None:
        self.terrain = terrain
        self.reach = reach
        self.margin = float(reach.tread_margin or 0.0)
        blocks = [f.block for f in terrain.features if isinstance(f, RoughPatch)]
        spacing = 0.5 * min(blocks) if blocks else reach.sole_length / 4.0
        self.samples = min(21, max(5, math.ceil(reach.sole_length / spacing) + 1))
        """Points across and along the sole :meth:`Terrain.sole_support` samples (every
        half block on a rough patch, so that the highest block under a sole is found)."""
        self._owners = [self._owner(surface) for surface in terrain.surfaces]

    def _owner(self, surface) -> int:
        """Index of the feature a surface belongs to, -1 for the ground between features."""
        for index, feature in enumerate(self.terrain.features):
            inside = feature.start - 1e-9 <= surface.x_min and surface.x_max <= feature.end + 1e-9
            if inside and surface.x_max > surface.x_min:
                return index
        return -1

    def top(self, surface: int) -> Top:
        """The top of surface ``surface`` (a rough patch's surfaces are one top; -1: the
        floor beyond the laid ground)."""
        if surface < 0:
            return ("floor", -1)
        owner = self._owners[surface]
        if owner >= 0 and isinstance(self.terrain.features[owner], RoughPatch):
            return ("rough", owner)
        return ("top", surface)

    def is_narrow(self, top: Top) -> bool:
        """Whether ``top`` is a tread or a stone (one or two feet on it)."""
        return top[0] == "top" and self.terrain.surfaces[top[1]].kind in NARROW_KINDS

    def describe(self, top: Top) -> str:
        """The feature ``top`` belongs to, in words (``"Stairs at 0.6 m"``)."""
        if top[0] == "floor":
            return f"the floor at {self.terrain.floor:g} m beyond the terrain"
        owner = top[1] if top[0] == "rough" else self._owners[top[1]]
        if owner < 0:
            surface = self.terrain.surfaces[top[1]]
            return f"the ground from {surface.x_min:.2f} to {surface.x_max:.2f} m"
        feature = self.terrain.features[owner]
        return f"{type(feature).__name__} at {feature.start:g} m"

    def rests_on(self, center, yaw: float) -> Top:
        """The top a sole centred at ``center`` (x, y) [m] with heading ``yaw`` rests on."""
        return self.places(np.asarray(center, dtype=float)[None, :2], yaw, [0.0], [0.0])[0].top

    def support(self, center, yaw: float) -> SoleSupport:
        """Where a sole centred at ``center`` (x, y) [m] with heading ``yaw`` [rad] rests."""
        return self.terrain.sole_support(
            center,
            yaw,
            self.reach.sole_length,
            self.reach.sole_width,
            self.samples,
            self.reach.max_kink,
        )

    def places(self, centers: np.ndarray, yaw: float, offsets, strides) -> list[Place]:
        """The places of soles centred at ``centers`` (n, 2) [m] with heading ``yaw``
        [rad], ``offsets`` [m] from their nominal landing and ``strides`` [m] ahead of the
        support foot. The ground under each sole grown by the tread margin is sampled at
        once: a sole on one plane there rests on that plane's top with the margin (the
        same test as :meth:`~mpcwalk.terrain.Terrain.sole_support`'s margin, gaps in one
        plane included); a sole elsewhere holds only on a rough patch."""
        centers = np.asarray(centers, dtype=float).reshape(-1, 2)
        grow = max(self.margin - 1e-6, 0.0)
        length, width = self.reach.sole_length + 2 * grow, self.reach.sole_width + 2 * grow
        along = np.linspace(-0.5, 0.5, max(3, math.ceil(length / (0.5 * _SPACING)) + 1))
        du, dv = (a.ravel() for a in np.meshgrid(along * length, np.linspace(-0.5, 0.5, 5) * width))
        c, s = math.cos(yaw), math.sin(yaw)
        x = centers[:, :1] + c * du - s * dv
        y = centers[:, 1:] + s * du + c * dv
        heights = np.asarray(self.terrain.height(x, y))
        # one plane along x under the whole grown sole (the terrain's tops tilt along x)
        dx = x - x.mean(axis=1, keepdims=True)
        dh = heights - heights.mean(axis=1, keepdims=True)
        spread = (dx**2).sum(axis=1)
        slope = np.where(spread > 1e-12, (dx * dh).sum(axis=1) / np.maximum(spread, 1e-12), 0.0)
        residual = np.abs(dh - slope[:, None] * dx).max(axis=1)
        planar = np.isfinite(heights).all(axis=1) & (residual <= 1e-6)
        level = heights.mean(axis=1) + slope * (centers[:, 0] - x.mean(axis=1))
        rough = self._over_rough(x, y)
        out = []
        for i, center in enumerate(centers):
            if rough[i]:
                support = self.support(center, yaw)
                top = self.top(support.surface)
                if top[0] == "rough":
                    out.append(
                        Place(
                            offsets[i],
                            tuple(center),
                            strides[i],
                            support.height,
                            top,
                            True,
                            support.margin >= -_TOLERANCE,
                        )
                    )
                    continue
            surface = self.terrain.surface_index(center[0], center[1])
            holds = bool(planar[i]) and (surface < 0 or self._stands_on(surface))
            straddled = None if planar[i] else self._straddled(x[i], y[i])
            if straddled is not None:
                # over the joint of two tops it may straddle: it rests on both, or, at a
                # crest, on the top its centre is over, away from the joint line
                top = self.top(surface)
                height = self.support(center, yaw).height
                clear = not self._near_crest(straddled, float(center[0]))
                out.append(Place(offsets[i], tuple(center), strides[i], height, top, clear, clear))
                continue
            if (
                holds
                and surface >= 0
                and not self.terrain.surfaces[surface].contains(x[i], y[i]).all()
            ):
                # over the joint of two tops in one plane: the margin to the tops' edges
                holds = self.support(center, yaw).margin >= self.margin - _TOLERANCE
            top = self.top(surface)
            place = Place(offsets[i], tuple(center), strides[i], level[i], top, holds, holds)
            out.append(place)
        return out

    def _near_crest(self, tops: tuple[int, int], center_x: float) -> bool:
        """Whether a sole centred at ``center_x`` [m] over the joined ``tops`` straddles a
        crest with its centre in :data:`CREST_BAND` about the joint."""
        behind, ahead = sorted(
            (self.terrain.surfaces[t] for t in tops), key=lambda surface: surface.x_min
        )
        if ahead.slope >= behind.slope:  # a hollow: the sole rests on both tops
            return False
        back, front = (share * self.reach.sole_length for share in CREST_BAND)
        return behind.x_max - back < center_x < behind.x_max + front

    def _straddled(self, x: np.ndarray, y: np.ndarray) -> tuple[int, int] | None:
        """The two tops the points of a grown sole lie over when it may straddle their
        joint (both stood on, :meth:`~mpcwalk.terrain.Terrain.joined` within the reach's
        kink), else None."""
        tops = np.unique(self.terrain.surface_indices(x, y))
        if len(tops) != 2 or tops[0] < 0 or self.reach.max_kink <= 0.0:
            return None
        pair = (int(tops[0]), int(tops[1]))
        joined = self.terrain.joined(*pair, self.reach.max_kink)
        return pair if joined and all(self._stands_on(top) for top in pair) else None

    def _stands_on(self, surface: int) -> bool:
        """Whether a sole may stand on surface ``surface`` (not a pit, not too steep)."""
        top = self.terrain.surfaces[surface]
        steep = abs(top.slope) > math.radians(self.reach.max_slope_deg) + _TOLERANCE
        return top.kind != "pit" and not steep

    def _over_rough(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Whether any point of each row lies over a rough patch."""
        out = np.zeros(x.shape[0], dtype=bool)
        for feature in self.terrain.features:
            if isinstance(feature, RoughPatch):
                half = 0.5 * feature.width
                inside = (x >= feature.start) & (x <= feature.end) & (np.abs(y) <= half)
                out |= inside.any(axis=1)
        return out


__all__ = ["NARROW_KINDS", "SEARCH_STEP", "Place", "TerrainTops", "Top"]
