"""The LIPM with a flywheel (Pratt et al. 2006): the upper body's angular momentum as a
second input of the pendulum.

With the CoM at constant height ``z_c``, the ground reaction at the ZMP ``p`` and the rate
``L_dot`` of the centroidal angular momentum (about the CoM, world axes), the moment balance
about the CoM gives, per horizontal axis (Newton-Euler with ``f = m (c_ddot + g e_z)``)::

    m z_c c_ddot_x = m g (c_x - p_x) - L_dot_y
    m z_c c_ddot_y = m g (c_y - p_y) + L_dot_x

so ``c_ddot = omega^2 (c - r)`` about the centroidal moment pivot (CMP)
``r = p + [L_dot_y, -L_dot_x] / (m g)``: the ZMP stays in the support polygon while the CMP
may leave it by the torque the upper body applies, divided by the weight.

Per CoM axis ``a`` this module uses the *flywheel momentum* ``k_a``: ``k_x = L_y`` and
``k_y = -L_x``, so that both axes read the same, ``r_a = p_a + k_dot_a / (m g)``, and the
*flywheel angle* ``phi_a`` with ``I_a phi_dot_a = k_a``: the lean of the upper body towards
``+a`` (``phi_x`` the pitch, forward positive; ``phi_y`` minus the roll, leftward positive).
A forward push is resisted by ``k_dot_x > 0``: the upper body pitches forward, the hip
strategy. With the torque ``tau_a = k_dot_a`` held over a period ``T`` the discretisation of
``[phi_a, k_a]`` is exact::

    phi[k+1] = phi[k] + T k[k] / I + T^2 tau / (2 I),      k[k+1] = k[k] + T tau.

The flywheel is bounded by what the upper body can do: the torque the hips can apply
(``max_torque``), the momentum its joint speeds allow (``max_momentum``) and its lean before
a joint limit (``max_angle``). :func:`cmp_offset_bound` is the farthest the flywheel moves
the capture point with them (Pratt 2006's flywheel capture region).
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.models.lipm import GRAVITY

#: The flywheel axes, in the order of the CoM axes they act on: pitch (x), roll (y).
AXES = ("pitch", "roll")


def _pair(name: str, value) -> tuple[float, float]:
    array = np.broadcast_to(np.asarray(value, dtype=float), (2,))
    if not np.all(np.isfinite(array)) or np.any(array < 0.0):
        raise ConfigurationError(
            f"FlywheelLimits.{name} must be a non-negative number or two (pitch, roll), got "
            f"{value!r}."
        )
    return float(array[0]), float(array[1])


@dataclass(frozen=True)
class FlywheelLimits:
    """What the upper body can do as a flywheel, per CoM axis (pitch for x, roll for y).

    Attributes:
        mass: Total mass of the robot ``m`` [kg] (the CMP offset is ``tau / (m g)``).
        inertia: Rotational inertia of the upper body about its CoM [kg m^2] (pitch, roll).
        max_torque: Largest torque the hips apply to the upper body [N m] (pitch, roll);
            0 turns the flywheel off on that axis.
        max_momentum: Largest angular momentum [kg m^2/s]: the joints' speed limits times
            the inertia (pitch, roll).
        max_angle: Largest lean of the upper body from upright [rad] (pitch, roll).
        gravity: [m/s^2].
    """

    mass: float
    inertia: tuple[float, float]
    max_torque: tuple[float, float]
    max_momentum: tuple[float, float]
    max_angle: tuple[float, float]
    gravity: float = GRAVITY

    def __post_init__(self) -> None:
        if not (math.isfinite(self.mass) and self.mass > 0.0):
            raise ConfigurationError(
                f"FlywheelLimits.mass must be a positive number of kilograms, got {self.mass!r}."
            )
        for name in ("inertia", "max_torque", "max_momentum", "max_angle"):
            object.__setattr__(self, name, _pair(name, getattr(self, name)))
        if min(self.inertia) <= 0.0:
            raise ConfigurationError(
                f"FlywheelLimits.inertia must be positive (pitch, roll) [kg m^2], got "
                f"{self.inertia!r}."
            )

    @classmethod
    def small_humanoid(cls) -> "FlywheelLimits":
        """The upper body of ``bioloid-like`` as :func:`mpcwalk.ik.upper_body.upper_body_flywheel`
        measures it (rounded): the default of a generator built without a robot."""
        return cls(
            mass=2.02,
            inertia=(0.0031, 0.0062),
            max_torque=(0.75, 0.75),
            max_momentum=(0.018, 0.037),
            max_angle=(0.3, 0.3),
        )

    def without_flywheel(self) -> "FlywheelLimits":
        """The same robot with no flywheel (zero torque): the plain LIPM."""
        return FlywheelLimits(
            self.mass, self.inertia, (0.0, 0.0), (0.0, 0.0), (0.0, 0.0), self.gravity
        )

    @property
    def weight(self) -> float:
        """``m g`` [N]."""
        return self.mass * self.gravity


@dataclass(frozen=True)
class FlywheelState:
    """The flywheel at one tick, per CoM axis (x: pitch, y: minus the roll).

    Attributes:
        lean: Lean ``phi`` of the upper body towards +x and +y, shape (2,), in [rad].
        momentum: Flywheel momentum ``k``, shape (2,), in [kg m^2/s].
        torque: Its rate ``tau``, shape (2,), in [N m].
    """

    lean: np.ndarray
    momentum: np.ndarray
    torque: np.ndarray

    @property
    def angular_momentum(self) -> np.ndarray:
        """Centroidal angular momentum in world axes ``[L_x, L_y, 0] = [-k_y, k_x, 0]``,
        shape (3,), in [kg m^2/s]."""
        return np.array([-self.momentum[1], self.momentum[0], 0.0])

    @property
    def rotation_vector(self) -> np.ndarray:
        """The lean as a rotation vector in world axes ``[-phi_y, phi_x, 0]``, shape (3,), in
        [rad] (pitch about y, roll about x)."""
        return np.array([-self.lean[1], self.lean[0], 0.0])


def flywheel_transition(duration: float, inertia: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact transition ``(A, B)`` of ``[phi, k]`` over ``duration`` [s] with the torque held:
    ``A`` (2, 2), ``B`` (2,), for an upper body of ``inertia`` [kg m^2]."""
    T = float(duration)
    A = np.array([[1.0, T / inertia], [0.0, 1.0]])
    B = np.array([0.5 * T * T / inertia, T])
    return A, B


def cmp_offset_bound(limits: FlywheelLimits, omega: float) -> tuple[float, float]:
    """How far [m] the flywheel moves the capture point, per CoM axis (x, y): the impulse
    ``J`` the LIPM with a flywheel recovers is the LIPM's for a DCM moved back by this much.

    The DCM obeys ``xi_dot = omega (xi - r)`` with ``r = p + tau / (m g)``: a torque history
    ``tau(t)`` starting now shifts the capture condition by
    ``omega / (m g) int_0^inf exp(-omega t) tau(t) dt``. The largest shift within the limits
    is bang-bang (Pratt 2006): ``+tau_max`` for ``t1``, coasting at ``k_max`` for ``tc``,
    ``-tau_max`` for ``t1`` to stop at the lean ``phi_max``, which gives
    ``tau_max / (m g) (1 - exp(-omega t1)) (1 - exp(-omega (t1 + tc)))``, with
    ``t1 = min(sqrt(I phi_max / tau_max), k_max / tau_max)``.

    Args:
        limits: The flywheel's limits.
        omega: LIPM natural frequency ``sqrt(g / z_c)`` [1/s].
    """
    if not (math.isfinite(omega) and omega > 0.0):
        raise ConfigurationError(f"omega must be a positive number [1/s], got {omega!r}.")
    offsets = []
    for a in range(2):
        tau, k_max = limits.max_torque[a], limits.max_momentum[a]
        inertia, phi = limits.inertia[a], limits.max_angle[a]
        if tau <= 0.0 or k_max <= 0.0 or phi <= 0.0:
            offsets.append(0.0)
            continue
        t1 = min(math.sqrt(inertia * phi / tau), k_max / tau)
        lean = tau * t1 * t1 / inertia  # while speeding up and slowing down
        tc = max(phi - lean, 0.0) * inertia / (tau * t1)  # coasting at the momentum tau t1
        share = (1.0 - math.exp(-omega * t1)) * (1.0 - math.exp(-omega * (t1 + tc)))
        offsets.append(tau / limits.weight * share)
    return offsets[0], offsets[1]


__all__ = ["AXES", "FlywheelLimits", "FlywheelState", "cmp_offset_bound", "flywheel_transition"]
