"""The joint torque loop of a torque-controlled robot: each motor's gain measured by its joint
torque sensor, and the commands divided by it.

A motor applies a share of the torque it is commanded: its torque constant, its amplifier's
gain and its gear's efficiency differ from the datasheet's (the simulator's
``servo_strength``); the whole-body inverse dynamics, which computes the torques the robot
needs, cannot know it. The joint torque sensors
(:attr:`~mpcwalk.robot.sensors.SensorReadings.joint_torques`) measure what each joint gets.
:class:`TorqueLoop` pairs each reading with the command the motor held when it was taken
(the command of the tick whose time is the reading's, whatever the latency), estimates each
motor's gain ``g`` (applied over commanded) by least squares with exponential forgetting,
and divides the next commands by it:

.. math::

    g_j = \\frac{w_0 + \\sum_k \\lambda^{K-k} \\tau^{m}_{jk} \\tau^{c}_{jk}}
               {w_0 + \\sum_k \\lambda^{K-k} (\\tau^{c}_{jk})^2}, \\qquad
    \\tau^{c}_j = \\mathrm{clip}(\\tau_j / g_j, \\pm \\tau^{max}_j)

with ``lambda = exp(-dt / memory)`` and the prior ``w0`` (a gain of 1) as heavy as a torque
of ``prior_share`` of the joint's limit held over the memory: a joint that carries little
torque keeps its nominal gain, a loaded one reaches its own within a fraction of a second.
``g`` stays within :data:`GAIN_RANGE`.

A gain, not an integral of the torque error: a motor's error scales with its torque, which
changes several times a step; its gain does not. What a gain cannot see (friction, a
torque limit reached) the whole-body feedback still corrects.
"""

import math
from collections import deque

import numpy as np

from mpcwalk.exceptions import ConfigurationError

#: Smallest and largest gain (applied over commanded torque) the loop believes.
GAIN_RANGE = (0.5, 1.5)

#: Memory [s] of the gains' least squares (the time constant of their forgetting).
MEMORY = 0.5

#: Weight of the prior gain of 1, as a share of each joint's torque limit held over the memory.
PRIOR_SHARE = 0.05


class TorqueLoop:
    """Each motor's gain from the joint torque sensors; the commands divided by it.

    Args:
        torque_limits: Torque limit of each joint [N m] (the commands' bound; inf: none),
            shape (nb_joints,).
        control_period: Time between two commands [s].
        memory: Time constant [s] of the gains' forgetting.
        prior_share: Weight of the prior gain of 1, as a share of each joint's limit (a
            joint without a finite limit: of 1 N m).

    Raises:
        ConfigurationError: Limits that are not positive, a non-positive period or memory, a
            negative prior.
    """

    def __init__(
        self,
        torque_limits: np.ndarray,
        *,
        control_period: float,
        memory: float = MEMORY,
        prior_share: float = PRIOR_SHARE,
    ) -> None:
        limits = np.array(torque_limits, dtype=float)
        if limits.ndim != 1 or np.any(np.isnan(limits)) or np.any(limits <= 0.0):
            raise ConfigurationError(
                f"torque_limits must be one positive limit per joint [N m] (inf: none), got "
                f"{torque_limits!r}."
            )
        for name, value in (("control_period", control_period), ("memory", memory)):
            if not (math.isfinite(value) and value > 0.0):
                raise ConfigurationError(f"{name} must be > 0 [s], got {value!r}.")
        if not (math.isfinite(prior_share) and prior_share >= 0.0):
            raise ConfigurationError(f"prior_share must be >= 0, got {prior_share!r}.")
        self.limits = limits
        self.control_period = float(control_period)
        self.forgetting = math.exp(-self.control_period / memory)
        scale = np.where(np.isfinite(limits), limits, 1.0)
        # the prior, which never fades: what a torque of prior_share * limit held over the
        # memory adds to the sums
        self._prior = (prior_share * scale) ** 2 / (1.0 - self.forgetting)
        self._pending: deque[tuple[float, np.ndarray]] = deque(maxlen=128)
        self.reset()

    def reset(self) -> None:
        """Forget the commands and the gains (back to 1)."""
        self._pending.clear()
        self._numerator = np.zeros_like(self.limits)
        self._denominator = np.zeros_like(self.limits)
        self.gains = np.ones_like(self.limits)
        """Each motor's estimated gain (applied over commanded torque)."""
        self.readings_used = 0
        """Readings paired with their command so far."""

    def measure(self, time: float, measured: np.ndarray | None) -> None:
        """Take the joint torque sensors' ``measured`` torques [N m] of ``time`` [s]: paired
        with the command of that time, if one is still held; otherwise (no sensors, a
        reading before the first command, non-finite values) ignored."""
        if measured is None or not self._pending:
            return
        while self._pending and self._pending[0][0] < time - 0.25 * self.control_period:
            self._pending.popleft()  # older than the reading: never measured again
        if not self._pending or abs(self._pending[0][0] - time) > 0.25 * self.control_period:
            return
        _, commanded = self._pending.popleft()
        measured = np.asarray(measured, dtype=float)
        if measured.shape != commanded.shape or not np.all(np.isfinite(measured)):
            return
        decay = self.forgetting
        self._numerator = decay * self._numerator + measured * commanded
        self._denominator = decay * self._denominator + commanded * commanded
        ratio = (self._numerator + self._prior) / (self._denominator + self._prior)
        self.gains = np.clip(ratio, *GAIN_RANGE)
        self.readings_used += 1

    def command(self, time: float, torques: np.ndarray) -> np.ndarray:
        """The motor commands [N m] of the tick of ``time`` [s] for the joint ``torques`` the
        robot needs: divided by the gains, within the limits (kept to be paired with the
        reading of that time)."""
        commanded = np.clip(
            np.asarray(torques, dtype=float) / self.gains, -self.limits, self.limits
        )
        self._pending.append((float(time), commanded))
        return commanded


__all__ = ["GAIN_RANGE", "MEMORY", "PRIOR_SHARE", "TorqueLoop"]
