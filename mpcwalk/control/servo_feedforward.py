"""Servo feed-forward: joint targets that make compliant position servos hold a motion.

A position servo of stiffness ``kp`` [N m/rad] and velocity gain ``kv`` [N m s/rad] applies
``kp (target - q) - kv dq``. To move joint ``j`` along ``(q_j, dq_j)`` while it carries the
torque ``tau_j`` of the motion it needs the target

    q_j + (tau_j + (kv_j + d_j) dq_j) / kp_j          (d_j: passive joint damping).

Small humanoids with hobby servos (AX-12A: 1.5 N m stall torque, kp from about 9 N m/rad at the
default compliance slope to 74 N m/rad at slope 4; bioloid-like: 50) sag by degrees at the knees and hip rolls
without it: the swing foot of a kinematic plan
then does not lift and the CoM is off by centimetres.

The torques come from the inverse dynamics of the reference motion (Pinocchio's RNEA) with
the feet on the ground: the generalised forces ``ID(q, v, a)`` are balanced by the contact
wrenches of the feet in contact,

    ID(q, v, a) = S^T tau + sum_i J_i^T f_i,

where the wrenches ``f_i`` (sole frames) balance the floating base (first six rows) and are
shared between the feet in proportion to given weights: the weighted minimum-norm split
``f_i = w_i A_i^T lambda`` with ``A_i = J_i[:, :6]^T`` and
``(sum_i w_i A_i A_i^T) lambda = ID[:6]``. A horizontal base acceleration added to ``a``
moves the centre of pressure of that wrench: this is how a desired ZMP shift is realised.
"""

from collections.abc import Sequence

import numpy as np
import pinocchio as pin
from scipy.linalg import lapack

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.robot import Robot

_MIN_WEIGHT = 1e-3  # feet carrying less than this share of the wrench are left out


class ServoFeedforward:
    """Joint target offsets ``(tau + damping dq) / kp`` of a position-controlled robot.

    Args:
        robot: The robot; the stiffness, velocity gain and torque limit of each joint's
            position servo, and the passive joint damping, are its
            :attr:`~mpcwalk.robot.robot.Robot.servo_gains` (joints without a position
            actuator get no offset).

    Raises:
        ConfigurationError: The robot has no position actuator at all.
    """

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.model = robot.model
        self.data = robot.model.createData()
        gains = robot.servo_gains
        self.stiffness = np.array(gains.stiffness)
        """Servo stiffness of each joint [N m/rad] (inf: no position actuator)."""
        self.damping = np.array(gains.damping)
        """Servo velocity gain plus passive joint damping [N m s/rad]."""
        self.torque_limit = np.array(gains.torque_limit)
        """Servo torque limit of each joint [N m]."""
        if not np.any(np.isfinite(self.stiffness)):
            raise ConfigurationError(
                f"Robot '{robot.name}' has no position actuator: the servo feed-forward needs "
                "the stiffness kp of the joints."
            )
        self.sole_ids = [robot.frame_id(frame) for frame in robot.foot_frames]

    def compute_torques(
        self,
        q: np.ndarray,
        weights: Sequence[float],
        v: np.ndarray | None = None,
        a: np.ndarray | None = None,
    ) -> np.ndarray:
        """Joint torques [N m] of the motion ``(q, v, a)`` on the feet, shape (nq - 7,).

        Args:
            q: Configuration, shape (nq,).
            weights: Share of the contact wrench carried by the left and right feet (sum 1).
            v: Velocity, shape (nv,) (Pinocchio's convention); None for zero.
            a: Acceleration, shape (nv,); None for zero. Both None: static torques.
        """
        return self.compute_torques_and_wrenches(q, weights, v, a)[0]

    def compute_torques_and_wrenches(
        self,
        q: np.ndarray,
        weights: Sequence[float],
        v: np.ndarray | None = None,
        a: np.ndarray | None = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Joint torques [N m], shape (nq - 7,), and the contact wrenches of the left and
        right soles (force [N], moment [N m] in the sole frame, zero for a foot left out),
        shape (2, 6). Same arguments as :meth:`compute_torques`."""
        model, data = self.model, self.data
        if v is None and a is None:
            generalized = pin.computeGeneralizedGravity(model, data, q)
        else:
            zero = np.zeros(model.nv)
            generalized = pin.rnea(
                model, data, q, zero if v is None else v, zero if a is None else a
            )
        wrenches = np.zeros((2, 6))
        feet = [
            (i, float(w), f)
            for i, (w, f) in enumerate(zip(weights, self.sole_ids))
            if w >= _MIN_WEIGHT
        ]
        torques = generalized[6:].copy()
        if not feet:
            return torques, wrenches
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        jacobians = [
            (i, w, pin.getFrameJacobian(model, data, f, pin.ReferenceFrame.LOCAL))
            for i, w, f in feet
        ]
        schur = sum(w * jacobian[:, :6].T @ jacobian[:, :6] for _, w, jacobian in jacobians)
        # LAPACK's LU solve, as np.linalg.solve, without its wrapping
        _, _, multiplier, info = lapack.dgesv(schur, generalized[:6])
        if info != 0:
            multiplier = np.linalg.solve(schur, generalized[:6])  # raises LinAlgError
        for i, w, jacobian in jacobians:
            wrenches[i] = w * jacobian[:, :6] @ multiplier
            torques -= jacobian[:, 6:].T @ wrenches[i]
        return torques, wrenches

    def compute_offsets(
        self,
        q: np.ndarray,
        weights: Sequence[float],
        v: np.ndarray | None = None,
        a: np.ndarray | None = None,
    ) -> np.ndarray:
        """Joint target offsets [rad] ``(tau + damping dq) / kp``, within the torque limits.

        Same arguments as :meth:`compute_torques`; with ``v`` the servo's velocity gain and
        the joint damping the motion meets are compensated too.
        """
        torques = self.compute_torques(q, weights, v, a)
        if v is not None:
            torques += self.damping * v[6:]
        torques = np.minimum(np.maximum(torques, -self.torque_limit), self.torque_limit)
        return torques / self.stiffness
