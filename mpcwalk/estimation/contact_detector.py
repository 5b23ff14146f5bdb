"""Which feet touch the ground, from their force sensors' normal forces, with hysteresis.

A foot comes into contact when its normal force rises above ``on_fraction`` of the robot's
weight and leaves it when the force falls below ``off_fraction``: between the two thresholds
the previous state holds, so a noisy force hovering around one threshold does not make the
contact chatter (a Schmitt trigger; the thresholds are apart by several standard deviations
of the force sensor's noise).
"""

import math
from collections.abc import Sequence

import numpy as np

from mpcwalk.exceptions import ConfigurationError


class ContactDetector:
    """Contact state of each foot from its normal force, with hysteresis.

    Args:
        weight: The robot's weight m g [N]; the thresholds are fractions of it.
        on_fraction: A foot comes into contact when its normal force exceeds
            ``on_fraction * weight``.
        off_fraction: A foot leaves contact when its normal force falls below
            ``off_fraction * weight`` (lower than ``on_fraction``).
        nb_feet: Number of feet.

    Raises:
        ConfigurationError: A non-positive weight, or thresholds not ordered
            ``0 <= off_fraction < on_fraction``.
    """

    def __init__(
        self,
        weight: float,
        *,
        on_fraction: float = 0.08,
        off_fraction: float = 0.03,
        nb_feet: int = 2,
    ) -> None:
        if not (math.isfinite(weight) and weight > 0.0):
            raise ConfigurationError(f"weight must be a force > 0 N, got {weight!r}.")
        if not (0.0 <= off_fraction < on_fraction and math.isfinite(on_fraction)):
            raise ConfigurationError(
                "The contact thresholds must satisfy 0 <= off_fraction < on_fraction; got "
                f"off_fraction = {off_fraction!r}, on_fraction = {on_fraction!r}; put the "
                "'on' threshold above the 'off' one."
            )
        if nb_feet < 1:
            raise ConfigurationError(f"nb_feet must be >= 1, got {nb_feet!r}.")
        self.weight = float(weight)
        self.on_force = float(on_fraction) * self.weight
        self.off_force = float(off_fraction) * self.weight
        self.nb_feet = int(nb_feet)
        self._in_contact = np.zeros(self.nb_feet, dtype=bool)
        self._nb_switches = 0

    @property
    def in_contact(self) -> tuple[bool, ...]:
        """Contact state of each foot."""
        return tuple(bool(c) for c in self._in_contact)

    @property
    def nb_switches(self) -> int:
        """Contact changes (on or off, all feet) since :meth:`reset`."""
        return self._nb_switches

    def reset(self, normal_forces: Sequence[float] | np.ndarray) -> tuple[bool, ...]:
        """Start from the forces of one reading: a foot is in contact above the 'on'
        threshold.

        Args:
            normal_forces: Normal force of each foot [N].

        Returns:
            The contact state of each foot.
        """
        forces = self._checked(normal_forces)
        self._in_contact = forces > self.on_force
        self._nb_switches = 0
        return self.in_contact

    def update(self, normal_forces: Sequence[float] | np.ndarray) -> tuple[bool, ...]:
        """Update the contact states with one reading of the normal forces.

        Args:
            normal_forces: Normal force of each foot [N].

        Returns:
            The contact state of each foot.
        """
        forces = self._checked(normal_forces)
        new = np.where(self._in_contact, forces >= self.off_force, forces > self.on_force)
        self._nb_switches += int(np.count_nonzero(new != self._in_contact))
        self._in_contact = new
        return self.in_contact

    def _checked(self, normal_forces: Sequence[float] | np.ndarray) -> np.ndarray:
        forces = np.asarray(normal_forces, dtype=float)
        if forces.shape != (self.nb_feet,):
            raise ConfigurationError(
                f"ContactDetector expects {self.nb_feet} normal forces, got shape {forces.shape}."
            )
        if not np.isfinite(forces).all():  # a dropped reading counts as no force
            forces = np.where(np.isfinite(forces), forces, 0.0)
        return forces


__all__ = ["ContactDetector"]
