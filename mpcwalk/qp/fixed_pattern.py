"""Sparse matrices whose sparsity pattern never changes.

OSQP (and CasADi) can only update the values of a matrix whose pattern is the
one given at setup. :class:`FixedPattern` stores the pattern as coordinate
lists once; the values are then computed in that coordinate order (vectorised
numpy) and permuted into compressed-column order. Entries whose value happens
to be zero stay in the pattern as explicit zeros.
"""

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp


class FixedPattern:
    """Compressed-column sparsity pattern built from coordinate lists.

    Args:
        rows: Row index of each entry, shape (nnz,).
        cols: Column index of each entry, shape (nnz,); no (row, col) pair
            may appear twice.
        shape: ``(nb_rows, nb_cols)``.
    """

    def __init__(self, rows: np.ndarray, cols: np.ndarray, shape: tuple[int, int]) -> None:
        rows = np.asarray(rows, dtype=np.int64).ravel()
        cols = np.asarray(cols, dtype=np.int64).ravel()
        self.shape = (int(shape[0]), int(shape[1]))
        self.order = np.lexsort((rows, cols))
        """Permutation from coordinate order to compressed-column order."""
        self.rows = rows
        self.cols = cols
        self.indices = rows[self.order].astype(np.int32)
        self.indptr = np.zeros(self.shape[1] + 1, dtype=np.int32)
        np.cumsum(np.bincount(cols, minlength=self.shape[1]), out=self.indptr[1:])
        keys = rows[self.order] * self.shape[1] + cols[self.order]
        if len(keys) > 1 and np.any(np.diff(np.sort(keys)) == 0):
            raise ValueError("FixedPattern: duplicate (row, col) entries")
        self.flat = keys
        """Position of each entry (compressed-column order) in the row-major dense array."""

    @property
    def nnz(self) -> int:
        """Number of stored entries (explicit zeros included)."""
        return len(self.indices)

    def data(self, values: np.ndarray) -> np.ndarray:
        """Values given in coordinate order, returned in compressed-column order."""
        return np.asarray(values, dtype=float).ravel()[self.order]

    def matrix(self, data: np.ndarray) -> sp.csc_matrix:
        """CSC matrix from values already in compressed-column order.

        The matrix owns copies of the arrays: some solvers edit their input
        in place (qpsolvers' ``sip`` interface calls ``eliminate_zeros``),
        which would otherwise corrupt this pattern and the caller's values.
        """
        return sp.csc_matrix(
            (np.array(data, dtype=float), self.indices.copy(), self.indptr.copy()),
            shape=self.shape,
        )

    def dense(self, data: np.ndarray) -> np.ndarray:
        """Dense array from values in compressed-column order."""
        out = np.zeros(self.shape)
        out.ravel()[self.flat] = data
        return out

    def subset(self, keep: np.ndarray, row_offset: int = 0, nb_rows: int = -1) -> "SubPattern":
        """Entries flagged by ``keep`` (boolean, CSC order) as a pattern of their own.

        Args:
            keep: Shape (nnz,), in compressed-column order.
            row_offset: Subtracted from the row indices of the kept entries.
            nb_rows: Row count of the sub-pattern (default: same as this one).
        """
        return SubPattern(self, keep, row_offset, self.shape[0] if nb_rows < 0 else nb_rows)

    def row_slice(self, start: int, stop: int) -> "SubPattern":
        """Rows ``start:stop`` (e.g. the inequalities only)."""
        rows = self.indices
        return self.subset((rows >= start) & (rows < stop), start, stop - start)

    def upper_triangle(self) -> "SubPattern":
        """Entries on or above the diagonal (the P that OSQP expects)."""
        cols = np.repeat(np.arange(self.shape[1]), np.diff(self.indptr))
        return self.subset(self.indices <= cols)


class SubPattern:
    """Part of a :class:`FixedPattern`, with its own compressed-column layout."""

    def __init__(
        self, parent: FixedPattern, keep: np.ndarray, row_offset: int, nb_rows: int
    ) -> None:
        rows = parent.indices.astype(np.int64)
        cols = np.repeat(np.arange(parent.shape[1]), np.diff(parent.indptr))
        self.selection = np.flatnonzero(keep)
        """Positions, in the parent's CSC data, of the kept entries."""
        # A subset of CSC-ordered entries is still in CSC order, so the
        # sub-pattern's permutation is the identity.
        self.pattern = FixedPattern(
            rows[self.selection] - row_offset, cols[self.selection], (nb_rows, parent.shape[1])
        )

    def data(self, parent_data: np.ndarray) -> np.ndarray:
        """CSC data of the sub-pattern from the parent's CSC data."""
        return parent_data[self.selection]

    def matrix(self, parent_data: np.ndarray) -> sp.csc_matrix:
        """CSC matrix from the parent's CSC data."""
        return self.pattern.matrix(self.data(parent_data))

    def dense(self, parent_data: np.ndarray) -> np.ndarray:
        """Dense array from the parent's CSC data."""
        return self.pattern.dense(self.data(parent_data))


def stack_patterns(
    blocks: Sequence[tuple[np.ndarray, np.ndarray]],
) -> tuple[np.ndarray, np.ndarray]:
    """Concatenate coordinate lists ``[(rows, cols), ...]``."""
    if not blocks:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    rows = np.concatenate([np.asarray(r, dtype=np.int64).ravel() for r, _ in blocks])
    cols = np.concatenate([np.asarray(c, dtype=np.int64).ravel() for _, c in blocks])
    return rows, cols
