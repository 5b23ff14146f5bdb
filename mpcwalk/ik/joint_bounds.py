"""Joint position and velocity limits as bounds on an IK step, and the box QP they make."""

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError

DEFAULT_VELOCITY_LIMIT = 6.0
"""Joint velocity limit [rad/s] used where the model gives none (MJCF look-alikes); about
the no-load speed of a hobby servo (AX-12A: 59 rpm)."""

_INFINITY = 1e30  # DAQP's "no bound"


class JointBounds:
    """Bounds ``lower <= dq_j <= upper`` on the step of every actuated joint ``j``.

    A step covers at most ``limit_gain`` of the distance to a position limit and, with
    velocity bounds, moves no faster than the velocity limit. A joint already beyond a
    position limit is moved back, no faster than its velocity limit.

    Args:
        model: Pinocchio model: a free-flyer root, then 1-DoF joints (as
            :class:`~mpcwalk.robot.robot.Robot` guarantees).
        velocity_limit: Joint velocity limit [rad/s]: a float, one per actuated joint, or None
            for the model's limits (:data:`DEFAULT_VELOCITY_LIMIT` where it has none);
            ``np.inf`` disables it.

    Raises:
        ConfigurationError: ``velocity_limit`` is not positive or has the wrong size.
    """

    def __init__(self, model: pin.Model, velocity_limit: float | np.ndarray | None = None) -> None:
        self.root_nv = int(model.joints[1].nv)
        self.joint_q = np.array([model.idx_qs[j] for j in range(2, model.njoints)], dtype=int)
        lower = model.lowerPositionLimit[self.joint_q]
        upper = model.upperPositionLimit[self.joint_q]
        bounded = np.isfinite(lower) & np.isfinite(upper) & (upper > lower)
        self.q_lower = np.where(bounded, lower, -np.inf)
        """Lower position limits [rad], -inf where there is none, shape (nb_joints,)."""
        self.q_upper = np.where(bounded, upper, np.inf)
        """Upper position limits [rad], +inf where there is none."""
        nb_joints = len(self.joint_q)
        if velocity_limit is None:
            model_limit = model.velocityLimit[self.root_nv :]
            usable = np.isfinite(model_limit) & (model_limit > 0.0) & (model_limit < 1e10)
            limit = np.where(usable, model_limit, DEFAULT_VELOCITY_LIMIT)
        else:
            try:
                limit = np.broadcast_to(
                    np.asarray(velocity_limit, dtype=float), (nb_joints,)
                ).copy()
            except (TypeError, ValueError):
                limit = np.full(nb_joints, np.nan)
            if np.any(np.isnan(limit)) or np.any(limit <= 0.0):
                raise ConfigurationError(
                    f"velocity_limit must be a positive number [rad/s] or {nb_joints} of them "
                    f"(one per actuated joint), got {velocity_limit!r}."
                )
        self.velocity_limit = limit
        """Joint velocity limits [rad/s], shape (nb_joints,)."""

    def compute(
        self, q: np.ndarray, dt: float, limit_gain: float, velocity_bounds: bool = True
    ) -> tuple[np.ndarray, np.ndarray]:
        """Bounds (lower, upper) on the joint steps [rad] at ``q`` for a period ``dt`` [s]."""
        q_joints = q[self.joint_q]
        lower = limit_gain * (self.q_lower - q_joints)
        upper = limit_gain * (self.q_upper - q_joints)
        if velocity_bounds:
            step = dt * self.velocity_limit
            lower, upper = np.maximum(lower, -step), np.minimum(upper, step)
            beyond = lower > upper  # q beyond a limit: move back, no faster than v_max
            if beyond.any():
                back = np.clip(np.where(q_joints < self.q_lower, lower, upper), -step, step)
                lower[beyond], upper[beyond] = back[beyond], back[beyond]
        return lower, upper


def solve_box_qp(
    H: np.ndarray,
    c: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    root_nv: int,
    solver: str = "daqp",
) -> np.ndarray | None:
    """Minimise ``x^T H x / 2 + c^T x`` subject to ``lower <= x[root_nv:] <= upper``.

    Args:
        H: Positive definite Hessian, shape (nv, nv).
        c: Linear term, shape (nv,).
        lower: Lower bounds of the joint coordinates (may hold -inf).
        upper: Upper bounds of the joint coordinates (may hold +inf).
        root_nv: Number of unbounded leading coordinates (floating base).
        solver: ``"daqp"`` (called directly) or a qpsolvers back-end name.

    Returns:
        The solution, or None when the solver fails (it never raises).
    """
    lb = np.concatenate([np.full(root_nv, -_INFINITY), np.maximum(lower, -_INFINITY)])
    ub = np.concatenate([np.full(root_nv, _INFINITY), np.minimum(upper, _INFINITY)])
    try:
        if solver == "daqp":
            import daqp

            sense = np.zeros(len(lb), dtype=np.int32)
            x, _, exitflag, _ = daqp.solve(H, c, np.zeros((0, len(lb))), ub, lb, sense)
            return x if exitflag > 0 else None
        import qpsolvers

        return qpsolvers.solve_qp(H, c, lb=lb, ub=ub, solver=solver)
    except Exception:
        return None
