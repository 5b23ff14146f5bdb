"""QP solver back-ends (qpsolvers, direct warm-started OSQP, CasADi, KKT) behind one
registry (:mod:`mpcwalk.qp.solvers.registry`)."""

from mpcwalk.qp.solvers.base import QPSolver
from mpcwalk.qp.solvers.kkt import KktSolver
from mpcwalk.qp.solvers.qpsolvers_backend import QpsolversSolver
from mpcwalk.qp.solvers.registry import (
    SOLVERS,
    Backend,
    backend_entry,
    make_solver,
    solver_backend,
    solver_names,
    solver_registry,
)

__all__ = [
    "SOLVERS",
    "Backend",
    "KktSolver",
    "QPSolver",
    "QpsolversSolver",
    "backend_entry",
    "make_solver",
    "solver_backend",
    "solver_names",
    "solver_registry",
]
