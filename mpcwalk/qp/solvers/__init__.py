"""QP solver back-ends: qpsolvers, direct warm-started OSQP, CasADi."""

from mpcwalk.qp.solvers.registry import (
    KktSolver,
    QPSolver,
    QpsolversSolver,
    make_solver,
    solver_names,
)

__all__ = ["KktSolver", "QPSolver", "QpsolversSolver", "make_solver", "solver_names"]
