"""Inverse Cholesky factors of the walking QPs' cost matrices, built from their blocks.

An active-set solver such as quadprog (Goldfarb and Idnani) starts from ``R^-1``, the inverse
of the upper triangular Cholesky factor of the cost matrix ``P = R^T R``; given it, it skips
its own factorisation (the largest part of a solve on a QP with few binding rows).
:func:`inverse_cholesky` makes it for any positive definite matrix; when ``P`` is bordered,
``[[H_11, H_12], [H_21, H_22]]`` with ``H_11`` known in advance (the footstep MPC's jerks'
block depends on the first interval of the horizon alone) and ``H_22`` small (its footsteps),
:func:`bordered_inverse_factor` adds the border to the factor of ``H_11``.
"""

import numpy as np
from scipy.linalg import lapack


def inverse_cholesky(matrix: np.ndarray) -> np.ndarray:
    """``R^-1`` of the upper triangular Cholesky factor ``R`` of a symmetric positive
    definite ``matrix`` (``matrix = R^T R``), upper triangular.

    Raises:
        numpy.linalg.LinAlgError: ``matrix`` is not positive definite.
    """
    factor, info = lapack.dpotrf(matrix, lower=0)
    if info != 0:
        raise np.linalg.LinAlgError(f"The matrix is not positive definite (dpotrf info {info}).")
    inverse, info = lapack.dtrtri(factor, lower=0)
    if info != 0:  # pragma: no cover - a positive definite factor is invertible
        raise np.linalg.LinAlgError(f"The Cholesky factor is singular (dtrtri info {info}).")
    return np.triu(inverse)


def bordered_inverse_factor(inverse_11: np.ndarray, H: np.ndarray) -> np.ndarray:
    """``R^-1`` of ``H = R^T R`` from ``inverse_11``, the one of its leading block ``H_11``
    (:func:`inverse_cholesky`): ``R_12 = R_11^-T H_12``, ``R_22`` the Cholesky factor of
    ``H_22 - R_12^T R_12``, and ``R^-1 = [[R_11^-1, -R_11^-1 R_12 R_22^-1], [0, R_22^-1]]``.

    Raises:
        numpy.linalg.LinAlgError: ``H`` is not positive definite.
    """
    n = len(inverse_11)
    R_12 = inverse_11.T @ H[:n, n:]
    inverse_22 = inverse_cholesky(H[n:, n:] - R_12.T @ R_12)
    inverse = np.zeros(H.shape)
    inverse[:n, :n] = inverse_11
    inverse[:n, n:] = -(inverse_11 @ R_12) @ inverse_22
    inverse[n:, n:] = inverse_22
    return inverse


__all__ = ["bordered_inverse_factor", "inverse_cholesky"]
