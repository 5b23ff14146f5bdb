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

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import qpsolvers

from mpcwalk.qp.deferred import deferred_item
from mpcwalk.qp.fixed_pattern import FixedPattern

States = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""``(com, com_velocity, com_acceleration, zmp)`` over a horizon."""


@dataclass(frozen=True, init=False)
class Prediction:
    """States predicted over the horizon from an initial state and jerks.

    Attributes:
        times: Sample times, shape (N,), in [s].
        com: CoM positions, shape (N, 2), in [m].
        com_velocity: Shape (N, 2), in [m]/[s].
        com_acceleration: Shape (N, 2), in [m]/[s]^2.
        zmp: Shape (N, 2), in [m].

    The four states are given as arrays, or as ``states``: a function of no argument that
    returns them, called the first time one is read (:mod:`mpcwalk.qp.deferred`). A QP
    generator keeps the prediction of every tick's plan and reads its times; the states
    are read by the plots, the tests and the flywheel's horizon.
    """

    times: np.ndarray
    _states: "States | Callable[[], States]" = field(repr=False, compare=False)

    def __init__(
        self,
        times: np.ndarray,
        com: np.ndarray | None = None,
        com_velocity: np.ndarray | None = None,
        com_acceleration: np.ndarray | None = None,
        zmp: np.ndarray | None = None,
        *,
        states: "Callable[[], States] | None" = None,
        _states: "States | Callable[[], States] | None" = None,  # (replace's)
    ) -> None:
        held = states if states is not None else _states
        given = (com, com_velocity, com_acceleration, zmp)
        self.__dict__.update(times=times, _states=given if held is None else held)

    com = deferred_item("_states", 0, "CoM positions, shape (N, 2), in [m].")
    com_velocity = deferred_item("_states", 1, "Shape (N, 2), in [m]/[s].")
    com_acceleration = deferred_item("_states", 2, "Shape (N, 2), in [m]/[s]^2.")
    zmp = deferred_item("_states", 3, "Shape (N, 2), in [m].")


def predicted_states(maps: tuple[np.ndarray, ...], x0: Any, jerks: np.ndarray):
    """The function that makes the states of a :class:`Prediction` (when they are read)
    from the prediction maps ``(Pps, Ppu, Pvs, Pvu, Pas, Pau, Pzs, Pzu)`` of a tick, its
    state ``x0`` (3, 2) and the jerks (N, 2), each ``P?s x0 + P?u jerks``; the maps, ``x0``
    and ``jerks`` must not change after (the QPs pass this tick's maps and copies)."""

    def states() -> States:
        Pps, Ppu, Pvs, Pvu, Pas, Pau, Pzs, Pzu = maps
        return (
            Pps @ x0 + Ppu @ jerks,
            Pvs @ x0 + Pvu @ jerks,
            Pas @ x0 + Pau @ jerks,
            Pzs @ x0 + Pzu @ jerks,
        )

    return states


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
