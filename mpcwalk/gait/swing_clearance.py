"""Swing feet that clear the terrain: rise first, travel, then lower onto the tread.

Paper M's swing (:class:`~mpcwalk.gait.swing_foot.SwingFootTrajectory`) lifts the foot
``z_step`` above the straight line from the lift-off height to the landing height while it
moves: over a level floor nothing is in its way, but the toe of a foot climbing onto a stair
meets the nose of the step. On a terrain, every swing whose sole sweeps over ground higher
than the lower of its two footholds (a riser, a nose, a ramp, a block; outside both
footprints, :mod:`~mpcwalk.gait.sole_clearance`) takes a shaped profile instead
(:class:`SwingShape`), over the single support's share ``s`` in [0, 1]:

- the foot rises from its lift-off height to an apex ``H``: the highest ground under the
  sole swept along its way (tilted as it will be) plus the clearance and
  :data:`CHECK_MARGIN` (and at least ``z_step`` above the higher foothold), on a quintic
  rest-to-rest law over ``[0, s_up]``;
- it travels from its lift-off pose to its landing pose, on the same law over
  ``[s_0, s_1]``;
- it lowers onto the landing over ``[s_down, 1]``.

The three durations are shared out so that the three motions have the same peak
acceleration (each lasts as the square root of its distance). Travel overlaps the rise and
the lowering as far as the clearance allows: the largest overlap of :data:`OVERLAPS` whose
swing keeps every checked point of the sole at least the clearance above the terrain
(sampled :data:`CHECK_SAMPLES` times, with half of :data:`CHECK_MARGIN` to spare) is kept;
without overlap (the foot rises straight up, travels at the apex, then lowers straight
down) the clearance always holds. A swing over ground no higher than its lower foothold
keeps paper M's profile: a flat walk is unchanged. So does a swing, up or down, whose
ground stays under paper M's sole by at least :data:`CLEARANCE_KEPT` of that sole's own
lift (``4 h (1 - h) z_step`` above the straight line between the footholds when it is
``h`` of the way along), give or take :data:`LINE_TOLERANCE`: an even ramp, its foot and
its brow. Paper M's profile rises ``z_step`` above that line as above the floor, while the
shaped one, which lowers last, dropped the foot by up to ``z_step`` plus the step's drop in
its last tenth of a second, and the compliant leg, stretched to reach, lagged: g1 landed
1.34 cm short of each stride up a 3 deg ramp with it (paper M's: 0.49 cm; 0.39 cm on the
floor tilted 3 deg up, the same slope without a terrain), on the simulator's ground truth;
atlas-like's swing over a 5 deg ramp's brow landed 6.2 cm short (paper M's: 1.8 cm), and
it fell at the next brow, where with paper M's swing it walks the ramp up and down.
Risers, noses and blocks keep the shaped profile.
"""

import math
from dataclasses import dataclass, replace

import numpy as np

from mpcwalk.footsteps.footstep import FootGeometry, Footstep
from mpcwalk.gait.sole_clearance import foot_tilt, sole_gaps, sole_points, swing_pose
from mpcwalk.terrain import Terrain

#: Least clearance [m] of a swing sole above the terrain.
MIN_CLEARANCE = 0.01
#: Shares of the rise and of the lowering the travel may overlap, tried in this order.
OVERLAPS = (1.0, 0.8, 0.6, 0.4, 0.2)
#: Share of the clearance an overlapping swing keeps (the apex keeps all of it).
CLEARANCE_KEPT = 0.5
#: Instants of a swing at which a shape's clearance is checked.
CHECK_SAMPLES = 301
#: Height [m] the apex adds to the clearance; an overlapping swing keeps half of it at its
#: checked instants (what it may lose between them).
CHECK_MARGIN = 0.001
#: Drop [m] from which a swing is a step down: it lowers only once its travel has ended.
STEP_DOWN_MIN = 0.005
#: Height [m] the ground under a swing's way may rise above the straight line between its
#: footholds (an even ramp), besides the share of paper M's lift, for a swing to keep paper
#: M's profile.
LINE_TOLERANCE = 0.002
#: Positions along a swing's way at which the ground under the swept sole is sampled.
_SWEEP_SAMPLES = 101


def rest_to_rest(x: float) -> tuple[float, float]:
    """Rest-to-rest law ``10 x^3 - 15 x^4 + 6 x^5`` on [0, 1] (clipped) and its
    derivative."""
    x = min(max(x, 0.0), 1.0)
    return x**3 * (10.0 - 15.0 * x + 6.0 * x**2), 30.0 * x**2 * (1.0 - x) ** 2


def steps_down(lift: Footstep, landing: Footstep) -> bool:
    """Whether the swing from ``lift`` to ``landing`` goes down by :data:`STEP_DOWN_MIN`
    or more."""
    return float(landing.position[2]) < float(lift.position[2]) - STEP_DOWN_MIN


@dataclass(frozen=True)
class SwingShape:
    """A swing that rises, travels and lowers (see the module's documentation).

    Attributes:
        lift_height: Height [m] of the sole at lift-off.
        apex: Height [m] the sole rises to.
        landing_height: Height [m] of the sole at touch-down.
        rise_end: Share ``s_up`` of the single support when the rise ends.
        lower_start: Share ``s_down`` of the single support when the lowering starts.
        travel_start: Share ``s_0`` when the horizontal travel starts.
        travel_end: Share ``s_1`` when it ends.
    """

    lift_height: float
    apex: float
    landing_height: float
    rise_end: float
    lower_start: float
    travel_start: float
    travel_end: float

    def at(self, s: float) -> tuple[float, float, float, float]:
        """Share ``h`` of the way, its derivative, the height ``z`` [m] and its derivative
        [m] with respect to the share ``s`` of the single support."""
        span = self.travel_end - self.travel_start
        if span > 0.0:
            h, dh = rest_to_rest((s - self.travel_start) / span)
            dh /= span
        else:  # no way to travel
            h, dh = (0.0 if s < self.travel_start else 1.0), 0.0
        if s <= self.rise_end:
            r, dr = rest_to_rest(s / self.rise_end) if self.rise_end > 0.0 else (1.0, 0.0)
            rise = self.apex - self.lift_height
            z, dz = self.lift_height + rise * r, rise * dr / max(self.rise_end, 1e-12)
        elif s >= self.lower_start:
            width = 1.0 - self.lower_start
            r, dr = rest_to_rest((s - self.lower_start) / width) if width > 0.0 else (1.0, 0.0)
            drop = self.landing_height - self.apex
            z, dz = self.apex + drop * r, drop * dr / max(width, 1e-12)
        else:
            z, dz = self.apex, 0.0
        return h, dh, z, dz


class SwingClearance:
    """The shaped swings of a walk over a terrain.

    Args:
        terrain: The ground.
        foot: The sole's size.
        step_height: Paper M's ``z_step`` [m]: the least rise above the higher foothold.
        clearance: Least height [m] of the sole above the terrain under it, out of the
            footprints (default: ``step_height``, at least :data:`MIN_CLEARANCE`).
    """

    def __init__(
        self,
        terrain: Terrain,
        foot: FootGeometry,
        step_height: float,
        clearance: float | None = None,
    ) -> None:
        self.terrain = terrain
        self.foot = foot
        self.step_height = float(step_height)
        self.clearance = max(
            float(clearance) if clearance is not None else self.step_height, MIN_CLEARANCE
        )
        self._shapes: dict[tuple, SwingShape | None] = {}

    def shape(self, lift: Footstep, landing: Footstep) -> SwingShape | None:
        """The shaped swing from ``lift`` to ``landing``, or None when paper M's profile
        clears the terrain (nothing under the way higher than the lower foothold)."""
        key = (
            lift.position.tobytes(),
            lift.yaw,
            foot_tilt(lift),
            landing.position.tobytes(),
            landing.yaw,
            foot_tilt(landing),
        )
        if key not in self._shapes:
            self._shapes[key] = self._shape(lift, landing)
        return self._shapes[key]

    def interpolants(
        self, lift: Footstep, landing: Footstep, s: float, duration: float
    ) -> tuple[float, float, float, float] | None:
        """``h``, ``dh/dt``, ``z`` [m] and ``dz/dt`` [m/s] of the shaped swing at the share
        ``s`` of a single support lasting ``duration`` [s], or None (paper M's profile)."""
        shape = self.shape(lift, landing)
        if shape is None:
            return None
        h, dh, z, dz = shape.at(s)
        return h, dh / duration, z, dz / duration

    def _shape(self, lift: Footstep, landing: Footstep) -> SwingShape | None:
        length, width = self.foot.length, self.foot.width
        low, high = sorted((float(lift.position[2]), float(landing.position[2])))
        u, v = np.meshgrid(np.linspace(-1.0, 1.0, 9), np.linspace(-1.0, 1.0, 5))
        grid = np.stack([u.ravel(), v.ravel()], axis=1)
        points = []
        for h in np.linspace(0.0, 1.0, _SWEEP_SAMPLES):  # the whole sole along the way
            xy, yaw, roll, pitch = swing_pose(lift, landing, float(h))
            points.append(sole_points((*xy, 0.0), yaw, length, width, roll, pitch, grid))
        # the height of the sole's centre that puts every point on the ground under it
        gaps, exempt = sole_gaps(self.terrain, np.array(points), lift, landing, length, width)
        obstacle = float(-gaps[~exempt].min()) if (~exempt).any() else -math.inf
        if obstacle <= low + 1e-9:
            return None
        if _on_the_way(gaps, exempt, lift, landing, self.step_height):
            return None  # along a ramp: paper M's profile rises above it as on the floor
        apex = max(obstacle + self.clearance + CHECK_MARGIN, high + self.step_height)
        rise = math.sqrt(apex - float(lift.position[2]))
        travel = math.sqrt(float(np.linalg.norm(landing.xy - lift.xy)))
        lower = math.sqrt(apex - float(landing.position[2]))
        total = rise + travel + lower
        rise_end, lower_start = rise / total, 1.0 - lower / total

        def shaped(rise_overlap: float, lower_overlap: float) -> SwingShape:
            return SwingShape(
                float(lift.position[2]),
                apex,
                float(landing.position[2]),
                rise_end,
                lower_start,
                rise_end * (1.0 - rise_overlap),
                lower_start + (1.0 - lower_start) * lower_overlap,
            )

        # the largest overlap of the rise, then of the lowering, that keeps the clearance;
        # without overlap the sole rises and lowers over its footprints: clear by construction
        rise_overlap = next(
            (o for o in OVERLAPS if self._clears(shaped(o, 0.0), lift, landing)), 0.0
        )
        lower_overlap = (
            0.0
            if steps_down(lift, landing)
            else next(
                (o for o in OVERLAPS if self._clears(shaped(rise_overlap, o), lift, landing)),
                0.0,
            )
        )
        return shaped(rise_overlap, lower_overlap)

    def _clears(self, shape: SwingShape, lift: Footstep, landing: Footstep) -> bool:
        """Whether every checked point of the sole out of the footprints stays the
        clearance above the terrain over the shaped swing."""
        length, width = self.foot.length, self.foot.width
        points = []
        for s in np.linspace(0.0, 1.0, CHECK_SAMPLES):
            h, _, z, _ = shape.at(float(s))
            xy, yaw, roll, pitch = swing_pose(lift, landing, h)
            points.append(sole_points((*xy, z), yaw, length, width, roll, pitch))
        gaps, exempt = sole_gaps(self.terrain, np.array(points), lift, landing, length, width)
        checked = gaps[~exempt]
        return bool(
            checked.size == 0
            or checked.min() >= CLEARANCE_KEPT * self.clearance + 0.5 * CHECK_MARGIN
        )


def _on_the_way(
    gaps: np.ndarray,
    exempt: np.ndarray,
    lift: Footstep,
    landing: Footstep,
    step_height: float,
) -> bool:
    """Whether the ground under the swept sole (``gaps``: the points' heights above it at
    z = 0, one row per sample ``h`` of the way) stays within :data:`LINE_TOLERANCE` of the
    straight line from the lift-off height to the landing height, plus the share
    ``1 - CLEARANCE_KEPT`` of paper M's lift: paper M's sole is ``4 h (1 - h)
    step_height`` above that line when it is ``h`` of the way along (eq. 21-23 give
    ``v = 4 h (1 - h)``), and keeps :data:`CLEARANCE_KEPT` of it over the ground."""
    along = np.linspace(0.0, 1.0, gaps.shape[0])[:, None]
    line = (1.0 - along) * float(lift.position[2]) + along * float(landing.position[2])
    excess = np.where(exempt, -np.inf, -gaps - line)
    lifted = (1.0 - CLEARANCE_KEPT) * 4.0 * along * (1.0 - along) * step_height
    return bool((excess <= LINE_TOLERANCE + lifted).all())


def with_height(state, z: float, dz: float):
    """``state`` (a foot state) at the height ``z`` [m] rising at ``dz`` [m/s]."""
    position = np.array(state.position, dtype=float)
    velocity = np.array(state.linear_velocity, dtype=float)
    position[2], velocity[2] = z, dz
    position.setflags(write=False)
    velocity.setflags(write=False)
    return replace(state, position=position, linear_velocity=velocity)


__all__ = [
    "CHECK_MARGIN",
    "CHECK_SAMPLES",
    "MIN_CLEARANCE",
    "OVERLAPS",
    "SwingClearance",
    "SwingShape",
    "rest_to_rest",
    "steps_down",
    "with_height",
]
