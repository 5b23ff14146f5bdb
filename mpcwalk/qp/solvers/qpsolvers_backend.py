"""Every solver of ``qpsolvers`` as a back-end, through ``qpsolvers.solve_problem``."""

import time
import warnings

import numpy as np
import qpsolvers

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.qp.program import QuadraticProgram
from mpcwalk.qp.result import QPResult
from mpcwalk.qp.solvers.base import QPSolver, failure
from mpcwalk.qp.solvers.quadprog_dense import solve_dense_quadprog

#: qpsolvers back-ends that use the ``initvals`` warm start.
WARM_START_SOLVERS = frozenset({"osqp", "proxqp", "qpalm", "scs", "cvxopt"})
#: qpsolvers back-ends that need a positive definite P (not the sparse layout's).
DEFINITE_SOLVERS = frozenset({"quadprog", "daqp", "ecos", "pyqpmad", "qpax", "jaxopt_osqp"})


class QpsolversSolver(QPSolver):
    """Any solver of ``qpsolvers.available_solvers``.

    Args:
        name: qpsolvers name.
        settings: Forwarded to the solver (e.g. ``eps_abs=1e-6``).
    """

    def __init__(self, name: str, **settings) -> None:
        self.name = name
        self.settings = settings
        self.dense = name not in qpsolvers.sparse_solvers
        self._previous: np.ndarray | None = None
        if settings:
            self._check_settings()

    def _check_settings(self) -> None:
        """Refuse settings the back-end does not take, before the walk: they are tried on
        a one-variable QP (the back-ends raise on unknown keywords at their first solve)."""
        trial = qpsolvers.Problem(np.eye(1), np.zeros(1), lb=-np.ones(1), ub=np.ones(1))
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                qpsolvers.solve_problem(trial, self.name, **self.settings)
        except Exception as error:
            raise ConfigurationError(
                f"Solver '{self.name}' does not take the settings {self.settings!r}: "
                f"{type(error).__name__}: {error}; see the back-end's documentation for its "
                "options (qpsolvers passes them through)."
            ) from None

    def reset(self) -> None:
        self._previous = None

    def check(self, qp: QuadraticProgram) -> None:
        if qp.formulation == "sparse" and self.name in DEFINITE_SOLVERS:
            raise ConfigurationError(
                f"Solver '{self.name}' needs a positive definite cost matrix, but the "
                "sparse formulation's P is only semidefinite (states are not "
                "penalised in every direction); use formulation='dense' with it."
            )

    def solve(self, qp: QuadraticProgram, *, shift: float = 0.0) -> QPResult:
        self.check(qp)
        if (
            self.name == "quadprog"
            and not self.settings
            and getattr(qp, "plain_inequalities", False)
        ):
            # the call qpsolvers makes, on the same arrays, without its wrapping
            result = solve_dense_quadprog(*qp.dense_arrays(), name=self.name)
            self._previous = result.x
            return result
        problem = qp.problem(dense=self.dense)
        initvals = None
        if self._previous is not None and self.name in WARM_START_SOLVERS:
            initvals = qp.shift_primal(self._previous, shift)
        start = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                solution = qpsolvers.solve_problem(
                    problem, self.name, initvals=initvals, **self.settings
                )
            except (qpsolvers.QPError, ValueError, ArithmeticError) as error:
                return failure(self.name, f"error: {error}", time.perf_counter() - start)
        elapsed = time.perf_counter() - start
        found = bool(solution.found) and solution.x is not None
        self._previous = solution.x if found else None
        y = None  # OSQP-form dual: equalities, then inequalities
        has_y = qp.m_eq == 0 or solution.y is not None
        has_z = qp.m == qp.m_eq or solution.z is not None
        if found and has_y and has_z:
            parts: list[np.ndarray] = []
            if qp.m_eq and solution.y is not None:
                parts.append(solution.y)
            if qp.m > qp.m_eq and solution.z is not None:
                parts.append(solution.z)
            y = np.concatenate(parts) if parts else np.zeros(0)
        return QPResult(
            x=solution.x if found else None,
            y=y,
            success=found,
            status="found" if found else "not found",
            solve_time=elapsed,
            iterations=_iterations(solution.extras),
            primal_residual=solution.primal_residual(),
            dual_residual=solution.dual_residual() if y is not None else None,
            duality_gap=solution.duality_gap() if y is not None else None,
            solver=self.name,
        )


def _iterations(extras: dict) -> int | None:
    for key in ("iterations", "iter", "iter_count", "num_iterations"):
        value = extras.get(key)
        if value is not None:
            return int(np.ravel(value)[0])
    info = extras.get("info")
    for attr in ("iter", "iter_ext", "iterations"):
        if info is not None and getattr(info, attr, None) is not None:
            return int(getattr(info, attr))
    return None
