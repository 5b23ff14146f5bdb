"""The inverse-dynamics QP in the forms the back-ends of :mod:`mpcwalk.qp.solvers` read.

The walking QPs of :mod:`mpcwalk.qp` answer
:class:`~mpcwalk.qp.program.FixedPatternProgram`; :class:`DynamicsProgram` answers the part
of it the back-ends call (the qpsolvers form ``min 1/2 x'Px + q'x, G x <= h, A x = b``, the
OSQP form ``l <= A x <= u`` with equalities first, dense sparsity patterns and version
counters) for a dense QP whose values change every tick. Its shape is fixed by the contact
set (which soles carry a wrench), so the inverse dynamics keeps one program per contact set:
a back-end set up for one is set up again when the contacts change.

:func:`dynamics_solver_names` lists the back-ends of the registry that take such a program
(equalities and inequalities) and :func:`check_dynamics_solver` refuses any other name.
"""

import numpy as np
import qpsolvers
import scipy.sparse as sp

from mpcwalk.exceptions import ConfigurationError, NotReset
from mpcwalk.qp.fixed_pattern import FixedPattern
from mpcwalk.qp.solvers.registry import solver_names

#: Back-ends of the registry that cannot take the inverse dynamics' QP (``kkt``: no
#: inequality rows).
NO_INEQUALITIES = frozenset({"kkt"})
#: Back-ends of the registry that take inequality rows only (``quadprog-screened``, for the
#: footstep-adaptive MPCs), not the inverse dynamics' equalities.
INEQUALITIES_ONLY = frozenset({"quadprog-screened"})
#: The back-end of the inverse dynamics unless one is chosen.
DEFAULT_DYNAMICS_SOLVER = "daqp-direct"


def dynamics_solver_names() -> list[str]:
    """Back-ends of :data:`~mpcwalk.qp.solvers.registry.SOLVERS` installed here that take
    the inverse dynamics' QP (equality and inequality rows), in the registry's order."""
    return [name for name in solver_names() if name not in NO_INEQUALITIES | INEQUALITIES_ONLY]


def check_dynamics_solver(name: object) -> str:
    """``name`` if it is one of :func:`dynamics_solver_names`.

    Raises:
        ConfigurationError: Any other value; the message lists the choices.
    """
    choices = dynamics_solver_names()
    if not isinstance(name, str) or name not in choices:
        raise ConfigurationError(
            f"dynamics_solver must be a QP back-end that takes equality and inequality "
            f"constraints, got {name!r}; the choices on this installation are "
            f"{', '.join(choices)} (default {DEFAULT_DYNAMICS_SOLVER!r}; mpcwalk solvers "
            "lists them with their install hints)."
        )
    return name


def _dense_pattern(nb_rows: int, nb_cols: int, upper: bool = False) -> FixedPattern:
    rows, cols = np.meshgrid(np.arange(nb_rows), np.arange(nb_cols), indexing="ij")
    keep = rows <= cols if upper else np.ones_like(rows, dtype=bool)
    return FixedPattern(rows[keep], cols[keep], (nb_rows, nb_cols))


class DynamicsProgram:
    """A dense QP of fixed size: ``n`` variables, ``m_eq`` equalities, ``m - m_eq``
    one-sided inequalities, all values rewritten by :meth:`update`.

    Args:
        n: Number of variables.
        m_eq: Number of equality rows.
        m_ineq: Number of inequality rows.
    """

    formulation = "dense"
    fixed_pattern = True
    N = 0
    x0 = None
    sample_times = np.zeros(0)

    def __init__(self, n: int, m_eq: int, m_ineq: int) -> None:
        self.n, self.m_eq, self.m = int(n), int(m_eq), int(m_eq + m_ineq)
        self.P_pattern = _dense_pattern(self.n, self.n)
        self._P_upper_pattern = _dense_pattern(self.n, self.n, upper=True)
        self.A_pattern = _dense_pattern(self.m, self.n)
        self.P_version = self.A_version = 0
        self._updated = False
        self.P_dense = np.zeros((self.n, self.n))
        self.q = np.zeros(self.n)
        self.A_dense = np.zeros((self.m, self.n))
        self.l = np.zeros(self.m)
        self.u = np.zeros(self.m)

    def update(
        self,
        P: np.ndarray,
        q: np.ndarray,
        A_eq: np.ndarray,
        b_eq: np.ndarray,
        G: np.ndarray,
        h: np.ndarray,
    ) -> None:
        """Rewrite every value: cost ``(P, q)``, equalities ``A_eq x = b_eq``, inequalities
        ``G x <= h`` (shapes of the program's size)."""
        self.P_dense, self.q = P, q
        self.A_dense[: self.m_eq] = A_eq
        self.A_dense[self.m_eq :] = G
        self.l[: self.m_eq] = b_eq
        self.u[: self.m_eq] = b_eq
        self.l[self.m_eq :] = -np.inf
        self.u[self.m_eq :] = h
        self.P_version += 1
        self.A_version += 1
        self._updated = True

    def require_update(self) -> None:
        """Raise NotReset before the first :meth:`update`."""
        if not self._updated:
            raise NotReset("The inverse-dynamics QP is solved before it was built.")

    # ------------------------------------------------------------------ qpsolvers form
    def problem(self, dense: bool = True) -> qpsolvers.Problem:
        """The QP in qpsolvers form (dense arrays, or CSC matrices for sparse solvers)."""
        A, G = self.A_dense[: self.m_eq], self.A_dense[self.m_eq :]
        b, h = self.l[: self.m_eq].copy(), self.u[self.m_eq :].copy()
        P = self.P_dense
        if not dense:
            P, A, G = sp.csc_matrix(P), sp.csc_matrix(A), sp.csc_matrix(G)
        has_eq, has_ineq = self.m_eq > 0, self.m > self.m_eq
        return qpsolvers.Problem(
            P,
            self.q.copy(),
            G if has_ineq else None,
            h if has_ineq else None,
            A if has_eq else None,
            b if has_eq else None,
        )

    def dense_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(P, q, G, h)`` of the inequalities only (the equalities are left out: a
        back-end reading this form is refused by its own check when ``m_eq > 0``)."""
        return self.P_dense, self.q, self.A_dense[self.m_eq :], self.u[self.m_eq :].copy()

    def dense_rows(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(P, q, A, lower, upper)`` of ``lower <= A x <= upper``, the ``m_eq``
        equalities first (DAQP's form; views, not copies)."""
        return self.P_dense, self.q, self.A_dense, self.l, self.u

    # ------------------------------------------------------------------ OSQP form
    @property
    def P_data(self) -> np.ndarray:
        """Values of ``P`` in the CSC order of :attr:`P_pattern`."""
        return self.P_pattern.data(self.P_dense)

    @property
    def A_data(self) -> np.ndarray:
        """Values of ``A`` in the CSC order of :attr:`A_pattern`."""
        return self.A_pattern.data(self.A_dense)

    @property
    def P(self) -> sp.csc_matrix:
        """Cost matrix, CSC."""
        return self.P_pattern.matrix(self.P_data)

    @property
    def P_upper(self) -> sp.csc_matrix:
        """Upper triangle of ``P``, CSC (explicit zeros kept)."""
        pattern = self._P_upper_pattern
        return pattern.matrix(self.P_dense[pattern.rows, pattern.cols][pattern.order])

    @property
    def A(self) -> sp.csc_matrix:
        """Constraint matrix (equalities first), CSC."""
        return self.A_pattern.matrix(self.A_data)

    # ------------------------------------------------------------------ warm starts
    def shift_primal(self, x: np.ndarray, samples: float) -> np.ndarray:
        """The previous solution (the tick before had the same contacts when the size
        matches; zero otherwise)."""
        return np.array(x) if x is not None and len(x) == self.n else np.zeros(self.n)

    def shift_dual(self, y: np.ndarray, samples: float) -> np.ndarray:
        """The previous dual solution, or zero (see :meth:`shift_primal`)."""
        return np.array(y) if y is not None and len(y) == self.m else np.zeros(self.m)
