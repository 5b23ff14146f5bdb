"""QP solver back-ends (qpsolvers, direct warm-started OSQP, CasADi, KKT) behind one
registry (:mod:`mpcwalk.qp.solvers.registry`)."""

from mpcwalk.qp.solvers.base import QPSolver
from mpcwalk.qp.solvers.kkt import KktSolver
from mpcwalk.qp.solvers.qpsolvers_backend import QpsolversSolver
from mpcwalk.qp.solvers.registry import (
    SOLVERS,
    SolverEntry,
    SolverRegistry,
    make_solver,
    solver_names,
)

__all__ = [
    "SOLVERS",
    "KktSolver",
    "QPSolver",
    "QpsolversSolver",
    "SolverEntry",
    "SolverRegistry",
    "make_solver",
    "solver_names",
]
