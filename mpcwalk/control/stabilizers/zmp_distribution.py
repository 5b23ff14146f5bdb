"""The desired ZMP distributed between the feet: each foot's desired force and CoP.

In single support the support foot carries the whole weight with its CoP at the desired ZMP
(clamped into its sole). In double support the weight is shared by the ZMP's position along
the segment between the two sole centres (the ratio of
:func:`~mpcwalk.control.dcm_feedback.support_weights`, which the servo feed-forward uses for
its wrench split too): with ``s`` the left foot's share and ``d`` the ZMP's distance from that
segment, each foot's CoP is its sole centre plus ``d``, so that the weighted mean of the two
CoPs is the ZMP (Caron et al. 2019 distribute the ZMP by a ratio in the same way; Kajita et
al. 2010, the stabilizer of HRP-4C, likewise split the ZMP into the two feet's). A CoP that
would leave its sole is clamped ``margin`` inside it.
"""

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mpcwalk.control.dcm_feedback import support_weights
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.swing_foot import FeetState, FootState


@dataclass(frozen=True)
class FootWrenchTargets:
    """Desired vertical force and CoP of each foot.

    Attributes:
        weights: Share of the weight on the left and right feet, shape (2,), sum 1.
        forces: Desired normal force of each foot, shape (2,), in [N].
        cops: Desired CoP of each foot, world frame, shape (2, 2), in [m] (the sole centre
            for a foot that carries nothing).
    """

    weights: np.ndarray
    forces: np.ndarray
    cops: np.ndarray


class ZmpDistribution:
    """Share the desired ZMP and the robot's weight between the feet in contact.

    Args:
        sole_size: Sole length and width [m].
        margin: Distance [m] kept between a foot's desired CoP and its sole's edges.

    Raises:
        ConfigurationError: A margin that leaves no room in the sole.
    """

    def __init__(self, sole_size: tuple[float, float], *, margin: float = 0.0) -> None:
        half = 0.5 * np.asarray(sole_size, dtype=float)
        if not (np.all(np.isfinite(half)) and half.shape == (2,) and np.all(half > 0.0)):
            raise ConfigurationError(
                f"sole_size must be two positive lengths [m], got {sole_size!r}."
            )
        if not (0.0 <= margin < float(half.min())):
            raise ConfigurationError(
                f"The CoP margin must lie in [0, {half.min():g}) m (half the sole's smaller side), "
                f"got {margin!r}."
            )
        self.half_extent = half - margin
        """Half length and half width [m] of the region a foot's CoP is kept in."""

    def clamp_to_sole(self, point: Sequence[float] | np.ndarray, foot: FootState) -> np.ndarray:
        """``point`` [m], shape (2,), moved into the sole rectangle of ``foot`` (its yaw)."""
        c, s = math.cos(foot.yaw), math.sin(foot.yaw)
        dx, dy = (
            float(point[0]) - float(foot.position[0]),
            float(point[1]) - float(foot.position[1]),
        )
        half_x, half_y = float(self.half_extent[0]), float(self.half_extent[1])
        u = min(half_x, max(-half_x, c * dx + s * dy))  # in the sole frame
        v = min(half_y, max(-half_y, -s * dx + c * dy))
        return np.array([foot.position[0] + c * u - s * v, foot.position[1] + s * u + c * v])

    def distribute(self, zmp: np.ndarray, feet: FeetState, weight: float) -> FootWrenchTargets:
        """Desired force and CoP of each foot for the desired ``zmp`` [m], shape (2,), and the
        robot's ``weight`` [N]."""
        shares = support_weights(zmp, feet)
        left, right = feet.left, feet.right
        if left.in_contact and right.in_contact:
            # the ZMP's offset from the point of the segment between the soles at its share
            offset = [
                float(zmp[i]) - shares[0] * float(left.position[i]) - shares[1] * right.position[i]
                for i in (0, 1)
            ]
            cops = [
                self.clamp_to_sole(
                    (foot.position[0] + offset[0], foot.position[1] + offset[1]), foot
                )
                for foot in (left, right)
            ]
        else:
            cops = [
                self.clamp_to_sole(zmp, foot) if share > 0.0 else foot.position[:2].copy()
                for foot, share in ((left, shares[0]), (right, shares[1]))
            ]
        weights = np.array(shares, dtype=float)
        return FootWrenchTargets(weights, weight * weights, np.array(cops))
