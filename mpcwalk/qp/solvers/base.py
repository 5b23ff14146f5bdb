"""The interface of every QP back-end, and the checks they share."""

from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import cast

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.qp.program import FixedPatternProgram, QuadraticProgram
from mpcwalk.qp.result import QPResult, Residuals


class QPSolver(ABC):
    """A QP back-end bound to the walking QPs it solves (it may keep state, such as a
    factorisation or the previous solution for warm starts).

    Attributes:
        name: Back-end name, as given to :func:`~mpcwalk.qp.solvers.registry.make_solver`.
    """

    name: str = ""

    @abstractmethod
    def solve(self, qp: QuadraticProgram, *, shift: float = 0.0) -> QPResult:
        """Solve the QP as last updated.

        Args:
            qp: A walking QP (:class:`~mpcwalk.qp.program.QuadraticProgram`).
            shift: Sampling periods elapsed since the previous solve (the previous
                solution shifted by this much is the warm start).
        """

    def reset(self) -> None:
        """Forget warm-start data."""

    def check(self, qp: QuadraticProgram) -> None:
        """Raise ConfigurationError if this back-end cannot solve ``qp``'s class of
        problems (called once, before the first solve)."""


def fixed_pattern(qp: QuadraticProgram, solver: str) -> FixedPatternProgram:
    """``qp`` as a :class:`~mpcwalk.qp.program.FixedPatternProgram`, which back-ends that
    update the OSQP form in place (``osqp-direct``, CasADi, ``kkt``) need.

    Raises:
        ConfigurationError: ``qp`` rebuilds its matrices every tick (the footstep-adaptive
            MPC's dense QP); the message says to solve it through qpsolvers.
    """
    if not qp.fixed_pattern:
        raise ConfigurationError(
            f"Solver '{solver}' updates a QP with a fixed sparsity pattern in place (as "
            f"WalkingQP), but {type(qp).__name__} is dense and rebuilt every tick; solve it "
            "through qpsolvers instead (a name of qpsolvers.available_solvers, e.g. "
            "'quadprog' or 'daqp')."
        )
    return cast(FixedPatternProgram, qp)


def failure(name: str, status: str, elapsed: float) -> QPResult:
    """Result of a solve that gave no solution (``status`` says why; ``elapsed`` [s])."""
    return QPResult(None, None, False, status, elapsed, None, np.inf, None, None, name)


def found(
    name: str,
    x: np.ndarray,
    z: np.ndarray,
    elapsed: float,
    iterations: int,
    residuals: Residuals | Callable[[], Residuals],
) -> QPResult:
    """Result of a solve that found ``x`` with the multipliers ``z`` in ``elapsed`` [s],
    with its ``(primal, dual, gap)`` residuals, or the function that computes them when
    they are first read (:class:`~mpcwalk.qp.result.QPResult`)."""
    if callable(residuals):
        return QPResult(x, z, True, "found", elapsed, iterations, solver=name, residuals=residuals)
    primal, dual, gap = residuals
    return QPResult(x, z, True, "found", elapsed, iterations, primal, dual, gap, name)


def dense_residuals(P, q, G, h, x, z) -> tuple[float, float, float]:
    """Primal residual ``max(0, max(G x - h))``, dual residual ``||P x + q + G^T z||_inf``
    and duality gap ``|x'Px + q'x + h'z|`` of ``(x, z)`` for the dense QP
    ``min 1/2 x'Px + q'x, G x <= h``.

    ``G^T z`` is taken over the rows whose multiplier is not zero (an active-set solver's
    few binding rows: 1 to 3 of the footstep MPC's 268), the same sum without its zero
    terms."""
    Px = P @ x
    primal = float(max(0.0, np.max(G @ x - h))) if len(h) else 0.0
    return primal, dual_residual(Px + q, G, z), float(abs(x @ Px + q @ x + h @ z))


def dual_residual(gradient: np.ndarray, G: np.ndarray, z: np.ndarray) -> float:
    """``||gradient + G^T z||_inf``, the product over the rows of ``G`` whose multiplier in
    ``z`` is not zero."""
    binding = np.flatnonzero(z)
    if len(binding) < len(z):
        G, z = G.take(binding, axis=0), z.take(binding)
    return float(np.max(np.abs(gradient + z @ G)))
