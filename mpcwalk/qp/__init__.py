"""Walking MPC as a QP: parameters, construction (condensed and sparse), the QP protocol
and solver back-ends (qpsolvers, direct OSQP, CasADi, KKT)."""

from mpcwalk.qp.parameters import MpcParameters
from mpcwalk.qp.program import FixedPatternProgram, Prediction, QuadraticProgram
from mpcwalk.qp.result import QPResult, kkt_residuals
from mpcwalk.qp.solvers import (
    SOLVERS,
    Backend,
    KktSolver,
    QPSolver,
    QpsolversSolver,
    backend_entry,
    make_solver,
    solver_names,
)
from mpcwalk.qp.walking_qp import FORMULATIONS, WalkingQP


def __getattr__(name: str):
    # Back-ends with heavier imports are loaded on first use.
    if name == "OsqpSolver":
        from mpcwalk.qp.solvers.osqp_direct import OsqpSolver

        return OsqpSolver
    if name == "CasadiSolver":
        from mpcwalk.qp.solvers.casadi_qp import CasadiSolver

        return CasadiSolver
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "FORMULATIONS",
    "SOLVERS",
    "Backend",
    "CasadiSolver",
    "FixedPatternProgram",
    "KktSolver",
    "MpcParameters",
    "OsqpSolver",
    "Prediction",
    "QPResult",
    "QPSolver",
    "QpsolversSolver",
    "QuadraticProgram",
    "WalkingQP",
    "backend_entry",
    "kkt_residuals",
    "make_solver",
    "solver_names",
]
