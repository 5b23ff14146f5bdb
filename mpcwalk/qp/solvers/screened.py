"""A dense QP solved on the rows that bind: constraint screening around quadprog.

The footstep-adaptive MPC's QP (:class:`~mpcwalk.qp.footstep_qp.FootstepQP`, and the hip
strategy's with its flywheel) has hundreds of rows (the ZMP in its support at every
constraint point, the reach of every footstep, the flywheel's bounds) of which one to three
bind at the optimum of a walking tick (measured over a 20-step walk: 268 rows, a median of 1
active; with the flywheel 420 rows, 2 active). An active-set solver such as quadprog pays for
every row at each of its iterations, active or not.

:class:`ScreenedSolver` solves the QP on a few rows (the ones nearest to binding at the
previous tick's solution; the slack of each row, in its own units), checks every row on that
solution, adds the rows it violates and solves again, until no row is violated. The cost is
strictly convex (``P`` positive definite), so the optimum is unique, and a point that is
optimal on a subset of the rows (its multipliers there) and satisfies the others is optimal
for the whole QP with zero multipliers on the rows left out (the KKT conditions hold): the
answer is quadprog's on the whole QP, up to round-off. The number of rounds is bounded by
the number of rows (each round adds at least one); a walking tick takes one or two.

The result's multipliers cover every row (zero on the rows never solved with), and its
residuals are the whole QP's.
"""

import functools
import time

import numpy as np
import quadprog

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.qp.cost_factor import inverse_cholesky
from mpcwalk.qp.program import QuadraticProgram
from mpcwalk.qp.result import QPResult, kkt_residuals
from mpcwalk.qp.solvers.base import QPSolver, failure

#: Rows taken into the first round: the nearest ones to binding at the predicted solution.
FIRST_ROWS = 8
#: A row is violated beyond this, relative to its right-hand side (at least 1 in its units).
VIOLATION_TOLERANCE = 1e-9


class ScreenedSolver(QPSolver):
    """quadprog on the rows near binding, rows added until none is violated (see the
    module's documentation).

    Only a dense QP with inequality rows and a positive definite ``P`` applies (the
    footstep-adaptive MPC's); it takes no settings.

    Args:
        first_rows: Rows of the first round (the nearest to binding at the predicted
            solution).
    """

    name = "quadprog-screened"

    def __init__(self, first_rows: int = FIRST_ROWS) -> None:
        if isinstance(first_rows, bool) or int(first_rows) != first_rows or first_rows < 0:
            raise ConfigurationError(
                f"Solver '{self.name}' takes first_rows, a non-negative integer (rows of "
                f"the first round), got {first_rows!r}."
            )
        self.first_rows = int(first_rows)
        self._previous: np.ndarray | None = None
        self._qp: QuadraticProgram | None = None
        self.rounds = 0
        """Rounds of the last solve (solves of a subset of the rows)."""

    def reset(self) -> None:
        self._previous = self._qp = None

    def check(self, qp: QuadraticProgram) -> None:
        if qp.formulation == "sparse" or qp.m_eq:
            raise ConfigurationError(
                f"Solver '{self.name}' solves dense QPs with a positive definite cost matrix "
                "and inequality rows only (the footstep-adaptive MPC's); use 'quadprog' or "
                "'daqp' for this one."
            )

    @staticmethod
    def _factor(qp: QuadraticProgram, P: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """``(order, R_inv)``: the program's own factor of its cost when it offers one
        (``cost_factor()``, from its blocks), else ``P``'s Cholesky factor inverted; None for
        ``R_inv`` when ``P`` is not positive definite."""
        factor = getattr(qp, "cost_factor", None)
        try:
            if factor is not None:
                return factor()
            return np.arange(len(P)), inverse_cholesky(P)
        except np.linalg.LinAlgError:
            return np.arange(len(P)), None

    def solve(self, qp: QuadraticProgram, *, shift: float = 0.0) -> QPResult:
        self.check(qp)
        qp.require_update()
        P, q, G, h = qp.dense_arrays()
        start = time.perf_counter()
        m = len(h)
        tolerance = VIOLATION_TOLERANCE * np.maximum(1.0, np.abs(h))
        rows = np.zeros(0, dtype=int)
        if m and self._previous is not None and self._qp is qp and len(self._previous) == len(q):
            # the rows nearest to binding at the previous solution shifted to this tick
            slack = h - G @ qp.shift_primal(self._previous, shift)
            k = min(self.first_rows, m)
            if k:
                rows = np.sort(np.argpartition(slack, k - 1)[:k])
        self._qp = qp
        order, inverse = self._factor(qp, P)
        if inverse is None:
            self._previous = None
            return failure(self.name, "P is not positive definite", time.perf_counter() - start)
        q_ordered = -q[order]
        x = np.empty(len(q))
        lagrangian = np.zeros(0)
        self.rounds = iterations = 0
        while True:
            self.rounds += 1
            C = -G[np.ix_(rows, order)].T if len(rows) else None
            b = -h[rows] if len(rows) else None
            try:
                x_ordered, _, _, its, lagrangian, _ = quadprog.solve_qp(
                    inverse, q_ordered, C, b, 0, True
                )
            except ValueError as error:  # inconsistent rows
                self._previous = None
                return failure(self.name, f"error: {error}", time.perf_counter() - start)
            iterations += int(its[0])
            x[order] = x_ordered
            if not m:
                break
            violation = G @ x - h
            violated = np.flatnonzero(violation > tolerance)
            if not len(violated):
                break
            rows = np.union1d(rows, violated)
        elapsed = time.perf_counter() - start
        y = np.zeros(m)
        if len(rows):
            y[rows] = lagrangian
        self._previous = x
        lower = np.full(m, -np.inf)
        return QPResult(
            x=x,
            y=y,
            success=True,
            status="found",
            solve_time=elapsed,
            iterations=iterations,
            solver=self.name,
            residuals=functools.partial(kkt_residuals, P, q, G, lower, h, x, y),  # when read
        )


__all__ = ["FIRST_ROWS", "VIOLATION_TOLERANCE", "ScreenedSolver"]
