"""Online estimate of the CoM offset between the controller's model and the robot.

The estimator computes the CoM from the encoders and the model's masses: a torso heavier or
lighter than the model, or its CoM elsewhere, puts the robot's real CoM ``c_r`` at a constant
offset ``delta`` from the model's ``c_m`` (horizontally). The force sensors see it: where the
robot follows the plan (``c_m = c_ref``), the measured centre of pressure is the planned ZMP
plus ``delta`` (LIPM: ``p = c_r - c_r'' / omega^2``), and the robot walks with its CoP that
far off the plan, towards the edge of its feet. A bias of the estimated CoM (an attitude
error of the estimator tilts the CoM around the feet) reads the same way, and is removed the
same way.

:class:`ComOffsetEstimator` integrates, slowly, the difference between the measured CoP and
the planned ZMP (the pattern generator's, before the DCM feedback), while the DCM error is
small (the robot near its plan, so that the difference is a bias and not a push or a
transient of the feedback). The gate reads the DCM error low-pass filtered over ``T_f``: the
DCM error of a walk swings back and forth along each step (by several centimetres on the
estimated state of a large robot), and gating on its instantaneous value would sample the
CoP error at some phases of the gait only, whose mean is not the bias, or never at all; a
push moves the filtered error for a second or more. The CoP error itself is low-pass
filtered with the same time constant ``T_f`` before it is integrated: it jumps by the length
of a foot when the weight goes from heel to toe or from foot to foot, and the estimate moves
the IK's CoM target, whose second derivative the servo feed-forward turns into torques
(unfiltered, each jump is a spike of feed-forward torque and saturated servos):

    d e_f / dt = (p_measured - z_planned - e_f) / T_f,    d delta_hat / dt = e_f / T,

bounded by ``limit`` per axis. The controller then places the model's CoM at
``c_ref - delta_hat`` (the IK's CoM target) and compares ``c_m + delta_hat`` with the plan
(the DCM feedback): the robot's CoM is brought onto the plan and the difference, hence the
update, goes to zero when ``delta_hat = delta``. ``T`` is several step durations, so that the
CoP's swing from foot to foot along a step averages out.

Against the planned ZMP rather than the desired one (the plan plus the DCM feedback): a
compliant robot realises only part of the feedback's ZMP shift, and that shortfall, read
against the desired ZMP, looks like a CoM offset the other way. On the LIPM both converge
(the DCM error vanishes at the end); on position-controlled robots only the first does.
"""

import math

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.swing_foot import FeetState
from mpcwalk.robot.sensors import ForceTorqueReading


def anchored_cop(
    wrenches: tuple[ForceTorqueReading, ForceTorqueReading],
    in_contact: tuple[bool, bool],
    feet: FeetState,
    min_force: float = 0.0,
) -> np.ndarray | None:
    """The measured CoP placed on the planned feet, shape (2,), in [m], or None.

    Each foot's CoP in its sole frame, ``(-tau_y / f_z, tau_x / f_z)`` from its force/torque
    reading, is carried onto the foot's planned pose (``feet``: position and yaw), and the
    feet's CoPs are averaged with their normal forces (paper M eq. 31). As the DCM feedback
    anchors the CoM, this keeps a landing a few millimetres off its footstep (a drift of the
    whole robot from the plan) out of the comparison with the planned ZMP.

    Args:
        wrenches: Left and right force/torque readings (sole frames).
        in_contact: Whether each foot is in contact (estimated).
        feet: Planned feet poses.
        min_force: Feet pressing less than this [N] are left out.

    Returns:
        The CoP, or None when no foot presses more than ``min_force``.
    """
    total, x, y = 0.0, 0.0, 0.0
    for wrench, contact, foot in zip(wrenches, in_contact, (feet.left, feet.right)):
        force = float(wrench.force[2])
        if not contact or force <= max(min_force, 0.0):
            continue
        ax, ay = -float(wrench.torque[1]), float(wrench.torque[0])  # the CoP times f_z
        c, s = math.cos(foot.yaw), math.sin(foot.yaw)
        x += force * float(foot.position[0]) + c * ax - s * ay
        y += force * float(foot.position[1]) + s * ax + c * ay
        total += force
    return np.array([x / total, y / total]) if total > 0.0 else None


def _positive(name: str, value: float, allow_inf: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or math.isnan(value):
        valid = False
    else:
        valid = value > 0.0 and (allow_inf or math.isfinite(value))
    if not valid:
        raise ConfigurationError(
            f"ComOffsetEstimator {name} must be a positive number, got {value!r}."
        )
    return float(value)


class ComOffsetEstimator:
    """Slow integrator of the steady CoP error: the offset of the robot's CoM from the model's.

    Args:
        time_constant: ``T`` [s]: the estimate moves by the CoP error over ``T`` per second.
        limit: Bound of the estimate on each axis [m].
        dcm_threshold: The estimate moves only while the norm of the filtered DCM error is
            below this [m].
        filter_time_constant: Time constant ``T_f`` [s] of the low-pass filters of the CoP
            error and of the DCM error.

    Raises:
        ConfigurationError: A non-positive or non-finite parameter.
    """

    def __init__(
        self,
        *,
        time_constant: float,
        limit: float,
        dcm_threshold: float = math.inf,
        filter_time_constant: float = 1.0,
    ) -> None:
        self.time_constant = _positive("time_constant", time_constant)
        self.limit = _positive("limit", limit)
        self.dcm_threshold = _positive("dcm_threshold", dcm_threshold, allow_inf=True)
        self.filter_time_constant = _positive("filter_time_constant", filter_time_constant)
        self._dcm_error = (0.0, 0.0)
        self._offset = (0.0, 0.0)
        self._cop_error = (0.0, 0.0)

    @property
    def offset(self) -> np.ndarray:
        """Estimated offset of the robot's CoM from the model's, shape (2,), in [m]."""
        return np.array(self._offset)

    @property
    def dcm_error(self) -> np.ndarray:
        """Low-pass filtered DCM error [m], shape (2,)."""
        return np.array(self._dcm_error)

    @property
    def cop_error(self) -> np.ndarray:
        """Low-pass filtered CoP error ``e_f`` [m], shape (2,)."""
        return np.array(self._cop_error)

    def reset(self) -> None:
        """Forget the estimate and the filters (a new walk)."""
        self._dcm_error = (0.0, 0.0)
        self._offset = (0.0, 0.0)
        self._cop_error = (0.0, 0.0)

    def update(
        self,
        cop: np.ndarray,
        desired_zmp: np.ndarray,
        dcm_error: np.ndarray,
        dt: float,
    ) -> np.ndarray:
        """Move the estimate by the CoP error of one tick.

        Args:
            cop: Measured centre of pressure, shape (2,) (or (3,)), in [m].
            desired_zmp: Planned ZMP of the same time, shape (2,), in [m].
            dcm_error: DCM error of the same time, shape (2,), in [m].
            dt: Duration of the tick [s].

        Returns:
            The estimate [m], shape (2,).
        """
        share = 1.0 - math.exp(-dt / self.filter_time_constant)
        gx, gy = self._dcm_error
        gx, gy = gx + share * (float(dcm_error[0]) - gx), gy + share * (float(dcm_error[1]) - gy)
        self._dcm_error = (gx, gy)
        ex, ey = float(cop[0]) - float(desired_zmp[0]), float(cop[1]) - float(desired_zmp[1])
        if math.hypot(gx, gy) < self.dcm_threshold and math.isfinite(ex + ey):
            rate, limit = dt / self.time_constant, self.limit
            fx, fy = self._cop_error
            fx, fy = fx + share * (ex - fx), fy + share * (ey - fy)
            dx, dy = self._offset
            self._cop_error = (fx, fy)
            self._offset = (
                min(limit, max(-limit, dx + rate * fx)),
                min(limit, max(-limit, dy + rate * fy)),
            )
        return self.offset
