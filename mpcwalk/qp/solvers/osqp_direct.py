"""Direct, warm-started OSQP back-end."""

import time

import numpy as np
import osqp

from mpcwalk.qp.program import FixedPatternProgram, QuadraticProgram
from mpcwalk.qp.result import QPResult
from mpcwalk.qp.solvers.base import QPSolver, fixed_pattern


class OsqpSolver(QPSolver):
    """OSQP set up once per QP; each tick only updates vectors.

    Each call pushes ``q``, ``l`` and ``u``, and the values of ``A``
    (``Ax``) only when the QP's ``A_version`` moved (the sparsity pattern is
    fixed, so OSQP keeps its setup and only refactors). A new ``P``
    (``P_version``; only with per-phase CoM
    weights) gets a new setup instead. The previous primal and dual
    solutions, shifted by the elapsed sampling periods, are the warm start.

    Args:
        eps_abs: Absolute tolerance.
        eps_rel: Relative tolerance.
        max_iter: Iteration limit.
        polish: Polish the solution (off: it costs a factorisation per tick).
        warm_start: Warm start from the shifted previous solution.
        check_termination: Iterations between convergence checks (OSQP's
            default of 25 is a floor on the iteration count once warm).
        adaptive_rho_interval: Iterations between step-size updates; OSQP's
            default (0) times its setup, so iteration counts would vary from
            run to run.
        settings: Other OSQP settings (e.g. ``rho=0.1``).
    """

    name = "osqp-direct"

    def __init__(
        self,
        *,
        eps_abs: float = 1e-5,
        eps_rel: float = 1e-5,
        max_iter: int = 4000,
        polish: bool = False,
        warm_start: bool = True,
        check_termination: int = 5,
        adaptive_rho_interval: int = 25,
        **settings,
    ) -> None:
        self.settings = dict(
            eps_abs=eps_abs,
            eps_rel=eps_rel,
            max_iter=max_iter,
            polishing=polish,
            check_termination=check_termination,
            adaptive_rho_interval=adaptive_rho_interval,
            verbose=False,
            **settings,
        )
        self.warm_start = warm_start
        self._solver: osqp.OSQP | None = None
        self._qp: FixedPatternProgram | None = None
        self._versions = (-1, -1)
        self._previous: tuple[np.ndarray, np.ndarray] | None = None

    def reset(self) -> None:
        self._solver = self._qp = self._previous = None

    def check(self, qp: QuadraticProgram) -> None:
        fixed_pattern(qp, self.name)

    def solve(self, program: QuadraticProgram, *, shift: float = 0.0) -> QPResult:
        qp = fixed_pattern(program, self.name)
        qp.require_update()
        start = time.perf_counter()
        versions = (qp.P_version, qp.A_version)
        if self._solver is None or self._qp is not qp or versions[0] != self._versions[0]:
            # A new P (per-phase CoM weights) gets a new setup: OSQP keeps the
            # scaling of its setup, and with weights switched on and off it
            # was seen to stall at the iteration limit.
            if self._qp is not qp:
                self._previous = None
            self._solver = osqp.OSQP()
            self._solver.setup(qp.P_upper, qp.q, qp.A, qp.l, qp.u, **self.settings)
            self._qp = qp
        else:
            update = dict(q=qp.q, l=qp.l, u=qp.u)
            if versions[1] != self._versions[1] and qp.m:
                update["Ax"] = qp.A_data
            self._solver.update(**update)
        self._versions = versions
        if self.warm_start and self._previous is not None:
            x_previous, y_previous = self._previous
            self._solver.warm_start(
                x=qp.shift_primal(x_previous, shift), y=qp.shift_dual(y_previous, shift)
            )
        elif self.warm_start:
            self._solver.warm_start(x=np.zeros(qp.n), y=np.zeros(qp.m))
        result = self._solver.solve(raise_error=False)
        elapsed = time.perf_counter() - start
        info = result.info
        success = info.status_val == osqp.SolverStatus.OSQP_SOLVED
        x = np.array(result.x) if success else None
        y = np.array(result.y) if success else None
        self._previous = (x, y) if x is not None and y is not None else None
        return QPResult(
            x=x,
            y=y,
            success=success,
            status=str(info.status),
            solve_time=elapsed,
            iterations=int(info.iter),
            primal_residual=float(info.prim_res) if success else np.inf,
            dual_residual=float(info.dual_res) if success else None,
            duality_gap=float(abs(info.duality_gap)) if success else None,
            solver=self.name,
        )
