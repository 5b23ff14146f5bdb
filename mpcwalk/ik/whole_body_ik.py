"""Whole-body differential IK on Pinocchio: one small QP per control tick.

Each tick linearises the tasks (CoM, both soles in SE3, torso orientation, posture and, when
the targets carry one, the centroidal angular momentum of :mod:`mpcwalk.ik.momentum_task`) at
``q`` and solves for the displacement ``dq`` (``v = dq / dt``):

    minimise   sum_i || W_i (J_i dq + gain e_i - dt ff_i) ||^2 + (damping + mu) ||dq||^2
    subject to lower_i <= dq_i <= upper_i     for every actuated joint i

with ``mu = lm_damping * sum_i ||gain W_i e_i||^2`` (Levenberg-Marquardt: large errors, e.g.
an unreachable target near stretched knees, damp the step) and the bounds the tighter of the
position limits (``limit_gain (q_min - q) <= dq <= limit_gain (q_max - q)``) and the velocity
limits (``|dq| <= dt v_max``). The constraints are all simple bounds, so the QP is solved only
when needed: the damped least-squares solution (one Cholesky solve) is kept when it lies
within the bounds, else DAQP (or any qpsolvers back-end) solves the box-constrained QP. A
failed QP never raises: the least-squares step clipped to the bounds (a feasible step) is
used and the result says so.
"""

import math
import time

import numpy as np
import pinocchio as pin
from scipy.linalg import lapack

from mpcwalk._checks import as_float
from mpcwalk.exceptions import ConfigurationError, SolverNotFound
from mpcwalk.ik.joint_bounds import JointBounds, solve_box_qp
from mpcwalk.ik.momentum_task import AngularMomentumTask
from mpcwalk.ik.targets import IKResult, IKTargets, IKWeights, TaskErrors
from mpcwalk.ik.tasks import ComTask, FrameTask, PostureTask, update_kinematics
from mpcwalk.ik.upper_body import upper_body_bodies, upper_body_inertia


class WholeBodyIK:
    """Differential IK of a floating-base humanoid (:class:`~mpcwalk.robot.robot.Robot`).

    Args:
        robot: The robot (its Pinocchio model; its ``q0`` is the posture reference).
        weights: Task weights.
        solver: QP back-end when a bound is active: ``"daqp"`` (called directly) or any
            installed qpsolvers name.
        qp_only_when_needed: Solve the QP only when the damped least-squares step violates a
            bound (the result is the same); False always solves the QP (for benchmarks).
        velocity_limit: Joint velocity limit [rad/s]: a float, one per actuated joint, or None
            for the model's limits (:data:`~mpcwalk.ik.joint_bounds.DEFAULT_VELOCITY_LIMIT` where
            it has none);
            ``np.inf`` disables it.
        limit_gain: Fraction of the distance to a position limit a step may cover, in (0, 1].
        gain: Task gain in (0, 1]: 1 reaches a reachable target in one step (to first order).
        damping: Tikhonov damping of every velocity coordinate [cost^2].
        lm_damping: Levenberg-Marquardt factor (unitless): the damping ``mu`` grows with the
            squared weighted error, which keeps the norm of every step ``dq`` below about
            ``1 / (2 sqrt(lm_damping))`` however singular the Jacobian (stretched knees;
            exactly so without feed-forward and posture terms).
        torso_frame: Frame kept at the torso orientation (default: the robot's).
        posture_reference: Posture reference, shape (nq,) (default: ``robot.q0``).
        upright_pelvis: Also keep the floating base (the pelvis) at its nominal orientation
            relative to the torso frame, where joints (a waist) lie between them: the trunk
            moves as one rigid body, as on paper M's robot. Without a waist the torso task
            already does, and no task is added.

    Raises:
        FrameNotFound: ``torso_frame`` or a sole frame does not exist.
        SolverNotFound: ``solver`` is not installed.
        ConfigurationError: A parameter is out of range or has the wrong shape.
    """

    def __init__(
        self,
        robot,
        *,
        weights: IKWeights = IKWeights(),
        solver: str = "daqp",
        qp_only_when_needed: bool = True,
        velocity_limit: float | np.ndarray | None = None,
        limit_gain: float = 0.5,
        gain: float = 1.0,
        damping: float = 1e-6,
        lm_damping: float = 1.0,
        torso_frame: str | None = None,
        posture_reference: np.ndarray | None = None,
        upright_pelvis: bool = False,
    ) -> None:
        if solver == "daqp":  # called directly: importing qpsolvers (and its back-ends) is slow
            try:
                import daqp  # noqa: F401
            except ImportError:
                raise SolverNotFound("daqp", []) from None
        else:
            import qpsolvers

            if solver not in qpsolvers.available_solvers:
                raise SolverNotFound(solver, ["daqp", *qpsolvers.available_solvers])
        for name, value in (("limit_gain", limit_gain), ("gain", gain)):
            if not 0.0 < float(value) <= 1.0:
                raise ConfigurationError(f"{name} must be in (0, 1], got {value!r}.")
        if not (damping > 0.0 and lm_damping >= 0.0):
            raise ConfigurationError(
                f"damping must be > 0 and lm_damping >= 0, got {damping!r} and {lm_damping!r}."
            )
        model = robot.model
        self.robot, self.model, self.data = robot, model, model.createData()
        self.weights, self.solver, self.qp_only_when_needed = weights, solver, qp_only_when_needed
        self.limit_gain, self.gain = float(limit_gain), float(gain)
        self.damping, self.lm_damping = float(damping), float(lm_damping)
        left, right = robot.foot_frames
        self.com_task = ComTask(weights.com)
        self.left_task = FrameTask(
            model,
            left,
            position_weight=weights.sole_position,
            orientation_weight=weights.sole_orientation,
            name="left_sole",
        )
        self.right_task = FrameTask(
            model,
            right,
            position_weight=weights.sole_position,
            orientation_weight=weights.sole_orientation,
            name="right_sole",
        )
        self.torso_task = FrameTask(
            model,
            torso_frame or robot.torso_frame,
            position_weight=None,
            orientation_weight=weights.torso_orientation,
            name="torso",
        )
        reference = robot.q0 if posture_reference is None else posture_reference
        self.posture_task = PostureTask(model, weights.posture, reference)
        self.pelvis_task, self._pelvis_offset = _pelvis_task(
            robot, self.torso_task, weights.torso_orientation, upright_pelvis
        )
        tasks: list[ComTask | FrameTask] = [self.com_task, self.left_task, self.right_task]
        tasks += [self.torso_task] + ([self.pelvis_task] if self.pelvis_task else [])
        self.tasks = tuple(tasks)
        self._rows = np.cumsum([0] + [task.dimension for task in self.tasks])
        self._task_weights = np.concatenate([task.weights for task in self.tasks])
        self._task_weight_column = self._task_weights[:, None]
        self._error_starts = np.array([0, 3, 6, 9, 12, 15, 18])  # com, soles (p, R), torso
        self._blocks = [slice(self._rows[i], self._rows[i + 1]) for i in range(len(self.tasks))]
        self._A = np.zeros((self._rows[-1], model.nv))
        self._r = np.zeros(self._rows[-1])
        self._e = np.zeros(self._rows[-1])
        self.bounds = JointBounds(model, velocity_limit)
        nv_root = self.bounds.root_nv
        self._joint_slice = slice(nv_root, model.nv)
        self._posture_hessian = np.zeros(model.nv)
        self._posture_hessian[nv_root:] = self.posture_task.weights**2
        self.momentum_task: AngularMomentumTask | None = None  # made at its first target
        self._momentum_target: np.ndarray | None = None

    @property
    def velocity_limit(self) -> np.ndarray:
        """Joint velocity limits [rad/s], shape (nb_joints,)."""
        return self.bounds.velocity_limit

    def _check(self, q: np.ndarray, targets: IKTargets, dt: float) -> tuple[np.ndarray, float]:
        if not isinstance(targets, IKTargets):
            raise ConfigurationError(
                f"targets must be an IKTargets, got {type(targets).__name__}; build one with "
                "IKTargets(com, left_sole, right_sole, torso_rotation)."
            )
        q = np.asarray(q, dtype=float)
        if q.shape != (self.model.nq,) or not np.isfinite(q).all():
            raise ConfigurationError(
                f"q must be {self.model.nq} finite numbers (robot '{self.robot.name}'), got "
                f"shape {q.shape}."
            )
        dt = as_float(dt)
        if not (math.isfinite(dt) and dt > 0.0):
            raise ConfigurationError(f"dt must be a positive number of seconds, got {dt!r}.")
        return q, dt

    def _set_targets(self, targets: IKTargets) -> None:
        # IKTargets are checked when built (or trusted by construction): no checks here
        self.com_task.set_checked_target(targets.com, targets.com_velocity)
        self.left_task.set_checked_target(targets.left_sole, targets.left_sole_velocity)
        self.right_task.set_checked_target(targets.right_sole, targets.right_sole_velocity)
        angular = targets.torso_angular_velocity
        velocity = None if angular is None else np.concatenate([np.zeros(3), angular])
        self.torso_task.set_checked_target(pin.SE3(targets.torso_rotation, np.zeros(3)), velocity)
        if self.pelvis_task is not None:
            rotation = targets.torso_rotation @ self._pelvis_offset
            self.pelvis_task.set_checked_target(pin.SE3(rotation, np.zeros(3)), velocity)
        self._momentum_target = targets.angular_momentum
        if self._momentum_target is not None and self.momentum_task is None:
            model, robot = self.model, self.robot
            bodies = upper_body_bodies(model, robot.hip_joints)
            rotational = upper_body_inertia(model, robot.q0, bodies).inertia
            self.momentum_task = AngularMomentumTask(
                (rotational[0, 0], rotational[1, 1]), self.weights.angular_momentum
            )

    def _errors(self, posture_error: np.ndarray) -> TaskErrors:
        e = self._e[: self._error_starts[-1]]  # the pelvis task's error is not reported
        norms = np.sqrt(np.add.reduceat(e * e, self._error_starts[:-1]))
        com, left_p, left_o, right_p, right_o, torso = norms.tolist()
        posture = math.sqrt(float(posture_error.dot(posture_error)))  # np.linalg.norm
        return TaskErrors(com, left_p, left_o, right_p, right_o, torso, posture)

    def _main_error(self) -> float:
        """Largest CoM/sole/torso error norm in ``self._e``, in [m] or [rad]."""
        e = self._e[: self._error_starts[-1]]
        return float(np.sqrt(np.add.reduceat(e * e, self._error_starts[:-1]).max()))

    def _build(self, q, dt, feedforward, limit_gain, velocity_bounds):
        """Fill the QP of one step at q: (H, c, lower, upper) on the actuated joints."""
        model, data, gain = self.model, self.data, self.gain
        update_kinematics(model, data, q)
        A, r, e = self._A, self._r, self._e
        for task, block in zip(self.tasks, self._blocks):
            e[block], A[block], feedforward_rate = task.compute_linearization(
                model, data, q, feedforward
            )
            if feedforward:
                r[block] = dt * feedforward_rate
        if feedforward:
            r -= gain * e
        else:
            np.multiply(e, -gain, out=r)
        weights = self._task_weights
        A *= self._task_weight_column
        r *= weights
        weighted_error = gain * weights * e
        mu = self.lm_damping * float(weighted_error @ weighted_error)
        posture_error = self.posture_task.compute_error(model, data, q)
        H = A.T @ A
        H.flat[:: model.nv + 1] += self._posture_hessian + (self.damping + mu)
        c = -(A.T @ r)
        c[self._joint_slice] += self._posture_hessian[self._joint_slice] * (gain * posture_error)
        if self._momentum_target is not None and self.momentum_task is not None:
            self.momentum_task.set_target(self._momentum_target)
            H_momentum, c_momentum = self.momentum_task.least_squares_terms(model, data, q, dt)
            H += H_momentum
            c += c_momentum
        lower, upper = self.bounds.compute(q, dt, limit_gain, velocity_bounds)
        return H, c, lower, upper, posture_error

    def _solve_qp(self, H, c, lower, upper) -> np.ndarray | None:
        return solve_box_qp(H, c, lower, upper, self.bounds.root_nv, self.solver)

    def _step(self, q, dt, feedforward, limit_gain, velocity_bounds, force_qp=False):
        """One step: returns (dq or None, status, used_qp, posture_error)."""
        H, c, lower, upper, posture_error = self._build(
            q, dt, feedforward, limit_gain, velocity_bounds
        )
        _, x, info = lapack.dposv(H, -c)
        finite = info == 0 and np.isfinite(x).all()
        joints = self._joint_slice
        if finite and not force_qp:
            xj = x[joints]
            if (xj >= lower).all() and (xj <= upper).all():
                return x, "unconstrained", False, posture_error
        solution = self._solve_qp(H, c, lower, upper)
        if solution is not None and np.isfinite(solution).all():
            solution[joints] = np.minimum(np.maximum(solution[joints], lower), upper)  # tolerances
            return solution, "qp", True, posture_error
        if finite:
            x[joints] = np.clip(x[joints], lower, upper)
            return x, "fallback", True, posture_error
        return None, "kept", True, posture_error

    def solve(self, q: np.ndarray, targets: IKTargets, dt: float) -> IKResult:
        """One IK step of a control tick (never raises on a solver failure).

        Args:
            q: Current configuration, shape (nq,).
            targets: References (see :class:`IKTargets` for the feed-forward velocities).
            dt: Control period, in [s].

        Returns:
            The next configuration, the velocity, the task errors at ``q``, the wall time.

        Raises:
            ConfigurationError: Wrong shapes or a non-positive ``dt``.
        """
        start = time.perf_counter()
        q, dt = self._check(q, targets, dt)
        self._set_targets(targets)
        x, status, used_qp, posture_error = self._step(
            q,
            dt,
            targets.has_velocities,
            self.limit_gain,
            True,
            force_qp=not self.qp_only_when_needed,
        )
        errors = self._errors(posture_error)
        if x is None:
            q_next, v = q.copy(), np.zeros(self.model.nv)
        else:
            q_next, v = pin.integrate(self.model, q, x), x / dt
        return IKResult(
            q_next,
            v,
            errors,
            time.perf_counter() - start,
            status in ("unconstrained", "qp"),
            status,
            1,
            int(used_qp),
        )

    def solve_pose(
        self,
        q: np.ndarray,
        targets: IKTargets,
        *,
        max_iterations: int = 200,
        tolerance: float = 1e-9,
    ) -> IKResult:
        """Iterate to convergence (offline use): full steps, position limits, no velocity
        limits.

        The first iterations pull the posture towards its reference; once the steps are
        small the posture term only damps the step (its reference follows q), so that the
        CoM, sole and torso errors converge to zero when the targets are reachable.

        Args:
            q: Initial configuration, shape (nq,).
            targets: References (velocities ignored).
            max_iterations: Maximum number of steps.
            tolerance: Largest CoM/sole/torso error accepted, in [m] and [rad].

        Returns:
            The final configuration (``q_next``), the errors there, ``success`` True when
            they are below ``tolerance``, ``v`` the total displacement (over 1 s).
        """
        start = time.perf_counter()
        q_start, _ = self._check(q, targets, 1.0)
        if int(max_iterations) < 1 or not float(tolerance) > 0.0:
            raise ConfigurationError(
                f"solve_pose needs max_iterations >= 1 and tolerance > 0, got {max_iterations!r} "
                f"and {tolerance!r}."
            )
        self._set_targets(targets)
        reference = self.posture_task.reference
        q_current, qp_solves, iterations, polishing = q_start.copy(), 0, 0, False
        try:
            for iterations in range(1, max_iterations + 1):
                if not polishing and iterations > max_iterations // 2:
                    polishing = True
                if polishing:
                    self.posture_task.set_target(self.model, q_current)
                x, _, used_qp, _ = self._step(q_current, 1.0, False, 1.0, False)
                if polishing and self._main_error() < 0.1 * tolerance:
                    break
                qp_solves += int(used_qp)
                if x is None:
                    break
                q_current = pin.integrate(self.model, q_current, x)
                if not polishing and float(np.abs(x).max()) < 1e-8:
                    polishing = True
        finally:
            self.posture_task.set_target(self.model, reference)
        errors = self.errors(q_current, targets)
        converged = max(errors.position_max, errors.orientation_max) < tolerance
        return IKResult(
            q_current,
            pin.difference(self.model, q_start, q_current),
            errors,
            time.perf_counter() - start,
            converged,
            "converged" if converged else "max_iterations",
            iterations,
            qp_solves,
        )

    def errors(self, q: np.ndarray, targets: IKTargets) -> TaskErrors:
        """Task errors of configuration ``q`` with respect to ``targets``."""
        q, _ = self._check(q, targets, 1.0)
        self._set_targets(targets)
        update_kinematics(self.model, self.data, q)
        for task, block in zip(self.tasks, self._blocks):
            self._e[block] = task.compute_error(self.model, self.data, q)
        return self._errors(self.posture_task.compute_error(self.model, self.data, q))


def _pelvis_task(
    robot, torso_task: FrameTask, weight: float, upright: bool
) -> tuple[FrameTask | None, np.ndarray]:
    """The orientation task of the floating base's body (None without ``upright`` or when
    the torso frame is fixed to that body) and the base's rotation relative to the torso
    frame in the nominal posture ``robot.q0``, shape (3, 3)."""
    model = robot.model
    torso_joint = model.frames[torso_task.frame_id].parentJoint
    if not upright or torso_joint <= 1:
        return None, np.eye(3)
    base = next(f.name for f in model.frames if f.parentJoint == 1 and f.type == pin.FrameType.BODY)
    data = model.createData()
    pin.framesForwardKinematics(model, data, robot.q0)
    offset = data.oMf[torso_task.frame_id].rotation.T @ data.oMf[model.getFrameId(base)].rotation
    task = FrameTask(model, base, position_weight=None, orientation_weight=weight, name="pelvis")
    return task, offset
