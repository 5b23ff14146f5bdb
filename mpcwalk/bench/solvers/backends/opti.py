"""The walking QP through CasADi's Opti modelling layer (benchmark back-end).

Opti is how many CasADi users write an MPC. Here the decision vector is one
Opti variable and every number of the QP is an Opti parameter: the nonzeros
of ``P`` and ``A`` (on the fixed sparsity patterns of
:class:`~mpcwalk.qp.program.FixedPatternProgram`), ``q``, ``l`` and ``u``. Each tick sets the
parameter values and calls ``Opti.solve``, so the time includes Opti's own
per-call work (``set_value``, argument assembly, the conic call through
qpOASES) on top of the solver. Building the Opti problem (symbols) is not
timed; the first solve of a new :class:`OptiSolver` is, and it includes
Opti's compilation of the problem (tens of milliseconds) besides qpOASES's
cold start. Like the CasADi conic plugin, qpOASES keeps its working set from
one call to the next, so later solves are hot-started.
"""

import time
from typing import Any

import numpy as np

from mpcwalk.qp.program import FixedPatternProgram, QuadraticProgram
from mpcwalk.qp.result import QPResult, kkt_residuals
from mpcwalk.qp.solvers.base import QPSolver, fixed_pattern

#: Bounds beyond this are infinite for qpOASES.
_INFINITY = 1e20


class OptiSolver(QPSolver):
    """Walking QP through ``casadi.Opti("conic")`` with the qpOASES plugin.

    Args:
        options: Extra options of the qpOASES plugin.
    """

    name = "casadi-opti"

    def __init__(self, **options) -> None:
        import casadi

        self._ca = casadi
        self.options = {"printLevel": "none", "error_on_fail": False, **options}
        self._previous: np.ndarray | None = None
        self._built: tuple[Any, FixedPatternProgram, dict] | None = None

    def reset(self) -> None:
        self._previous = None
        self._built = None

    def _build(self, qp: FixedPatternProgram) -> tuple[Any, dict]:
        if self._built is not None and self._built[1] is qp:
            return self._built[0], self._built[2]
        ca = self._ca

        def sparsity(pattern):
            return ca.Sparsity(
                pattern.shape[0],
                pattern.shape[1],
                pattern.indptr.tolist(),
                pattern.indices.tolist(),
            )

        opti = ca.Opti("conic")
        x = opti.variable(qp.n)
        sym = {
            "x": x,
            "q": opti.parameter(qp.n),
            "P": opti.parameter(len(qp.P_data)),
            "A": opti.parameter(len(qp.A_data)),
            "l": opti.parameter(qp.m),
            "u": opti.parameter(qp.m),
        }
        P = ca.MX(sparsity(qp.P_pattern), sym["P"])
        A = ca.MX(sparsity(qp.A_pattern), sym["A"])
        opti.minimize(0.5 * ca.bilin(P, x, x) + ca.dot(sym["q"], x))
        opti.subject_to(opti.bounded(sym["l"], A @ x, sym["u"]))
        opti.solver("qpoases", self.options)
        self._built = (opti, qp, sym)
        self._previous = None
        return opti, sym

    @staticmethod
    def _set(opti, sym: dict, qp: FixedPatternProgram) -> None:
        opti.set_value(sym["q"], qp.q)
        opti.set_value(sym["P"], qp.P_data)
        opti.set_value(sym["A"], qp.A_data)
        opti.set_value(sym["l"], np.maximum(qp.l, -_INFINITY))
        opti.set_value(sym["u"], np.minimum(qp.u, _INFINITY))

    def check(self, qp: QuadraticProgram) -> None:
        fixed_pattern(qp, self.name)

    def solve(self, program: QuadraticProgram, *, shift: float = 0.0) -> QPResult:
        qp = fixed_pattern(program, self.name)
        qp.require_update()
        opti, sym = self._build(qp)
        x0 = np.zeros(qp.n) if self._previous is None else qp.shift_primal(self._previous, shift)
        start = time.perf_counter()
        self._set(opti, sym, qp)
        opti.set_initial(sym["x"], x0)
        status = ""
        x: np.ndarray | None = None
        y: np.ndarray | None = None
        try:
            solution = opti.solve_limited()
            success = bool(opti.stats().get("success", False))
            status = str(opti.stats().get("return_status", ""))
            if success:
                x = np.asarray(solution.value(sym["x"]), dtype=float).ravel()
                y = np.asarray(solution.value(opti.lam_g), dtype=float).ravel()
        except RuntimeError as error:
            success, status = False, f"error: {str(error).splitlines()[-1][:120]}"
        elapsed = time.perf_counter() - start
        self._previous = x
        primal, dual, gap = np.inf, None, None
        if success and x is not None and y is not None:
            primal, dual, gap = kkt_residuals(qp.P, qp.q, qp.A, qp.l, qp.u, x, y)
        return QPResult(
            x=x,
            y=y,
            success=success,
            status=status,
            solve_time=elapsed,
            iterations=None,
            primal_residual=primal,
            dual_residual=dual,
            duality_gap=gap,
            solver=self.name,
        )
