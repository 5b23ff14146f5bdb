"""QP back-ends chosen by a string, all returning a :class:`QPResult`.

Names:

- ``"osqp-direct"``: OSQP set up once, then vector updates and a warm start
  from the shifted previous solution (:class:`OsqpSolver`);
- ``"casadi"`` (= ``"casadi-qpoases"``) and ``"casadi-<plugin>"``: CasADi's
  conic interface (:class:`CasadiSolver`);
- ``"kkt"``: one linear solve of the KKT system, for QPs without inequalities
  (``constrained=False``), exact up to round-off;
- any name of ``qpsolvers.available_solvers`` (``"daqp"``, ``"proxqp"``,
  ``"quadprog"``, ``"clarabel"``...): through ``qpsolvers.solve_problem``.
"""

import time
import warnings
from abc import ABC, abstractmethod

import numpy as np
import qpsolvers
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg

from mpcwalk.exceptions import ConfigurationError, SolverNotFound
from mpcwalk.qp.result import QPResult, kkt_residuals
from mpcwalk.qp.walking_qp import WalkingQP

#: qpsolvers back-ends that use the ``initvals`` warm start.
WARM_START_SOLVERS = frozenset({"osqp", "proxqp", "qpalm", "scs", "cvxopt"})
#: qpsolvers back-ends that need a positive definite P (not the sparse layout's).
DEFINITE_SOLVERS = frozenset({"quadprog", "daqp", "ecos", "pyqpmad", "qpax", "jaxopt_osqp"})


class QPSolver(ABC):
    """A QP back-end bound to the walking QPs it solves (it may keep state,
    such as a factorisation or the previous solution for warm starts)."""

    name: str = ""

    @abstractmethod
    def solve(self, qp: WalkingQP, *, shift: float = 0.0) -> QPResult:
        """Solve the QP as last updated.

        Args:
            qp: The walking QP.
            shift: Sampling periods elapsed since the previous solve (the
                previous solution shifted by this much is the warm start).
        """

    def reset(self) -> None:
        """Forget warm-start data."""

    def check(self, qp: WalkingQP) -> None:
        """Raise ConfigurationError if this back-end cannot solve ``qp``'s class
        of problems (called once, before the first solve)."""


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

    def reset(self) -> None:
        self._previous = None

    def check(self, qp: WalkingQP) -> None:
        if qp.formulation == "sparse" and self.name in DEFINITE_SOLVERS:
            raise ConfigurationError(
                f"Solver '{self.name}' needs a positive definite cost matrix, but the "
                "sparse formulation's P is only semidefinite (states are not "
                "penalised in every direction); use formulation='dense' with it."
            )

    def solve(self, qp: WalkingQP, *, shift: float = 0.0) -> QPResult:
        self.check(qp)
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
                return _failure(self.name, f"error: {error}", time.perf_counter() - start)
        elapsed = time.perf_counter() - start
        found = bool(solution.found) and solution.x is not None
        self._previous = solution.x if found else None
        y = None  # OSQP-form dual: equalities, then inequalities
        has_y = qp.m_eq == 0 or solution.y is not None
        has_z = qp.m == qp.m_eq or solution.z is not None
        if found and has_y and has_z:
            parts = ([solution.y] if qp.m_eq else []) + ([solution.z] if qp.m > qp.m_eq else [])
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


class KktSolver(QPSolver):
    """Exact solve of a QP without inequalities through its KKT system; the
    factorisation is kept until the matrices change."""

    name = "kkt"

    def __init__(self) -> None:
        self._key = None
        self._factor = None

    def reset(self) -> None:
        self._key = self._factor = None

    def check(self, qp: WalkingQP) -> None:
        if qp.m > qp.m_eq:
            raise ConfigurationError(
                "Solver 'kkt' solves QPs without inequality constraints only; build the "
                "QP with constrained=False or choose another solver (e.g. 'osqp-direct')."
            )

    def solve(self, qp: WalkingQP, *, shift: float = 0.0) -> QPResult:
        self.check(qp)
        start = time.perf_counter()
        key = (id(qp), qp.P_version, qp.A_version)
        if key != self._key:
            if qp.m_eq:
                K = sp.bmat([[qp.P, qp.A.T], [qp.A, None]], format="csc")
                self._factor = scipy.sparse.linalg.splu(K)
            else:
                self._factor = scipy.linalg.cho_factor(qp.P.toarray())
            self._key = key
        if qp.m_eq:
            sol = self._factor.solve(np.concatenate([-qp.q, qp.l]))
            x, y = sol[: qp.n], sol[qp.n :]
        else:
            x, y = scipy.linalg.cho_solve(self._factor, -qp.q), np.zeros(0)
        elapsed = time.perf_counter() - start
        primal, dual, gap = kkt_residuals(qp.P, qp.q, qp.A, qp.l, qp.u, x, y)
        return QPResult(x, y, True, "solved", elapsed, 1, primal, dual, gap, self.name)


def _failure(name: str, status: str, elapsed: float) -> QPResult:
    return QPResult(None, None, False, status, elapsed, None, np.inf, None, None, name)


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


def solver_names() -> list[str]:
    """Names accepted by :func:`make_solver` on this installation."""
    from mpcwalk.qp.solvers.casadi_qp import available_plugins

    casadi = [f"casadi-{p}" for p in available_plugins()]
    return (
        ["osqp-direct", "kkt"]
        + (["casadi"] + casadi if casadi else [])
        + list(qpsolvers.available_solvers)
    )


def make_solver(name: str, **settings) -> QPSolver:
    """Back-end called ``name`` (see the module docstring).

    Raises:
        SolverNotFound: Unknown or uninstalled solver; the message lists the
            available ones.
    """
    if name == "osqp-direct":
        from mpcwalk.qp.solvers.osqp_direct import OsqpSolver

        return OsqpSolver(**settings)
    if name == "kkt":
        if settings:
            raise ConfigurationError(
                f"Solver 'kkt' takes no settings, got {', '.join(sorted(settings))}."
            )
        return KktSolver()
    if name == "casadi" or name.startswith("casadi-"):
        from mpcwalk.qp.solvers.casadi_qp import CasadiSolver, available_plugins

        plugin = "qpoases" if name == "casadi" else name[len("casadi-") :]
        if plugin not in available_plugins():
            raise SolverNotFound(name, solver_names())
        return CasadiSolver(plugin, **settings)
    if name in qpsolvers.available_solvers:
        return QpsolversSolver(name, **settings)
    raise SolverNotFound(name, solver_names())
