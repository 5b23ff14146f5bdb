"""The walking MPC of Wieber (2006) as a quadratic program with cheap updates.

Per horizontal axis the state is the cart-table state ``[c, c_dot, c_ddot]``
and the decision variables are the CoM jerks over ``N`` samples of period
``sampling_period``; sample ``i = 1..N`` lies at ``t + i * sampling_period``.
The ZMP (and optionally the CoM projection) of each sample is kept inside the
support polygon of that sample's time; see :class:`MpcParameters` for the
cost. :class:`WalkingQP` builds the matrices once and :meth:`WalkingQP.update`
rewrites only what changes from one control tick to the next.
"""

import numpy as np
import qpsolvers
import scipy.sparse as sp

from mpcwalk.exceptions import ConfigurationError, NotReset
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.height_profile import height_profile
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.affine_bounds import affine_bounds
from mpcwalk.qp.fixed_pattern import FixedPattern
from mpcwalk.qp.layouts import CondensedLayout
from mpcwalk.qp.parameters import MpcParameters
from mpcwalk.qp.program import Prediction, predicted_states
from mpcwalk.qp.schedule_tables import ScheduleTables, SupportSequence
from mpcwalk.qp.sparse_layout import SparseLayout

FORMULATIONS = ("dense", "sparse")
#: Times within this of a phase boundary, up to round-off, belong to the new
#: phase (as in ``ContactSchedule.phase_index``), in [s].
_BOUNDARY_EPS = 1e-9


class WalkingQP:
    """Walking MPC QP, built once, updated every control tick.

    The problem is available in OSQP form (``P``, ``q``, ``A``, ``l``, ``u``,
    CSC matrices with a fixed sparsity pattern) and in qpsolvers form
    (:meth:`problem`). :meth:`update` rewrites ``q``, ``l`` and ``u`` every
    tick. The values of the constraint matrix (and of ``P`` when the CoM
    weights depend on the contact phase) are recomputed only when the
    sequence of support polygons over the horizon changes: the cache key is
    the tuple of phase indices at the sample times (and at the next tick,
    and those bounding the CoM, see
    :meth:`~mpcwalk.qp.schedule_tables.ScheduleTables.com_phases`), with
    phases that share a polygon (double support closing one step and opening
    the next) merged. :attr:`A_version` and :attr:`P_version` count these
    rewrites so that solvers push new matrix values only when needed.

    It answers :class:`~mpcwalk.qp.program.FixedPatternProgram` (and so
    :class:`~mpcwalk.qp.program.QuadraticProgram`).

    Args:
        lipm: Pendulum model (CoM height, gravity).
        parameters: Horizon, weights and margins.
        formulation: ``"dense"`` (condensed: jerks only) or ``"sparse"``
            (states kept as variables, dynamics as equality constraints).
        control_period: When given, the ZMP (and the CoM if constrained) is
            also kept in the support polygon at ``t + control_period``, the
            next output of a generator, which falls between the samples; in
            [s]. None: samples only.
    """

    #: The OSQP form keeps one sparsity pattern (:class:`~mpcwalk.qp.program.FixedPatternProgram`).
    fixed_pattern = True

    def __init__(
        self,
        lipm: LIPM = LIPM(),
        parameters: MpcParameters = MpcParameters(),
        formulation: str = "dense",
        control_period: float | None = None,
    ) -> None:
        if formulation not in FORMULATIONS:
            raise ConfigurationError(
                f"QP formulation must be one of {', '.join(FORMULATIONS)}, got {formulation!r}."
            )
        self.parameters = parameters
        self.formulation = formulation
        self.model = CartTable(lipm, parameters.sampling_period)
        layout_class = CondensedLayout if formulation == "dense" else SparseLayout
        if control_period is not None and not (
            np.isfinite(control_period) and control_period > 0.0
        ):
            raise ConfigurationError(
                f"control_period must be a positive number of seconds or None, got "
                f"{control_period!r}."
            )
        self.control_period = control_period
        self.layout = layout = layout_class(self.model, parameters, control_period)
        self.N = parameters.horizon
        self.n, self.m, self.m_eq = layout.n, layout.m, layout.m_eq
        self.sample_offsets = parameters.sampling_period * np.arange(1, self.N + 1)
        self._P_upper = layout.P_pattern.upper_triangle()
        self._G_rows = layout.A_pattern.row_slice(self.m_eq, self.m)
        self._Aeq_rows = layout.A_pattern.row_slice(0, self.m_eq)
        self._com_weights = np.full(self.N, parameters.com_weight)
        self.supports = SupportSequence.empty(self.N)
        """Half-planes of the inequality rows as last updated."""
        self.P_data = layout.P_data(self._com_weights)
        """Values of the full symmetric ``P`` in CSC order."""
        self.q = np.zeros(self.n)
        self.l = np.full(self.m, -np.inf)
        self.u = np.full(self.m, np.inf)
        self.P_version = 0
        self.A_version = 0
        self.x0: np.ndarray | None = None
        self.sample_times = self.sample_offsets.copy()
        self._schedule: ContactSchedule | None = None
        self._tables: ScheduleTables | None = None
        self.time = 0.0
        self._key: bytes | None = None
        self._cache: dict = {}
        self._query = np.zeros(2 * self.N + 1)
        self._bounds_map: tuple = (self.l, None, self.u, None)

    # ------------------------------------------------------------- update
    def update(
        self,
        x0: np.ndarray,
        t: float,
        schedule: ContactSchedule,
        *,
        zmp_reference: np.ndarray | None = None,
        com_reference: np.ndarray | None = None,
        velocity_reference: np.ndarray | None = None,
    ) -> bool:
        """Set the initial state and time; rewrite what changed.

        Args:
            x0: Cart-table state at ``t``, shape (3, 2): rows position [m],
                velocity [m/s], acceleration [m/s^2]; columns x, y.
            t: Current time, in [s]; samples lie at ``t + i * sampling_period``.
            schedule: Contact schedule giving the support polygons.
            zmp_reference: Shape (N, 2), in [m]; default: the schedule's
                polygonal reference (paper M eq. 6-8).
            com_reference: Shape (N, 2), in [m]; default: the support centre.
            velocity_reference: Shape (N, 2), in [m]/[s]; default: zero (e.g.
                :meth:`~mpcwalk.gait.ContactSchedule.reference_velocity` gives the
                average walking velocity of each step, Herdt 2010).

        Returns:
            Whether matrix values (``A`` or ``P``) changed.
        """
        x0 = np.asarray(x0, dtype=float)
        if x0.shape != (3, 2) or not np.isfinite(x0).all():
            raise ConfigurationError(
                "WalkingQP.update expects x0 of shape (3, 2) (rows position, velocity, "
                f"acceleration; columns x, y) with finite values, got shape {x0.shape}."
            )
        p, layout, N = self.parameters, self.layout, self.N
        times = t + self.sample_offsets
        tables = self.tables(schedule)
        query = self._query
        query[0] = t + (self.control_period or 0.0)
        query[1 : N + 1] = times
        np.add(times, p.sampling_period, out=query[N + 1 :])
        query += _BOUNDARY_EPS
        all_idx = schedule.phase_index(query)
        idx = all_idx[1 : N + 1]
        com_idx = tables.com_phases(idx, all_idx[N + 1 :])
        key = tables.polygon_id[np.concatenate([all_idx[: N + 1], com_idx])].tobytes()
        changed = False
        if self._set_heights(schedule, t, times):
            self._key = None  # the ZMP rows changed: every value is recomputed
            self.P_data = layout.P_data(self._com_weights)
            self.P_version += 1
            changed = True
        if key != self._key:
            self._key = key
            tick_idx = all_idx[0]
            self.supports = SupportSequence(
                tables.A[idx],
                tables.b[idx],
                tables.A[com_idx],
                tables.b[com_idx],
                tables.A[tick_idx],
                tables.b[tick_idx],
            )
            if layout.m_ineq:
                self.A_version += 1
                changed = True
            if p.com_weight_single_support_only and p.com_weight:
                weights = p.com_weight * tables.single[idx]
                if not np.array_equal(weights, self._com_weights):
                    self._com_weights = weights
                    self.P_data = layout.P_data(weights)
                    self.P_version += 1
                    changed = True
            self._bounds_map = affine_bounds(layout, self.supports)
        zmp_ref = self._reference(zmp_reference, "zmp_reference")
        if zmp_ref is None:
            zmp_ref = tables.zmp_reference(times) if p.zmp_weight else np.zeros((N, 2))
        com_ref = self._reference(com_reference, "com_reference")
        if com_ref is None and self._com_weights.any():  # else the cost has no CoM term
            com_ref = tables.centers[idx]
        vel_ref = self._reference(velocity_reference, "velocity_reference")
        if vel_ref is None:
            vel_ref = np.zeros((N, 2))
        self.q = layout.q(x0, zmp_ref, vel_ref, com_ref, self._com_weights)
        l0, Kl, u0, Ku = self._bounds_map
        state = x0.T.ravel()  # x0 of the x axis, then of the y axis
        self.l = l0 if Kl is None else l0 + Kl @ state
        self.u = u0 if Ku is None else u0 + Ku @ state
        self.x0, self.time, self.sample_times = x0.copy(), float(t), times
        return changed

    def _set_heights(self, schedule: ContactSchedule, t: float, times: np.ndarray) -> bool:
        """The layout's ZMP rows for the CoM height the schedule's footsteps give over the
        horizon (:class:`~mpcwalk.gait.height_profile.HeightProfile`); whether they
        changed. On level footsteps the rows are the model's constant ones."""
        lipm = self.model.lipm
        profile = height_profile(schedule, lipm.com_height)
        if profile.is_level:
            return self.layout.set_heights(None)
        eta = profile.eta(times, lipm.gravity)
        tick = None if self.control_period is None else t + self.control_period
        eta_tick = None if tick is None else float(profile.eta(tick, lipm.gravity)[0])
        return self.layout.set_heights(eta, eta_tick)

    def tables(self, schedule: ContactSchedule) -> ScheduleTables:
        """Per-phase tables of ``schedule`` (built once per schedule)."""
        if schedule is not self._schedule or self._tables is None:
            self._schedule, self._key = schedule, None
            self._tables = ScheduleTables.from_schedule(schedule)
        return self._tables

    def walking_velocity(self, t: float, schedule: ContactSchedule) -> np.ndarray:
        """Average walking velocity of the step at each sample of a tick at ``t`` [s]
        (``schedule.reference_velocity`` at the sample times), shape (N, 2), in [m/s]."""
        return self.tables(schedule).reference_velocity(t + self.sample_offsets)

    def _reference(self, value, name: str) -> np.ndarray | None:
        if value is None:
            return None
        arr = np.asarray(value, dtype=float)
        if arr.shape != (self.N, 2) or not np.isfinite(arr).all():
            raise ConfigurationError(
                f"{name} must have shape ({self.N}, 2) (one (x, y) per sample) with "
                f"finite values, got shape {arr.shape}."
            )
        return arr

    # ------------------------------------------------------------- matrices
    def _cached(self, name: str, version: int, build):
        entry = self._cache.get(name)
        if entry is None or entry[0] != version:
            entry = (version, build())
            self._cache[name] = entry
        return entry[1]

    @property
    def A_data(self) -> np.ndarray:
        """Values of ``A`` (OSQP form) in CSC order (computed when first asked after each
        change)."""
        return self._cached(
            "A_data",
            self.A_version,
            lambda: self.layout.A_pattern.data(self.layout.A_values(self.supports)),
        )

    @property
    def P_pattern(self) -> FixedPattern:
        """Sparsity pattern of the full symmetric ``P``, shape (n, n)."""
        return self.layout.P_pattern

    @property
    def A_pattern(self) -> FixedPattern:
        """Sparsity pattern of ``A`` (OSQP form), shape (m, n)."""
        return self.layout.A_pattern

    @property
    def P(self) -> sp.csc_matrix:
        """Full symmetric cost matrix, shape (n, n), CSC."""
        return self._cached("P", self.P_version, lambda: self.layout.P_pattern.matrix(self.P_data))

    @property
    def P_upper(self) -> sp.csc_matrix:
        """Upper triangle of ``P`` (what OSQP expects), CSC, fixed pattern."""
        return self._cached("P_upper", self.P_version, lambda: self._P_upper.matrix(self.P_data))

    @property
    def P_upper_data(self) -> np.ndarray:
        """CSC values of :attr:`P_upper` (for ``OSQP.update(Px=...)``)."""
        return self._P_upper.data(self.P_data)

    @property
    def A(self) -> sp.csc_matrix:
        """Constraint matrix of the OSQP form, shape (m, n): equalities then
        inequalities, CSC with a fixed pattern."""
        return self._cached("A", self.A_version, lambda: self.layout.A_pattern.matrix(self.A_data))

    def problem(self, dense: bool = False) -> qpsolvers.Problem:
        """The QP in qpsolvers form ``min 1/2 x'Px + q'x, G x <= h, A x = b``.

        Args:
            dense: Give numpy arrays instead of CSC matrices (for dense solvers).
        """
        self.require_update()
        kind = "dense" if dense else "csc"
        pattern = self.layout.P_pattern
        P = self._cached(
            f"P_{kind}",
            self.P_version,
            lambda: pattern.dense(self.P_data) if dense else pattern.matrix(self.P_data),
        )
        G = h = A = b = None
        if self.layout.m_ineq:
            G = self._cached(
                f"G_{kind}",
                self.A_version,
                lambda: self._dense_inequalities() if dense else self._G_rows.matrix(self.A_data),
            )
            h = self.u[self.m_eq :]
        if self.m_eq:
            A = self._cached(
                f"Aeq_{kind}",
                self.A_version,
                lambda: (
                    self._Aeq_rows.dense(self.A_data)
                    if dense
                    else self._Aeq_rows.matrix(self.A_data)
                ),
            )
            b = self.l[: self.m_eq]
        return qpsolvers.Problem(P, self.q, G, h, A, b)

    def dense_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(P, q, G, h)`` of the dense form with inequality rows only (the condensed
        layout's): ``P`` and ``G`` cached per matrix version, the QP's own vectors.

        Raises:
            ConfigurationError: The QP has equality rows (sparse layout).
        """
        self.require_update()
        if self.m_eq:
            raise ConfigurationError(
                "dense_arrays() needs a QP without equality rows (formulation='dense')."
            )
        G = self._cached("G_dense", self.A_version, self._dense_inequalities)
        return self.dense_cost(), self.q, G, self.u

    def dense_cost(self) -> np.ndarray:
        """The full symmetric ``P`` as a dense array (cached per version)."""
        return self._cached(
            "P_dense", self.P_version, lambda: self.layout.P_pattern.dense(self.P_data)
        )

    def whitened_inequalities(self, transform: np.ndarray) -> np.ndarray:
        """The dense inequality rows of the condensed layout times
        ``blockdiag(transform, transform)``, ``transform`` (N, N) acting on one axis's jerks
        (a back-end's whitening of the cost, whose two axis blocks are the same)."""
        layout = self.layout
        if not isinstance(layout, CondensedLayout):
            raise ConfigurationError(
                "whitened_inequalities() needs the condensed layout (formulation='dense')."
            )
        return layout.dense_inequalities(self.supports, transform)

    def _dense_inequalities(self) -> np.ndarray:
        layout = self.layout
        if isinstance(layout, CondensedLayout):
            return layout.dense_inequalities(self.supports)
        return self._G_rows.dense(self.A_data)

    def require_update(self) -> None:
        """Raise NotReset before the first :meth:`update`."""
        if self.x0 is None:
            raise NotReset("WalkingQP.update(x0, t, schedule) must be called before solving.")

    # ------------------------------------------------------------- solutions
    def jerks(self, x: np.ndarray) -> np.ndarray:
        """CoM jerks of a solution, shape (N, 2), in [m]/[s]^3."""
        return np.asarray(x)[: 2 * self.N].reshape(2, self.N).T

    def predict(self, jerks: np.ndarray, x0: np.ndarray | None = None) -> Prediction:
        """Exact states at the samples for jerks (N, 2) from ``x0`` (default:
        the state of the last :meth:`update`)."""
        x0 = self.x0 if x0 is None else np.array(x0, dtype=float)
        L = self.layout  # this tick's maps, and a copy of the jerks: the states made when read
        maps = (L.Pps, L.Ppu, L.Pvs, L.Pvu, L.Pas, L.Pau, L.Pzs, L.Pzu)
        states = predicted_states(maps, x0, np.array(jerks, dtype=float))
        return Prediction(times=self.sample_times.copy(), states=states)

    def shift_primal(self, x: np.ndarray, samples: float) -> np.ndarray:
        """Primal vector shifted by ``samples`` sampling periods (warm start)."""
        return self.layout.shift(np.asarray(x, dtype=float), "primal", samples)

    def shift_dual(self, y: np.ndarray, samples: float) -> np.ndarray:
        """Dual vector (OSQP form) shifted by ``samples`` sampling periods."""
        return self.layout.shift(np.asarray(y, dtype=float), "dual", samples)
