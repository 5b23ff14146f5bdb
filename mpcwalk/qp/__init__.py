"""Walking MPC as a QP: parameters, construction (condensed and sparse) and
solver back-ends (qpsolvers, direct OSQP, CasADi)."""

from .parameters import MpcParameters
from .result import QPResult, kkt_residuals
from .solvers import KktSolver, QPSolver, QpsolversSolver, make_solver, solver_names
from .walking_qp import FORMULATIONS, Prediction, WalkingQP


def __getattr__(name: str):
    # Back-ends with heavier imports are loaded on first use.
    if name == "OsqpSolver":
        from .osqp_solver import OsqpSolver

        return OsqpSolver
    if name == "CasadiSolver":
        from .casadi_solver import CasadiSolver

        return CasadiSolver
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "CasadiSolver", "FORMULATIONS", "KktSolver", "MpcParameters", "OsqpSolver", "Prediction",
    "QPResult", "QPSolver", "QpsolversSolver", "WalkingQP", "kkt_residuals", "make_solver",
    "solver_names",
]
