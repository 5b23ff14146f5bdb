"""quadprog on a dense QP with inequality rows only, without the qpsolvers layer.

``qpsolvers.solve_problem(problem, "quadprog")`` hands ``quadprog.solve_qp`` the arrays
``(P, -q, -G^T, -h, 0)`` of a dense problem ``min 1/2 x'Px + q'x, G x <= h``, then wraps
the answer and computes its residuals. :func:`solve_dense_quadprog` makes the same call on
the same arrays (so the same solution, bit for bit) and the same residuals (to rounding:
the dual one sums over the binding rows only), without building the problem and solution
objects of qpsolvers around them, which cost a third of the solve on the footstep-adaptive
MPC's QP (74 columns, 268 rows).
"""

import functools
import time

import numpy as np
import quadprog

from mpcwalk.qp.result import QPResult
from mpcwalk.qp.solvers.base import dense_residuals, failure, found


def solve_dense_quadprog(
    P: np.ndarray, q: np.ndarray, G: np.ndarray, h: np.ndarray, name: str = "quadprog"
) -> QPResult:
    """Solve ``min 1/2 x'Px + q'x  s.t.  G x <= h`` with quadprog, as qpsolvers does.

    Args:
        P: Positive definite cost matrix, shape (n, n) (quadprog reads its lower part).
        q: Shape (n,).
        G: Shape (m, n).
        h: Shape (m,).
        name: Back-end name given to the result.

    Returns:
        The result, with qpsolvers' residuals (primal ``max(0, max(G x - h))``, dual
        ``||P x + q + G^T z||_inf``, gap ``|x'Px + q'x + h'z|``) and multipliers ``z >= 0``
        (positive on the binding rows); a failed result when quadprog finds no solution or
        ``P`` is not positive definite.
    """
    start = time.perf_counter()
    try:
        x, _, _, iterations, z, _ = quadprog.solve_qp(P, -q, -G.T, -h, 0)
    except ValueError as error:
        elapsed = time.perf_counter() - start
        message = str(error)
        if "matrix G is not positive definite" in message:
            return failure(name, "error: matrix P is not positive definite", elapsed)
        return failure(name, "not found", elapsed)
    elapsed = time.perf_counter() - start
    residuals = functools.partial(dense_residuals, P, q, G, h, x, z)  # computed when read
    return found(name, x, z, elapsed, int(np.ravel(iterations)[0]), residuals)


__all__ = ["solve_dense_quadprog"]
