"""The QP protocol the walking QPs answer, and the prediction a solution gives.

Define, build, solve, read back (as qpmpc's ``MPCProblem`` -> ``MPCQP`` -> ``solve_mpc`` ->
``Plan``): a receding-horizon generator builds its QP once, rewrites what changed every
tick (:meth:`QuadraticProgram.update`), hands it to a back-end of :mod:`mpcwalk.qp.solvers`
and reads the solution back as CoM jerks (:meth:`QuadraticProgram.jerks`) and the states
they predict (:meth:`QuadraticProgram.predict`, a :class:`Prediction`).

:class:`~mpcwalk.qp.walking_qp.WalkingQP` (fixed footsteps) and
:class:`~mpcwalk.qp.footstep_qp.FootstepQP` (footsteps as variables) both answer
:class:`QuadraticProgram`, which is all a ``qpsolvers`` back-end needs. The QPs whose
matrices keep one sparsity pattern from tick to tick (``fixed_pattern`` True: the
``WalkingQP``) also answer :class:`FixedPatternProgram`, the OSQP form that the direct
back-ends (OSQP, CasADi, KKT) update in place.
"""

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
import qpsolvers

from mpcwalk.qp.fixed_pattern import FixedPattern


@dataclass(frozen=True)
class Prediction:
    """States predicted over the horizon from an initial state and jerks.

    Attributes:
        times: Sample times, shape (N,), in [s].
        com: CoM positions, shape (N, 2), in [m].
        com_velocity: Shape (N, 2), in [m]/[s].
        com_acceleration: Shape (N, 2), in [m]/[s]^2.
        zmp: Shape (N, 2), in [m].
    """

    times: np.ndarray
    com: np.ndarray
    com_velocity: np.ndarray
    com_acceleration: np.ndarray
    zmp: np.ndarray


class QuadraticProgram(Protocol):
    """A walking QP over the CoM jerks of ``N`` samples (and possibly more variables).

    Attributes:
        formulation: ``"dense"`` (condensed) or ``"sparse"`` (states as variables).
        fixed_pattern: Whether the QP also answers :class:`FixedPatternProgram`.
        n: Number of variables.
        m: Number of constraint rows (equalities first), as last updated.
        m_eq: Number of equality rows.
        N: Number of samples of the horizon.
        x0: Cart-table state of the last :meth:`update`, shape (3, 2), or None before.
        sample_times: Sample times of the last :meth:`update`, shape (N,), in [s].
    """

    formulation: str
    fixed_pattern: bool
    n: int
    m: int
    m_eq: int
    N: int
    x0: np.ndarray | None
    sample_times: np.ndarray

    def update(self, x0: np.ndarray, t: float, *args: Any, **kwargs: Any) -> Any:
        """Rewrite the QP for the tick at ``t`` [s] from the cart-table state ``x0``
        (3, 2); the other arguments are the QP's own (references, supports)."""

    def require_update(self) -> None:
        """Raise :class:`~mpcwalk.exceptions.NotReset` before the first :meth:`update`."""

    def problem(self, dense: bool = ...) -> qpsolvers.Problem:
        """The QP in qpsolvers form ``min 1/2 x'Px + q'x, G x <= h, A x = b``."""

    def dense_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(P, q, G, h)`` of the inequality-only dense form, numpy arrays (no copy: the
        QP's own, valid until the next :meth:`update`)."""

    def jerks(self, x: np.ndarray) -> np.ndarray:
        """CoM jerks of a solution, shape (N, 2), in [m]/[s]^3."""

    def predict(self, jerks: np.ndarray) -> Prediction:
        """States at the samples of the last :meth:`update` for jerks (N, 2)."""

    def shift_primal(self, x: np.ndarray, samples: float) -> np.ndarray:
        """Primal vector shifted by ``samples`` sampling periods (warm start)."""


class FixedPatternProgram(QuadraticProgram, Protocol):
    """A QP in OSQP form ``min 1/2 x'Px + q'x, l <= A x <= u`` whose matrices keep one
    sparsity pattern: each tick rewrites ``q``, ``l`` and ``u``, and the values of ``P``
    and ``A`` only when their version counters move.

    Attributes:
        q: Linear cost, shape (n,).
        l: Lower bounds, shape (m,); equalities first.
        u: Upper bounds, shape (m,).
        P_data: Values of the full symmetric ``P`` in the CSC order of :attr:`P_pattern`.
        P_version: Incremented when the values of ``P`` change.
        A_version: Incremented when the values of ``A`` change.
    """

    q: np.ndarray
    l: np.ndarray
    u: np.ndarray
    P_data: np.ndarray
    P_version: int
    A_version: int

    @property
    def A_data(self) -> np.ndarray:
        """Values of ``A`` in the CSC order of :attr:`A_pattern`."""

    @property
    def P_pattern(self) -> FixedPattern:
        """Sparsity pattern of the full symmetric ``P``, shape (n, n)."""

    @property
    def A_pattern(self) -> FixedPattern:
        """Sparsity pattern of ``A``, shape (m, n)."""

    @property
    def P(self) -> Any:
        """Full symmetric cost matrix, shape (n, n), CSC."""

    @property
    def P_upper(self) -> Any:
        """Upper triangle of ``P`` (what OSQP expects), CSC."""

    @property
    def A(self) -> Any:
        """Constraint matrix, shape (m, n), CSC."""

    def shift_dual(self, y: np.ndarray, samples: float) -> np.ndarray:
        """Dual vector (OSQP form) shifted by ``samples`` sampling periods (warm start)."""
