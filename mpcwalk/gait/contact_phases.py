"""The contact phases of a schedule (:class:`Phase`) and their support centres."""

from dataclasses import dataclass

import numpy as np

from mpcwalk.footsteps.footstep import Footstep, Side
from mpcwalk.models.support_polygon import SupportPolygon


@dataclass(frozen=True)
class Phase:
    """One contact phase.

    Attributes:
        start: Start time, in [s].
        end: End time, in [s].
        step_index: Step this phase belongs to; -1 for the initial stance and
            ``nb_steps`` for the final one.
        single_support: True when one foot only is on the ground.
        support_side: Supporting foot in single support, else None.
        feet: Feet on the ground during the phase (one or two).
        polygon: Support polygon of the phase.
    """

    start: float
    end: float
    step_index: int
    single_support: bool
    support_side: Side | None
    feet: dict[Side, Footstep]
    polygon: SupportPolygon

    @property
    def duration(self) -> float:
        """Phase length, in [s]."""
        return self.end - self.start


def _center(feet: dict[Side, Footstep]) -> np.ndarray:
    """Mean of the feet's (x, y), as ``np.mean(..., axis=0)`` computes it (the sum over the
    feet, divided by their number)."""
    points = [foot.xy for foot in feet.values()]
    if len(points) == 1:
        return points[0] / 1.0
    return (points[0] + points[1]) / 2.0 if len(points) == 2 else np.mean(points, axis=0)


def phase_centers(phases: list[Phase]) -> np.ndarray:
    """The support centre of each phase (its support foot, or the midpoint of its feet),
    shape (n, 2), in [m]: :func:`_center` of each phase's feet, the same operations on all
    the phases at once."""
    if not phases:
        return np.zeros((0, 2))
    if any(len(ph.feet) > 2 for ph in phases):  # pragma: no cover - one or two feet
        return np.array([_center(ph.feet) for ph in phases])
    pairs = [tuple(foot.xy for foot in ph.feet.values()) for ph in phases]
    first = np.array([pair[0] for pair in pairs])
    second = np.array([pair[-1] for pair in pairs])
    two = np.array([len(pair) == 2 for pair in pairs])[:, None]
    return np.where(two, (first + second) / 2.0, first / 1.0)


__all__ = ["Phase", "phase_centers"]
