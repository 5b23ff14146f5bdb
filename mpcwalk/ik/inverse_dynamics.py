"""Whole-body inverse dynamics on Pinocchio: one QP per control tick gives the joint torques.

The variables are the generalised acceleration ``a`` (nv) and the wrench ``f_i`` (6, sole
frame) of each sole in contact; the joint torques are eliminated through the equations of
motion ``M(q) a + h(q, v) = S^T tau + sum_i J_i^T f_i``:

    minimise   sum_k w_k || J_k a + J_dot_k v - a*_k ||^2 + w_f sum_i ||f_i - f_i,ref||^2 / (m g)^2
               + eps ||a||^2
               (f_i towards the share w_i / sum w of the weight, along the sole's normal)
    subject to M_b a + h_b = sum_i J_i,b^T f_i                (floating base: 6 rows)
               J_i a + J_dot_i v = -k_c J_i v                  (each sole in contact stays)
               C_i f_i <= d_i                                  (contact wrench cone)
               -tau_max <= M_j a + h_j - sum_i J_i,j^T f_i <= tau_max   (torque limits)

where the tasks ``k`` are the CoM (the pattern generator's acceleration plus a PD on the
estimated CoM), the swing soles (PD on pose, feed-forward acceleration), the torso
orientation, the posture (PD to the IK's ``q_ref``) and the centroidal angular momentum
(damped to zero), each with ``a* = a_ref + kp e + kd (v_ref - v)``
(:class:`~mpcwalk.ik.dynamics_targets.DynamicsGains`). ``J_dot v`` comes from Pinocchio's
frame (classical) accelerations at zero joint acceleration and from the time variation of
the centroidal map. The cone (:mod:`mpcwalk.ik.contact_wrench`) keeps each normal force
unilateral and below ``w_i fz_max``: the load ``w_i`` of a sole ramps over a few ticks at
touch-down and lift-off, so the torques do not jump when the contacts switch. The QP goes to
a back-end of :mod:`mpcwalk.qp.solvers` (every one that takes equalities), warm-started from
the previous tick's solution when the contacts did not change.
"""

import time
from collections.abc import Mapping
from typing import Any, cast

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.contact_wrench import CONE_ROWS, cone_bounds
from mpcwalk.ik.delay_margin import delay_capped
from mpcwalk.ik.dynamics_program import DynamicsProgram
from mpcwalk.ik.dynamics_targets import (
    DynamicsGains,
    DynamicsResult,
    DynamicsTargets,
    DynamicsWeights,
)
from mpcwalk.ik.sole_support import ROCKING_RATE, SoleSupport
from mpcwalk.qp.program import FixedPatternProgram
from mpcwalk.qp.solvers.registry import make_solver

_LOCAL = pin.ReferenceFrame.LOCAL
_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def torque_limits(robot) -> np.ndarray:
    """Torque limit of each joint [N m], shape (nv - 6,): the servo's
    (:attr:`~mpcwalk.robot.robot.Robot.servo_gains`), else the model's effort limit where
    it has one (> 0), else inf."""
    limits = np.array(robot.servo_gains.torque_limit, dtype=float)
    effort = np.asarray(robot.model.effortLimit[6:], dtype=float)
    missing = ~np.isfinite(limits) & np.isfinite(effort) & (effort > 0.0)
    limits[missing] = effort[missing]
    return limits


class InverseDynamicsQP:
    """Whole-body inverse dynamics of a floating-base humanoid
    (:class:`~mpcwalk.robot.robot.Robot`), solved by a back-end of the solver registry.

    Args:
        robot: The robot (its Pinocchio model, sole frames and sizes, torque limits).
        solver: Name of a back-end of :data:`~mpcwalk.qp.solvers.registry.SOLVERS` that
            takes equality constraints (``"daqp"``, ``"quadprog"``, ``"proxqp"``, ``"osqp-direct"``...).
        solver_settings: Settings of that back-end.
        weights: Task weights.
        gains: PD gains of the tasks.
        friction: Friction coefficient of the ground (the pyramid is inscribed in its cone).
        cop_margin: Share in (0, 1] of the half sole the centre of pressure may reach.
        rocking_rate: Roll and pitch rate [rad/s] of a loaded sole above which its CoP's
            share shrinks (:class:`~mpcwalk.ik.sole_support.SoleSupport`; 0, the default: never).
        control_period: Time between two solves [s] (the share's recovery).
        max_normal_force: Largest normal force of a fully loaded sole [N] (default: three
            times the robot's weight).
        torque_limit: Joint torque limits [N m], one per joint or one for all (default:
            :func:`torque_limits`).
        torso_frame: Frame whose orientation is a task (default: the robot's).
        state_delay: Age [s] of the state the torques act on: the posture frequency is then
            capped to keep a 60 deg phase margin with the damping of the least damped joint
            (:func:`~mpcwalk.ik.delay_margin.delay_limited_frequency`: the joints shake
            one another through the body), those of the swing soles and the torso to keep
            :data:`~mpcwalk.ik.delay_margin.TASK_MARGIN`; None: the gains unchanged.

    Raises:
        SolverNotFound: ``solver`` is not installed.
        ConfigurationError: A back-end that cannot take this QP (``kkt`` takes
            no inequalities), or a parameter out of range.
    """

    def __init__(
        self,
        robot,
        *,
        solver: str = "daqp-direct",
        solver_settings: Mapping[str, Any] | None = None,
        weights: DynamicsWeights = DynamicsWeights(),
        gains: DynamicsGains = DynamicsGains(),
        friction: float = 0.7,
        cop_margin: float = 0.9,
        rocking_rate: float = ROCKING_RATE,
        control_period: float = 0.01,
        max_normal_force: float | None = None,
        torque_limit: float | np.ndarray | None = None,
        torso_frame: str | None = None,
        state_delay: float | None = None,
    ) -> None:
        model = robot.model
        self.robot, self.model, self.data = robot, model, model.createData()
        self.nv, self.nj = model.nv, model.nv - 6
        self.weights, self.gains = weights, gains
        self.mass = float(pin.computeTotalMass(model))
        self.weight = self.mass * float(np.linalg.norm(model.gravity.linear))
        self.support = SoleSupport(robot.sole_size, friction, cop_margin, rocking_rate=rocking_rate)
        self.control_period = control_period
        self.max_normal_force = 3.0 * self.weight if max_normal_force is None else max_normal_force
        if not (np.isfinite(self.max_normal_force) and self.max_normal_force > 0.0):
            raise ConfigurationError(f"max_normal_force must be > 0 [N], got {max_normal_force!r}.")
        limits = torque_limits(robot) if torque_limit is None else torque_limit
        self.torque_limit = np.broadcast_to(np.asarray(limits, dtype=float), (self.nj,)).copy()
        if np.any(~(self.torque_limit > 0.0)):
            raise ConfigurationError(
                f"torque limits must be > 0 [N m] (inf: none), got {self.torque_limit}."
            )
        self._limited = np.flatnonzero(np.isfinite(self.torque_limit))
        self.sole_ids = [robot.frame_id(frame) for frame in robot.foot_frames]
        self.torso_frame = torso_frame or robot.torso_frame
        self.torso_id = robot.frame_id(self.torso_frame)
        posture, swing, torso = float(gains.posture), float(gains.swing_foot), float(gains.torso)
        if state_delay is not None:  # damping rate b / M_jj at q0 of the least damped joint
            inertia = np.diag(pin.crba(model, self.data, robot.q0))[6:]
            rate = float(np.min(np.asarray(model.damping[6:], dtype=float) / inertia))
            posture, swing, torso = delay_capped((posture, swing, torso), rate, state_delay)
        self.posture_frequencies = np.full(self.nj, posture)
        """Natural frequency [rad/s] of each joint's posture PD, shape (nv - 6,)."""
        self.swing_frequency, self.torso_frequency = swing, torso
        """Natural frequencies [rad/s] of the swing soles' and the torso's PD."""
        self.solver_name = solver
        self.solver = make_solver(solver, **dict(solver_settings or {}))
        self._programs: dict[tuple[bool, bool], DynamicsProgram] = {}
        self._lower = np.tril_indices(self.nv, -1)
        self._torque_rows: dict[int, np.ndarray] = {}  # tau's rows, per program size
        self._contacts: tuple[bool, bool] | None = None
        self._torques = np.zeros(self.nj)
        self.program((True, True))  # the back-end's check, now

    def reset(self) -> None:
        """Forget the warm start and the held torques."""
        self.solver.reset()
        self.support.reset()
        self._contacts, self._torques = None, np.zeros(self.nj)

    def program(self, contacts: tuple[bool, bool]) -> DynamicsProgram:
        """The QP of a contact set (built once; the back-end checks it then)."""
        program = self._programs.get(contacts)
        if program is None:
            k = sum(contacts)
            program = DynamicsProgram(
                self.nv + 6 * k, 6 + 6 * k, CONE_ROWS * k + 2 * len(self._limited)
            )
            self.solver.check(cast(FixedPatternProgram, program))
            self._programs[contacts] = program
        return program

    def static_torques(self, q: np.ndarray) -> np.ndarray:
        """Joint torques [N m] that hold configuration ``q`` at rest on both soles (the QP of
        targets ``q`` reaches, the warm start left as it was)."""
        robot = self.robot
        left, right = robot.compute_sole_placements(q)
        zero = np.zeros(3)
        targets = DynamicsTargets(
            com=robot.compute_com(q),
            com_velocity=zero,
            com_acceleration=zero,
            left_sole=left,
            right_sole=right,
            torso_rotation=robot.compute_frame_placement(q, self.torso_frame).rotation,
            posture=q,
        )
        contacts, torques = self._contacts, self._torques
        result = self.solve(q, np.zeros(self.nv), targets)
        self._contacts = contacts
        if not result.success:
            self._torques = torques
        return result.torques

    # ------------------------------------------------------------------ kinematics
    def _kinematics(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Fill ``self.data`` at ``(q, v)``: returns the mass matrix and the nonlinear
        effects; frame Jacobians, classical accelerations at ``a = 0`` and the centroidal
        map and its time variation are then read from the data."""
        model, data = self.model, self.data
        M = pin.crba(model, data, q).copy()  # its upper triangle: mirror it
        M[self._lower] = M.T[self._lower]
        h = pin.nonLinearEffects(model, data, q, v).copy()
        pin.computeCentroidalMapTimeVariation(model, data, q, v)
        pin.forwardKinematics(model, data, q, v, np.zeros(self.nv))
        pin.computeJointJacobians(model, data)
        pin.updateFramePlacements(model, data)
        return M, h

    def _frame(self, frame_id: int, reference) -> tuple[np.ndarray, np.ndarray]:
        """Jacobian (6, nv) and drift ``J_dot v`` (6,) of a frame (classical acceleration)."""
        model, data = self.model, self.data
        jacobian = pin.getFrameJacobian(model, data, frame_id, reference)
        drift = pin.getFrameClassicalAcceleration(model, data, frame_id, reference).vector
        return jacobian, drift

    # ------------------------------------------------------------------ the QP
    def _tasks(self, q, v, targets: DynamicsTargets, contacts):
        """Rows ``(J, r, w)`` of the least-squares tasks ``w ||J a - r||^2``."""
        data, gains, weights = self.data, self.gains, self.weights
        rows = []
        Ag, dAg = data.Ag, data.dAg
        com_jacobian = Ag[:3] / self.mass
        com = data.com[0]
        com_velocity = com_jacobian @ v
        kp, kd = gains.pd(gains.com)
        desired = (
            targets.com_acceleration
            + kp * (targets.com - com)
            + kd * (targets.com_velocity - com_velocity)
        )
        rows.append((com_jacobian, desired - dAg[:3] @ v / self.mass, weights.com))
        kp, kd = gains.pd(self.swing_frequency)
        for i, frame_id in enumerate(self.sole_ids):
            if contacts[i]:
                continue
            jacobian, drift = self._frame(frame_id, _LWA)
            pose = data.oMf[frame_id]
            target = targets.soles[i]
            error = np.concatenate(
                [
                    target.translation - pose.translation,
                    pin.log3(target.rotation @ pose.rotation.T),
                ]
            )
            velocity = jacobian @ v
            desired = (
                targets.sole_accelerations[i]
                + kp * error
                + kd * (targets.sole_velocities[i] - velocity)
            )
            rows.append((jacobian, desired - drift, weights.swing_foot))
        jacobian, drift = self._frame(self.torso_id, _LWA)
        kp, kd = gains.pd(self.torso_frequency)
        rotation = data.oMf[self.torso_id].rotation
        error = pin.log3(targets.torso_rotation @ rotation.T)
        angular = jacobian[3:] @ v
        desired = kp * error + kd * (targets.torso_angular_velocity - angular)
        rows.append((jacobian[3:], desired - drift[3:], weights.torso))
        momentum = Ag[3:] @ v
        rows.append((Ag[3:], -gains.momentum * momentum - dAg[3:] @ v, weights.momentum))
        return rows

    def _posture(self, q, v, targets: DynamicsTargets) -> np.ndarray:
        """Desired joint accelerations of the posture task, shape (nj,)."""
        kp, kd = self.gains.pd(self.posture_frequencies)
        error = pin.difference(self.model, q, targets.posture)[6:]
        v_ref = targets.posture_velocity
        a_ref = targets.posture_acceleration
        desired = kp * error + kd * ((0.0 if v_ref is None else v_ref[6:]) - v[6:])
        return desired if a_ref is None else desired + a_ref[6:]

    def build(self, q: np.ndarray, v: np.ndarray, targets: DynamicsTargets):
        """Fill the QP of the tick at ``(q, v)`` (Pinocchio's convention, estimated state).

        Returns:
            The program, the contact set, the mass matrix, the nonlinear effects and the
            contact Jacobians (sole frames), for :meth:`solve` to recover the torques.
        """
        nv, nj = self.nv, self.nj
        contacts = (targets.contact_weights[0] > 0.0, targets.contact_weights[1] > 0.0)
        program = self.program(contacts)
        M, h = self._kinematics(q, v)
        n = program.n
        P = np.zeros((n, n))
        c = np.zeros(n)
        for J, r, w in self._tasks(q, v, targets, contacts):
            if w > 0.0:
                P[:nv, :nv] += w * J.T @ J
                c[:nv] -= w * J.T @ r
        w = self.weights.posture
        diagonal = P.reshape(-1)[:: n + 1]  # a view of P's diagonal
        diagonal[6:nv] += w
        c[6:nv] -= w * self._posture(q, v, targets)
        diagonal[:nv] += self.weights.acceleration
        diagonal[nv:] += self.weights.force / self.weight**2
        loads = [w for w, on in zip(targets.contact_weights, contacts) if on]
        for k, load in enumerate(loads):  # towards the share of the weight of its load
            share = load / sum(loads) * self.weight
            c[nv + 6 * k + 2] -= self.weights.force / self.weight**2 * share
        m_eq = program.m_eq
        A_eq, b_eq = np.zeros((m_eq, n)), np.zeros(m_eq)
        A_eq[:6, :nv], b_eq[:6] = M[:6], -h[:6]
        G = np.zeros((program.m - m_eq, n))
        h_ineq = np.zeros(program.m - m_eq)
        jacobians = []
        k = 0
        for i, frame_id in enumerate(self.sole_ids):
            if not contacts[i]:
                continue
            J, drift = self._frame(frame_id, _LOCAL)
            jacobians.append((i, k, J))
            columns = slice(nv + 6 * k, nv + 6 * k + 6)
            A_eq[:6, columns] = -J[:, :6].T
            A_eq[6 + 6 * k : 12 + 6 * k, :nv] = J
            b_eq[6 + 6 * k : 12 + 6 * k] = -drift - self.gains.contact * (J @ v)
            rows = slice(CONE_ROWS * k, CONE_ROWS * (k + 1))
            before = self._contacts is not None and self._contacts[i]
            rate = float(np.hypot(*(J[3:5] @ v))) if self.support.active else 0.0  # roll, pitch
            G[rows, columns] = self.support.cone(i, rate, not before, self.control_period)
            limit = targets.contact_weights[i] * self.max_normal_force
            h_ineq[rows] = cone_bounds(limit)
            k += 1
        limited = self._limited
        if len(limited):  # tau = M_j a + h_j - sum_i J_i,j^T f_i
            start = CONE_ROWS * k
            T = self._torque_rows.get(n)
            if T is None:
                T = self._torque_rows[n] = np.zeros((nj, n))
            T[:, :nv] = M[6:]
            for _, k_i, J in jacobians:
                T[:, nv + 6 * k_i : nv + 6 * k_i + 6] = -J[:, 6:].T
            rows_tau = T[limited]
            G[start : start + len(limited)] = rows_tau
            G[start + len(limited) :] = -rows_tau
            bound = self.torque_limit[limited]
            h_ineq[start : start + len(limited)] = bound - h[6:][limited]
            h_ineq[start + len(limited) :] = bound + h[6:][limited]
        program.update(P, c, A_eq, b_eq, G, h_ineq)
        return program, contacts, M, h, jacobians

    def solve(self, q: np.ndarray, v: np.ndarray, targets: DynamicsTargets) -> DynamicsResult:
        """Joint torques of one tick (never raises on a solver failure: the previous
        torques are kept and the result says so).

        Args:
            q: Estimated configuration, shape (nq,).
            v: Estimated velocity, shape (nv,).
            targets: The references of the tick.

        Raises:
            ConfigurationError: ``q`` or ``v`` of the wrong size or not finite.
        """
        start = time.perf_counter()
        q = np.asarray(q, dtype=float)
        v = np.asarray(v, dtype=float)
        if q.shape != (self.model.nq,) or v.shape != (self.nv,):
            raise ConfigurationError(
                f"q and v must have sizes nq = {self.model.nq} and nv = {self.nv}, got "
                f"shapes {q.shape} and {v.shape}."
            )
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v))):
            raise ConfigurationError("q and v must be finite (check the estimated state).")
        program, contacts, M, h, jacobians = self.build(q, v, targets)
        shift = 0.0 if contacts == self._contacts else 1.0
        result = self.solver.solve(cast(FixedPatternProgram, program), shift=shift)
        self._contacts = contacts
        wrenches = np.zeros((2, 6))
        x = result.x
        if not result.success or x is None or not np.all(np.isfinite(x)):
            self.solver.reset()
            return DynamicsResult(
                np.zeros(self.nv),
                self._torques.copy(),
                wrenches,
                contacts,
                False,
                result.status,
                time.perf_counter() - start,
                result.solve_time,
                np.inf,
                self.solver_name,
            )
        a = x[: self.nv]
        generalized = M @ a + h
        for i, k, J in jacobians:
            wrenches[i] = x[self.nv + 6 * k : self.nv + 6 * k + 6]
            generalized -= J.T @ wrenches[i]
        torques = np.clip(generalized[6:], -self.torque_limit, self.torque_limit)
        self._torques = torques
        return DynamicsResult(
            a.copy(),
            torques,
            wrenches,
            contacts,
            True,
            "solved",
            time.perf_counter() - start,
            result.solve_time,
            float(np.abs(generalized[:6]).max()),
            self.solver_name,
        )
