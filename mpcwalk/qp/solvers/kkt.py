"""Exact solve of an equality-constrained QP through its KKT system."""

import time
from typing import Any

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.qp.program import QuadraticProgram
from mpcwalk.qp.result import QPResult, kkt_residuals
from mpcwalk.qp.solvers.base import QPSolver, fixed_pattern


class KktSolver(QPSolver):
    """Exact solve of a QP without inequalities through its KKT system; the
    factorisation is kept until the matrices change."""

    name = "kkt"

    def __init__(self) -> None:
        self._key: tuple[int, int, int] | None = None
        self._factor: Any = None  # sparse LU or dense Cholesky factor of the last matrices

    def reset(self) -> None:
        self._key = self._factor = None

    def check(self, qp: QuadraticProgram) -> None:
        fixed_pattern(qp, self.name)
        if qp.m > qp.m_eq:
            raise ConfigurationError(
                "Solver 'kkt' solves QPs without inequality constraints only; build the "
                "QP with constrained=False or choose another solver (e.g. 'osqp-direct')."
            )

    def solve(self, qp: QuadraticProgram, *, shift: float = 0.0) -> QPResult:
        self.check(qp)
        program = fixed_pattern(qp, self.name)
        start = time.perf_counter()
        key = (id(program), program.P_version, program.A_version)
        if key != self._key:
            if program.m_eq:
                K = sp.bmat([[program.P, program.A.T], [program.A, None]], format="csc")
                self._factor = scipy.sparse.linalg.splu(K)
            else:
                self._factor = scipy.linalg.cho_factor(program.P.toarray())
            self._key = key
        if program.m_eq:
            sol = self._factor.solve(np.concatenate([-program.q, program.l]))
            x, y = sol[: program.n], sol[program.n :]
        else:
            x, y = scipy.linalg.cho_solve(self._factor, -program.q), np.zeros(0)
        elapsed = time.perf_counter() - start
        P, A = program.P, program.A
        primal, dual, gap = kkt_residuals(P, program.q, A, program.l, program.u, x, y)
        return QPResult(x, y, True, "solved", elapsed, 1, primal, dual, gap, self.name)
