"""Base position and linear velocity in the world: leg kinematics fused with the accelerometer.

A linear Kalman filter per world axis, state (position p, velocity v) of the floating base's
origin (Flayols, Del Prete, Wensing, Mifsud, Benallegue and Mansard 2017, "Experimental
evaluation of simple estimators for humanoid robots", Humanoids; Bloesch et al. 2013,
"State estimation for legged robots", RSS, for the anchored feet):

- prediction with the accelerometer: ``a = R_imu f - g e_z``, the specific force rotated to the
  world minus gravity (the IMU's acceleration stands for the base origin's; the process noise
  covers the difference and the tilt error);
- measurements from each foot in contact, anchored in the world: the base position
  ``anchor - R p_foot`` and velocity ``-R v_contact``, with ``p_foot`` the sole origin relative
  to the base and ``v_contact`` the velocity of the foot's contact point (its CoP) relative to
  the base, base frame, from the encoders. Each foot's measurement is weighted by the fraction
  of the robot's weight it carries (variance ``noise^2 / load``).

A foot that touches down is anchored where the leg kinematics put it relative to the feet
already anchored (or to the estimated base when none is), not where the filtered estimate
puts it (which the accelerometer's impact transients disturb), again every tick until it
carries ``anchor_load_fraction`` of the weight; it is then held there until it leaves the
ground. Anchoring at half the weight makes the handover symmetric: both feet then carry the
same load, so their compliant contacts (rubber soles, a simulator's soft contacts) are
compressed alike and the handover adds no drift.

The three axes share one 2 x 2 covariance (same noises on each axis).
"""

import math
from collections.abc import Callable

import numpy as np

from mpcwalk.exceptions import ConfigurationError, NotReset


def _positive(name: str, value: float, unit: str) -> float:
    if not (math.isfinite(value) and value > 0.0):
        raise ConfigurationError(f"{name} must be > 0 {unit}, got {value!r}.")
    return float(value)


class BaseEstimator:
    """Kalman filter of the base position and velocity from anchored feet and the IMU.

    Args:
        acceleration_noise: Standard deviation of the process acceleration [m/s^2] (the
            accelerometer's noise, its tilt error g sin(tilt), the IMU's lever arm).
        position_noise: Standard deviation of one fully loaded foot's base position
            measurement [m] (encoder errors through the leg, the contact's compliance).
        velocity_noise: Standard deviation of one fully loaded foot's base velocity
            measurement [m/s] (filtered encoder velocities through the leg).
        anchor_load_fraction: Load (fraction of the weight) from which a foot that touched
            down is held at its anchor.
        flat_ground: Anchor every foot at the height of the feet anchored at :meth:`reset`
            (a flat floor). False takes the heights from the leg kinematics too (stairs,
            uneven ground); they then drift with the compression of the contacts.
        nb_feet: Number of feet.
        ground: Height [m] of the known ground under a point ``(x, y)`` [m] (a terrain the
            robot's map holds): every foot is anchored at the map's height under it, on any
            terrain (``flat_ground`` is then ignored).

    Raises:
        ConfigurationError: A non-positive noise or a load fraction outside (0, 1].
    """

    def __init__(
        self,
        *,
        acceleration_noise: float = 2.0,
        position_noise: float = 0.002,
        velocity_noise: float = 0.1,
        anchor_load_fraction: float = 0.5,
        flat_ground: bool = True,
        nb_feet: int = 2,
        ground: Callable[[float, float], float] | None = None,
    ) -> None:
        self.acceleration_noise = _positive("acceleration_noise", acceleration_noise, "m/s^2")
        self.position_noise = _positive("position_noise", position_noise, "m")
        self.velocity_noise = _positive("velocity_noise", velocity_noise, "m/s")
        if not (0.0 < anchor_load_fraction <= 1.0):
            raise ConfigurationError(
                f"anchor_load_fraction must be in (0, 1], got {anchor_load_fraction!r}."
            )
        self.anchor_load_fraction = float(anchor_load_fraction)
        self.flat_ground = bool(flat_ground) and ground is None
        self.ground = ground
        """Height [m] of the known ground under a point (x, y) [m], or None."""
        self.nb_feet = int(nb_feet)
        self._state: np.ndarray | None = None  # rows: position, velocity; columns: x, y, z
        self._covariance = np.eye(2)
        self._anchors = np.full((self.nb_feet, 3), np.nan)
        self._anchored = np.zeros(self.nb_feet, dtype=bool)
        self._frozen = np.zeros(self.nb_feet, dtype=bool)
        self._sums = np.zeros((self.nb_feet, 3))
        self._sum_weights = np.zeros(self.nb_feet)
        self._ground_height: float | None = None

    @property
    def position(self) -> np.ndarray:
        """Base position, world frame, shape (3,), in [m] (a copy)."""
        return self._checked_state()[0].copy()

    @property
    def velocity(self) -> np.ndarray:
        """Base linear velocity, world frame, shape (3,), in [m/s] (a copy)."""
        return self._checked_state()[1].copy()

    @property
    def anchors(self) -> np.ndarray:
        """World position of each sole's anchor, shape (nb_feet, 3), in [m]; NaN for a foot
        not anchored (a copy)."""
        return np.where(self._anchored[:, None], self._anchors, np.nan)

    @property
    def covariance(self) -> np.ndarray:
        """Covariance of (position, velocity) on each axis, shape (2, 2) (a copy)."""
        return self._covariance.copy()

    def reset(
        self,
        position: np.ndarray,
        anchors: np.ndarray,
        in_contact: np.ndarray,
        *,
        velocity: np.ndarray | None = None,
    ) -> None:
        """Start at ``position`` with the feet in contact anchored at ``anchors``.

        Args:
            position: Base position, world frame, shape (3,), in [m].
            anchors: World position of each sole's origin, shape (nb_feet, 3), in [m].
            in_contact: Whether each foot is in contact, shape (nb_feet,).
            velocity: Base velocity, world frame, shape (3,), in [m/s]; None for zero.
        """
        state = np.zeros((2, 3))
        state[0] = position
        if velocity is not None:
            state[1] = velocity
        self._state = state
        self._covariance = np.diag([self.position_noise**2, self.velocity_noise**2])
        self._anchored = np.array(in_contact, dtype=bool).reshape(self.nb_feet)
        self._frozen = self._anchored.copy()
        self._sums = np.zeros((self.nb_feet, 3))
        self._sum_weights = np.zeros(self.nb_feet)
        self._anchors = np.array(anchors, dtype=float).reshape(self.nb_feet, 3)
        self._ground_height = (
            float(np.mean(self._anchors[self._anchored, 2])) if self._anchored.any() else None
        )

    def update(
        self,
        acceleration: np.ndarray,
        dt: float,
        rotation: np.ndarray,
        foot_positions: np.ndarray,
        contact_velocities: np.ndarray,
        in_contact: np.ndarray,
        loads: np.ndarray,
    ) -> np.ndarray:
        """Predict with the acceleration, then correct with the feet in contact.

        Args:
            acceleration: Base acceleration, world frame, gravity removed, shape (3,), in
                [m/s^2].
            dt: Time since the previous update [s].
            rotation: Base orientation in the world, shape (3, 3).
            foot_positions: Each sole's origin relative to the base, base frame, shape
                (nb_feet, 3), in [m].
            contact_velocities: Velocity of each foot's contact point relative to the base,
                base frame (the base's rotation included), shape (nb_feet, 3), in [m/s].
            in_contact: Whether each foot is in contact, shape (nb_feet,).
            loads: Fraction of the robot's weight each foot carries, shape (nb_feet,).

        Returns:
            The state, shape (2, 3): base position [m] and velocity [m/s], world frame (the
            filter's own array: copy it to keep it).

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        state = self._checked_state()
        if dt > 0.0:
            self._predict(state, acceleration, dt)
        world_feet = foot_positions @ rotation.T  # R p_foot, one row per foot
        weights = np.where(in_contact, np.minimum(np.maximum(loads, 0.0), 1.0), 0.0)
        self._anchored &= in_contact
        self._frozen &= in_contact
        self._sums[~in_contact] = 0.0
        self._sum_weights[~in_contact] = 0.0
        for foot in np.flatnonzero(in_contact & ~self._frozen):
            self._place_anchor(int(foot), state[0], world_feet, weights)
        anchored_weights = np.where(self._anchored, weights, 0.0)
        total = float(anchored_weights.sum())
        measured = None
        if total > 1e-6:
            measured = anchored_weights @ (self._anchors - world_feet) / total
        if measured is not None:
            self._correct(state, 0, measured, self.position_noise**2 / total)
        total = float(weights.sum())
        if total > 1e-6:
            measured = -(weights @ (contact_velocities @ rotation.T)) / total
            self._correct(state, 1, measured, self.velocity_noise**2 / total)
        return state

    def _place_anchor(
        self, foot: int, position: np.ndarray, world_feet: np.ndarray, weights: np.ndarray
    ) -> None:
        """Anchor a foot that touched down: the load-weighted mean of where the leg
        kinematics put it relative to the other anchored feet, while they carry load."""
        others = self._anchored.copy()
        others[foot] = False
        other_weight = float(weights[others].sum())
        if other_weight > 1e-6:
            reference = weights[others] @ (self._anchors[others] - world_feet[others])
            weight = min(float(weights[foot]), other_weight)
            self._sums[foot] += weight * (reference / other_weight + world_feet[foot])
            self._sum_weights[foot] += weight
            self._anchors[foot] = self._sums[foot] / self._sum_weights[foot]
        elif self._sum_weights[foot] > 0.0:  # the other feet left: keep the mean
            self._frozen[foot] = True
        else:  # no other foot to refer to (after a flight phase): the estimate
            self._anchors[foot] = position + world_feet[foot]
        if weights[foot] >= self.anchor_load_fraction:
            self._anchored[foot] = True
            self._frozen[foot] |= self._sum_weights[foot] == 0.0
        if self.ground is not None and self._anchored[foot]:
            # the map's height under the anchor: the leg kinematics drift with the
            # contacts' compression, the known tread does not
            self._anchors[foot, 2] = self.ground(*self._anchors[foot, :2])
        elif self.flat_ground and self._anchored[foot]:
            if self._ground_height is None:
                self._ground_height = float(self._anchors[foot, 2])
            self._anchors[foot, 2] = self._ground_height

    def _predict(self, state: np.ndarray, acceleration: np.ndarray, dt: float) -> None:
        state[0] += dt * state[1] + 0.5 * dt * dt * acceleration
        state[1] += dt * acceleration
        transition = np.array([[1.0, dt], [0.0, 1.0]])
        q = self.acceleration_noise**2
        noise = q * np.array([[dt**4 / 4.0, dt**3 / 2.0], [dt**3 / 2.0, dt * dt]])
        self._covariance = transition @ self._covariance @ transition.T + noise

    def _correct(self, state: np.ndarray, row: int, measured: np.ndarray, variance: float) -> None:
        """Kalman update with a measurement of the position (row 0) or velocity (row 1)."""
        covariance = self._covariance
        gain = covariance[:, row] / (covariance[row, row] + variance)
        state += gain[:, None] * (measured - state[row])[None, :]  # outer products
        self._covariance = covariance - gain[:, None] * covariance[row, :][None, :]

    def _checked_state(self) -> np.ndarray:
        if self._state is None:
            raise NotReset("BaseEstimator.update was called before reset; call reset first.")
        return self._state


__all__ = ["BaseEstimator"]
