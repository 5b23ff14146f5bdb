"""Where each planned landing may move: the band of the top it was placed on.

A footstep-adaptive MPC moves the landings of a plan (a push, the velocity cost). On a
terrain a landing moved off its tread puts the heel on a nose or the toe against a riser,
with the footstep's height still the tread's. :func:`tread_bands` gives every landing of a
plan placed on a terrain (:mod:`~mpcwalk.footsteps.terrain_steps`) the box of sole centres
that keep the whole sole on the top it rests on, with the placer's tread margin: the top's
footprint (axis-aligned along the terrain's heading, the world x axis) with its contiguous
neighbours in the same plane (a last tread continued by a landing), shrunk on each side by
the sole's half extent along that axis at the landing's yaw plus ``reach.tread_margin``.
A step down (a landing lower than its swing foot's lift-off) also keeps the placer's room
behind the heel (:data:`~mpcwalk.footsteps.terrain_steps.DESCENT_HEEL_ROOM`): a swing foot
falling short of its target must not put its heel on the nose it steps down from.
The bands are numbers (:class:`LandingBands`), known when the plan is made: linear bounds
of the footstep QP (:class:`~mpcwalk.qp.footstep_supports.StepVariables`).

A landing off the laid tops (the floor beyond the terrain, a rough patch, whose blocks the
sole may straddle) has no band (infinite bounds). A band always holds its planned landing:
a landing the placer put closer to an edge than the margin widens its band to itself.
"""

from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import FootstepPlan
from mpcwalk.footsteps.terrain_steps import DESCENT_HEEL_ROOM, DESCENT_MIN
from mpcwalk.footsteps.terrain_tops import TerrainTops
from mpcwalk.terrain import Terrain, TerrainReach


@dataclass(frozen=True)
class LandingBands:
    """Per landing of a plan, the box its sole centre stays in (world x, y).

    Attributes:
        lower: Smallest x and y of each landing's sole centre, shape (nb_steps, 2), in [m]
            (``-inf``: unbounded).
        upper: Largest x and y, shape (nb_steps, 2), in [m] (``inf``: unbounded).

    Raises:
        ConfigurationError: Shapes that differ or are not (n, 2), NaN, or a lower bound
            above its upper bound.
    """

    lower: np.ndarray
    upper: np.ndarray

    def __post_init__(self) -> None:
        lower = np.array(self.lower, dtype=float)
        upper = np.array(self.upper, dtype=float)
        if lower.ndim != 2 or lower.shape[1] != 2 or lower.shape != upper.shape:
            raise ConfigurationError(
                "LandingBands.lower and .upper must both have shape (nb_steps, 2) (x, y per "
                f"landing), got {lower.shape} and {upper.shape}."
            )
        if np.isnan(lower).any() or np.isnan(upper).any() or (lower > upper).any():
            raise ConfigurationError(
                "LandingBands need lower <= upper per landing and axis, without NaN (use "
                "-inf and inf for an unbounded axis); got lower "
                f"{lower.tolist()} and upper {upper.tolist()}."
            )
        object.__setattr__(self, "lower", lower)
        object.__setattr__(self, "upper", upper)

    def __len__(self) -> int:
        return len(self.lower)

    def clip(self, steps: np.ndarray, xy: np.ndarray) -> np.ndarray:
        """Positions ``xy`` (n, 2) [m] of landings ``steps`` (n,) moved into their bands."""
        return np.minimum(np.maximum(xy, self.lower[steps]), self.upper[steps])


def _footprint(terrain: Terrain, index: int) -> tuple[float, float, float, float]:
    """``(x_min, x_max, y_min, y_max)`` [m] of surface ``index`` with the contiguous
    surfaces in its plane and of its width, ahead and behind (:meth:`Terrain.joined
    <mpcwalk.terrain.Terrain.joined>` without a kink)."""
    surfaces = terrain.surfaces
    first = last = index
    while last + 1 < len(surfaces) and terrain.joined(last, last + 1, 0.0):
        last += 1
    while first > 0 and terrain.joined(first - 1, first, 0.0):
        first -= 1
    top = surfaces[index]
    return surfaces[first].x_min, surfaces[last].x_max, top.y_min, top.y_max


def tread_bands(plan: FootstepPlan, terrain: Terrain, reach: TerrainReach) -> LandingBands:
    """The band of every landing of ``plan`` on ``terrain`` (see the module's
    documentation); the landings are those the placer put there.

    Args:
        plan: Footsteps placed on ``terrain``.
        terrain: The ground.
        reach: The sole's size and the tread margin the placer kept.
    """
    tops = TerrainTops(terrain, reach)
    lower, upper = np.full((plan.nb_steps, 2), -np.inf), np.full((plan.nb_steps, 2), np.inf)
    length, width = reach.sole_length, reach.sole_width
    margin = float(reach.tread_margin or 0.0)
    lift = {plan.initial_left.side: plan.initial_left, plan.initial_right.side: plan.initial_right}
    for k, step in enumerate(plan.steps):
        lift_height, lift[step.side] = float(lift[step.side].position[2]), step
        top = tops.rests_on(step.xy, step.yaw)
        if top[0] != "top":
            continue  # the floor beyond the terrain, a rough patch: no band
        x_min, x_max, y_min, y_max = _footprint(terrain, top[1])
        heading = np.array([np.cos(step.yaw), np.sin(step.yaw)])
        c, s = np.abs(heading)
        half = 0.5 * np.array([c * length + s * width, s * length + c * width]) + margin
        low, high = np.array([x_min, y_min]) + half, np.array([x_max, y_max]) - half
        if float(step.position[2]) < lift_height - DESCENT_MIN:  # a step down: heel room
            room = DESCENT_HEEL_ROOM * length
            low, high = (
                low + room * np.maximum(heading, 0.0),
                high - room * np.maximum(-heading, 0.0),
            )
        xy = np.asarray(step.xy, dtype=float)
        lower[k], upper[k] = np.minimum(low, xy), np.maximum(high, xy)
    return LandingBands(lower, upper)


__all__ = ["LandingBands", "tread_bands"]
