"""Joint velocities from the encoders: finite differences through a first-order low-pass.

An encoder reports the angle quantised to its resolution (a Dynamixel AX-12's 1024 steps per
300 degrees: 5.1 mrad) plus noise. The finite difference of two readings is then a train of
spikes of one step per control period (0.51 rad/s at 100 Hz for a 5.1 mrad step) around the
true velocity; the first-order low-pass

    v_k = v_{k-1} + alpha (d_k - v_{k-1}),  alpha = dt / (dt + 1 / (2 pi f_c)),

with d_k the finite difference, averages the spikes over its time constant ``1 / (2 pi f_c)``
and follows motions slower than ``f_c`` with a lag of about that time constant.
"""

import math

import numpy as np

from mpcwalk.exceptions import ConfigurationError, NotReset


class JointVelocityFilter:
    """Low-pass filtered finite differences of the joint encoders.

    Args:
        nb_joints: Number of joints.
        cutoff_frequency: Cut-off frequency f_c of the first-order low-pass [Hz].

    Raises:
        ConfigurationError: A non-positive number of joints or cut-off frequency.
    """

    def __init__(self, nb_joints: int, *, cutoff_frequency: float = 15.0) -> None:
        if nb_joints < 1:
            raise ConfigurationError(f"nb_joints must be >= 1, got {nb_joints!r}.")
        if not (math.isfinite(cutoff_frequency) and cutoff_frequency > 0.0):
            raise ConfigurationError(f"cutoff_frequency must be > 0 Hz, got {cutoff_frequency!r}.")
        self.nb_joints = int(nb_joints)
        self.cutoff_frequency = float(cutoff_frequency)
        self.time_constant = 1.0 / (2.0 * math.pi * self.cutoff_frequency)
        self._positions: np.ndarray | None = None
        self._velocities = np.zeros(self.nb_joints)

    @property
    def velocities(self) -> np.ndarray:
        """Filtered joint velocities [rad/s], shape (nb_joints,) (a copy)."""
        return self._velocities.copy()

    def reset(self, positions: np.ndarray, velocities: np.ndarray | None = None) -> None:
        """Start from encoder ``positions`` [rad] with ``velocities`` [rad/s] (None: zero).

        Raises:
            ConfigurationError: Arrays of the wrong size.
        """
        positions = np.array(positions, dtype=float)
        if positions.shape != (self.nb_joints,):
            raise ConfigurationError(
                f"JointVelocityFilter expects {self.nb_joints} joint positions, got shape "
                f"{positions.shape}."
            )
        self._positions = positions
        self._velocities = (
            np.zeros(self.nb_joints)
            if velocities is None
            else np.array(velocities, dtype=float).reshape(self.nb_joints)
        )

    def update(self, positions: np.ndarray, dt: float) -> np.ndarray:
        """Filter one encoder reading taken ``dt`` after the previous one.

        Args:
            positions: Joint angles [rad], shape (nb_joints,).
            dt: Time since the previous reading [s]; 0 (a repeated reading) keeps the
                velocities.

        Returns:
            The filtered velocities [rad/s] (the filter's own array: copy it to keep it).

        Raises:
            NotReset: :meth:`reset` was not called.
        """
        if self._positions is None:
            raise NotReset("JointVelocityFilter.update was called before reset; call reset first.")
        if dt > 0.0:
            alpha = dt / (dt + self.time_constant)
            difference = (positions - self._positions) / dt
            self._velocities = self._velocities + alpha * (difference - self._velocities)
            self._positions = np.array(positions, dtype=float)
        return self._velocities


__all__ = ["JointVelocityFilter"]
