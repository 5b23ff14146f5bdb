"""How much of each sole the inverse dynamics may put its centre of pressure on.

The contact wrench cone (:mod:`mpcwalk.ik.contact_wrench`) lets the CoP reach a share ``m``
of the half sole, as if the whole sole rested on the ground. On uneven ground it does not:
a sole on bumps touches them at a few points inside its outline, and the CoP can only move
within their hull. Torque control asks the CoP where the tasks want it; asked beyond that
hull, the sole rolls about its edge, lands on the next bump, and rocks from edge to edge
(12 to 20 deg on the robustness matrix's rough ground), which shakes the robot down.

A sole that rocks says so: a loaded sole on its ground does not turn, so its roll and pitch
rate ``w`` (the rate of the sole in its own frame, from the estimated state) is near zero on
a floor that carries the whole sole (0.08 rad/s median on ``atlas-like``'s level walk in
torque mode, 0.44 at the 90th percentile) and large on bumps (3.7 rad/s at the 90th
percentile). :class:`SoleSupport`, when it is given a ``rocking_rate`` (the default,
:data:`ROCKING_RATE`, is off), shrinks the CoP's share of a sole turning faster than
``rocking_rate`` to ``m w_c / w`` (no lower than ``min_share``) at once, and lets it grow
back towards ``m`` at ``recovery_rate`` per second; a sole that touches down starts from
``m``. The controller never learns the ground's shape: it learns from the sole how much of
it carries the CoP.
"""

import math

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.contact_wrench import wrench_cone

#: Default roll and pitch rate [rad/s] of a loaded sole above which its CoP's share shrinks:
#: 0, off. At 1 rad/s the torque matrix's large robots walk more of its worlds (their rough
#: ground most), the small humanoid and ``g1`` fewer (docs/concepts/torque-control.md).
ROCKING_RATE = 0.0


class SoleSupport:
    """The CoP share of each sole, shrunk while the sole rocks (module docstring).

    Args:
        sole_size: Sole length and width [m].
        friction: Friction coefficient of the ground (the cone's pyramid).
        share: Share in (0, 1] of the half sole the CoP may reach on a sole that does not
            rock (the cone's ``cop_margin``).
        rocking_rate: Roll and pitch rate [rad/s] of a loaded sole above which its share
            shrinks; 0 or inf: never (the share stays ``share``).
        min_share: Smallest share in (0, ``share``].
        recovery_rate: Share per second [1/s] by which a shrunk share grows back, > 0.

    Raises:
        ConfigurationError: A parameter out of its range.
    """

    def __init__(
        self,
        sole_size: tuple[float, float],
        friction: float,
        share: float,
        *,
        rocking_rate: float = ROCKING_RATE,
        min_share: float = 0.5,
        recovery_rate: float = 2.0,
    ) -> None:
        self.full = wrench_cone(sole_size, friction, share)
        if not (rocking_rate >= 0.0):
            raise ConfigurationError(
                f"rocking_rate must be >= 0 [rad/s] (0: the CoP's share never shrinks), got "
                f"{rocking_rate!r}."
            )
        if not (0.0 < min_share <= share):
            raise ConfigurationError(
                f"min_share must be in (0, {share}] (the CoP's share on a sole that does not "
                f"rock), got {min_share!r}."
            )
        if not (math.isfinite(recovery_rate) and recovery_rate > 0.0):
            raise ConfigurationError(f"recovery_rate must be > 0 [1/s], got {recovery_rate!r}.")
        self.sole_size, self.friction, self.share = sole_size, friction, float(share)
        self.rocking_rate = float(rocking_rate)
        self.min_share, self.recovery_rate = float(min_share), float(recovery_rate)
        self.active = 0.0 < self.rocking_rate < math.inf
        self.shares = [self.share, self.share]
        """The CoP share of the left and right soles at the last :meth:`cone`."""
        # each sole's narrowed cone, its CoP rows (|tx| <= m W / 2 fz, |ty| <= m L / 2 fz)
        # rewritten in place with the same products as wrench_cone's
        self._narrowed = [self.full.copy(), self.full.copy()]
        self._width_rows = np.flatnonzero(self.full[:, 3])
        self._length_rows = np.flatnonzero(self.full[:, 4])

    def reset(self) -> None:
        """Both soles back to the full share."""
        self.shares = [self.share, self.share]

    def cone(self, sole: int, rate: float, touched_down: bool, dt: float) -> np.ndarray:
        """The wrench cone rows of ``sole`` (0 left, 1 right) for this tick.

        Args:
            sole: Which sole.
            rate: Its roll and pitch rate [rad/s] (the norm of its angular velocity's x and
                y in its own frame).
            touched_down: It came into contact this tick (its share starts from the full
                one).
            dt: Time since the last tick [s].
        """
        if not self.active:
            return self.full
        share = self.share if touched_down else self.shares[sole]
        share = min(share + self.recovery_rate * dt, self.share)
        if rate > self.rocking_rate:
            share = min(share, max(self.min_share, self.share * self.rocking_rate / rate))
        self.shares[sole] = share
        if share == self.share:
            return self.full
        length, width = (float(size) for size in self.sole_size)
        narrowed = self._narrowed[sole]
        narrowed[self._width_rows, 2] = -(0.5 * share * width)
        narrowed[self._length_rows, 2] = -(0.5 * share * length)
        return narrowed


__all__ = ["ROCKING_RATE", "SoleSupport"]
