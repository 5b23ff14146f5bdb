"""Common result of every QP back-end, and KKT residuals in OSQP form."""

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from mpcwalk.qp.deferred import deferred_item

Residuals = tuple[float, float | None, float | None]
"""``(primal_residual, dual_residual, duality_gap)`` of a solution."""


@dataclass(frozen=True, init=False)
class QPResult:
    """What one QP solve returned.

    Attributes:
        x: Primal solution, shape (n,), or None when the solver gave none.
        y: Dual solution in OSQP form (one per row of ``A``: equalities then
            inequalities; positive when an upper bound is active), or None.
        success: Whether the back-end reports an optimal solution.
        status: The back-end's own status, as a string.
        solve_time: Wall time of the back-end call (matrix/vector updates
            included), in [s].
        iterations: Iterations reported by the back-end, None if unknown.
        primal_residual: ``max`` constraint violation, in the units of the
            constraints ([m] for ZMP/CoM rows); inf without a solution.
        dual_residual: ``||P x + q + A^T y||_inf``; None if no dual is known.
        duality_gap: ``|x^T P x + q^T x + u^T y+ - l^T y-|``; None if unknown.
        solver: Back-end name as given to :func:`make_solver`.

    The three residuals are given as numbers, or as ``residuals``: a function of no
    argument that returns them, called the first time one is read. A walk reads none of
    them (its checks are on the solution itself); the benchmarks and the tests do. Their
    products with the QP's matrices took about a sixth of the ``mpc`` tick (paired walks
    with and without reading them, median ratio 0.83). The function must compute them
    from arrays that no later tick changes in place.
    """

    x: np.ndarray | None
    y: np.ndarray | None
    success: bool
    status: str
    solve_time: float
    iterations: int | None
    solver: str
    _residuals: "Residuals | Callable[[], Residuals]" = field(repr=False, compare=False)

    def __init__(
        self,
        x: np.ndarray | None,
        y: np.ndarray | None,
        success: bool,
        status: str,
        solve_time: float,
        iterations: int | None,
        primal_residual: float = np.inf,
        dual_residual: float | None = None,
        duality_gap: float | None = None,
        solver: str = "",
        *,
        residuals: "Callable[[], Residuals] | None" = None,
        _residuals: "Residuals | Callable[[], Residuals] | None" = None,  # (replace's)
    ) -> None:
        held = residuals if residuals is not None else _residuals
        given = (primal_residual, dual_residual, duality_gap)
        self.__dict__.update(  # (frozen: the fields are set once, here)
            x=x,
            y=y,
            success=success,
            status=status,
            solve_time=solve_time,
            iterations=iterations,
            solver=solver,
            _residuals=given if held is None else held,
        )

    primal_residual = deferred_item("_residuals", 0, "``max`` constraint violation.")
    dual_residual = deferred_item("_residuals", 1, "``||P x + q + A^T y||_inf``, or None.")
    duality_gap = deferred_item("_residuals", 2, "The duality gap, or None.")


def kkt_residuals(
    P: sp.spmatrix,
    q: np.ndarray,
    A: sp.spmatrix,
    l: np.ndarray,
    u: np.ndarray,
    x: np.ndarray,
    y: np.ndarray | None,
) -> tuple[float, float | None, float | None]:
    """Primal residual, dual residual and duality gap of ``(x, y)`` for
    ``min 1/2 x'Px + q'x  s.t.  l <= Ax <= u`` (OSQP sign convention).

    Args:
        P: Full symmetric cost matrix, shape (n, n).
        q: Shape (n,).
        A: Shape (m, n).
        l, u: Shape (m,); infinite entries allowed.
        x: Primal point, shape (n,).
        y: Dual point, shape (m,), or None.

    Returns:
        ``(primal_residual, dual_residual, duality_gap)``; the last two are
        None when ``y`` is None.
    """
    Ax = A @ x
    primal = 0.0
    if len(Ax):
        primal = float(max(0.0, np.max(Ax - u), np.max(l - Ax)))
    if y is None:
        return primal, None, None
    Px = P @ x
    dual = float(np.linalg.norm(Px + q + A.T @ y, np.inf)) if len(x) else 0.0
    upper = np.where(np.isfinite(u), u, 0.0) @ np.maximum(y, 0.0)
    lower = np.where(np.isfinite(l), l, 0.0) @ np.minimum(y, 0.0)
    gap = float(abs(x @ Px + q @ x + upper + lower))
    return primal, dual, gap
