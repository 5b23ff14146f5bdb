"""Walking MPC as a QP: parameters, construction (condensed and sparse) and
solver back-ends (qpsolvers, direct OSQP, CasADi)."""

from mpcwalk.qp.parameters import MpcParameters
from mpcwalk.qp.result import QPResult, kkt_residuals
from mpcwalk.qp.solvers.registry import (
    KktSolver,
    QPSolver,
    QpsolversSolver,
    make_solver,
    solver_names,
)
from mpcwalk.qp.walking_qp import FORMULATIONS, Prediction, WalkingQP


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
    "CasadiSolver",
    "KktSolver",
    "MpcParameters",
    "OsqpSolver",
    "Prediction",
    "QPResult",
    "QPSolver",
    "QpsolversSolver",
    "WalkingQP",
    "kkt_residuals",
    "make_solver",
    "solver_names",
]
