"""Inputs and outputs of the whole-body inverse dynamics: references, gains, weights, result.

The references of one tick are those of the time the torques act (the controller's next
references); every task turns its reference into a desired acceleration with a PD law on the
estimated state, ``a* = a_ref + kp e + kd (v_ref - v)``, so the gains are squared and plain
natural frequencies: ``kp = omega^2``, ``kd = 2 zeta omega``.
"""

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError

_ZERO3 = np.zeros(3)
_ZERO6 = np.zeros(6)


@dataclass(frozen=True)
class DynamicsTargets:
    """References of one inverse-dynamics tick, world frame.

    Attributes:
        com: CoM position, shape (3,), in [m].
        com_velocity: CoM velocity, shape (3,), in [m/s].
        com_acceleration: CoM acceleration (the pattern generator's), shape (3,), in [m/s^2].
        left_sole: Pose of the left sole (``pinocchio.SE3``).
        right_sole: Pose of the right sole.
        torso_rotation: Orientation of the torso frame, shape (3, 3).
        posture: Reference configuration (the IK's ``q_ref``), shape (nq,).
        contact_weights: Load of the left and right soles in [0, 1]: 0 a swing foot (its
            pose is a task), above 0 a sole in contact (its acceleration is constrained to
            zero and its normal force bounded by this share of the largest normal force: a
            ramp over a few ticks at touch-down and lift-off keeps the torques continuous).
        left_sole_velocity: Left sole velocity (linear [m/s], angular [rad/s], world axes),
            shape (6,).
        right_sole_velocity: Right sole velocity, shape (6,).
        left_sole_acceleration: Left sole acceleration (linear [m/s^2], angular [rad/s^2],
            world axes), shape (6,): the feed-forward of the swing foot.
        right_sole_acceleration: Right sole acceleration, shape (6,).
        torso_angular_velocity: Torso angular velocity, shape (3,), in [rad/s].
        posture_velocity: Reference velocity (the IK's), shape (nv,), or None for zero.
        posture_acceleration: Reference acceleration, shape (nv,), or None for zero.
    """

    com: np.ndarray
    com_velocity: np.ndarray
    com_acceleration: np.ndarray
    left_sole: pin.SE3
    right_sole: pin.SE3
    torso_rotation: np.ndarray
    posture: np.ndarray
    contact_weights: tuple[float, float] = (1.0, 1.0)
    left_sole_velocity: np.ndarray = field(default_factory=lambda: _ZERO6.copy())
    right_sole_velocity: np.ndarray = field(default_factory=lambda: _ZERO6.copy())
    left_sole_acceleration: np.ndarray = field(default_factory=lambda: _ZERO6.copy())
    right_sole_acceleration: np.ndarray = field(default_factory=lambda: _ZERO6.copy())
    torso_angular_velocity: np.ndarray = field(default_factory=lambda: _ZERO3.copy())
    posture_velocity: np.ndarray | None = None
    posture_acceleration: np.ndarray | None = None

    def __post_init__(self) -> None:
        weights = tuple(float(w) for w in self.contact_weights)
        if len(weights) != 2 or not all(0.0 <= w <= 1.0 for w in weights):
            raise ConfigurationError(
                f"contact_weights must be two loads in [0, 1] (left, right), got "
                f"{self.contact_weights!r}."
            )
        object.__setattr__(self, "contact_weights", weights)

    @property
    def soles(self) -> tuple[pin.SE3, pin.SE3]:
        """Left and right sole poses."""
        return self.left_sole, self.right_sole

    @property
    def sole_velocities(self) -> tuple[np.ndarray, np.ndarray]:
        """Left and right sole velocities, shape (6,) each."""
        return self.left_sole_velocity, self.right_sole_velocity

    @property
    def sole_accelerations(self) -> tuple[np.ndarray, np.ndarray]:
        """Left and right sole accelerations, shape (6,) each."""
        return self.left_sole_acceleration, self.right_sole_acceleration


@dataclass(frozen=True)
class DynamicsGains:
    """Natural frequencies [rad/s] (damping ratio 1) of the PD law of each task.

    Attributes:
        com: CoM position.
        swing_foot: Pose of a swing sole.
        torso: Torso orientation.
        posture: Joint angles towards the reference posture.
        momentum: Rate [1/s] at which the centroidal angular momentum is damped to zero.
        contact: Rate [1/s] at which a sole in contact is brought to rest
            (``J a + J_dot v = -contact J v``).
    """

    com: float = 10.0
    swing_foot: float = 25.0
    torso: float = 15.0
    posture: float = 15.0
    momentum: float = 5.0
    contact: float = 20.0

    def __post_init__(self) -> None:
        for name in ("com", "swing_foot", "torso", "posture", "momentum", "contact"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0.0):
                raise ConfigurationError(f"gain {name} must be a number >= 0, got {value!r}.")

    @staticmethod
    def pd(omega: Any) -> tuple[Any, Any]:
        """``(kp, kd)`` of natural frequency ``omega`` [rad/s] (a number or an array),
        critically damped."""
        return omega * omega, 2.0 * omega


@dataclass(frozen=True)
class DynamicsWeights:
    """Weights of the tasks (cost per squared acceleration error [(m/s^2)^-2], or
    [(rad/s^2)^-2]) and the regularisation.

    Attributes:
        com: CoM acceleration.
        swing_foot: Swing sole acceleration (linear and angular).
        torso: Torso angular acceleration.
        posture: Joint accelerations towards the reference posture.
        momentum: Rate of change of the centroidal angular momentum [(N m)^-2].
        force: Contact wrenches away from the share of the robot's weight of their sole's
            load (normal force only), per squared ``N`` over the weight squared: shares the
            load where the tasks leave it free.
        acceleration: Every acceleration coordinate (keeps the cost definite).
    """

    com: float = 1.0
    swing_foot: float = 1.0
    torso: float = 0.1
    posture: float = 5e-3
    momentum: float = 1e-3
    force: float = 1e-3
    acceleration: float = 1e-6

    def __post_init__(self) -> None:
        for name in ("com", "swing_foot", "torso", "posture", "momentum", "force"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0.0):
                raise ConfigurationError(f"weight {name} must be a number >= 0, got {value!r}.")
        if not (math.isfinite(self.acceleration) and self.acceleration > 0.0):
            raise ConfigurationError(
                f"weight acceleration must be > 0 (it keeps the cost definite), got "
                f"{self.acceleration!r}."
            )


@dataclass(frozen=True)
class DynamicsResult:
    """Result of one inverse-dynamics solve.

    Attributes:
        acceleration: Generalised acceleration, shape (nv,) (Pinocchio's convention).
        torques: Joint torques, shape (nv - 6,), in [N m] (``robot.joint_names`` order).
        wrenches: Contact wrench of the left and right soles (force [N], moment [N m] about
            the sole centre, sole frame), shape (2, 6); zero for a swing sole.
        contacts: Which soles were in contact (left, right).
        success: The QP was solved; False: the previous torques were kept.
        status: ``"solved"`` or the back-end's failure.
        solve_time: Wall time of the whole tick (build and solve) [s].
        qp_time: Wall time of the back-end's solve [s].
        dynamics_residual: Largest violation of the floating base's equations of motion
            ``M a + h - J_c^T f`` (first six rows) [N or N m].
        solver: Back-end name.
    """

    acceleration: np.ndarray
    torques: np.ndarray
    wrenches: np.ndarray
    contacts: tuple[bool, bool]
    success: bool
    status: str
    solve_time: float
    qp_time: float
    dynamics_residual: float
    solver: str

    @property
    def normal_forces(self) -> np.ndarray:
        """Normal force of each sole [N], shape (2,)."""
        return self.wrenches[:, 2].copy()

    @property
    def cops(self) -> np.ndarray:
        """Centre of pressure of each sole in its frame, shape (2, 2), in [m] (NaN for a
        sole carrying no load)."""
        out = np.full((2, 2), np.nan)
        for i, wrench in enumerate(self.wrenches):
            if wrench[2] > 1e-9:
                out[i] = (-wrench[4] / wrench[2], wrench[3] / wrench[2])
        return out
