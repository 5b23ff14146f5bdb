"""Condensed and sparse layouts of the walking QP (pure construction).

Both layouts describe the same problem (Wieber 2006) in the OSQP form::

    minimize    1/2 x^T P x + q^T x
    subject to  l <= A x <= u

where the rows of ``A`` are the dynamics equalities (sparse layout only,
``l = u``) followed by the inequalities, in groups of ``MAX_POLYGON_EDGES``
rows (one support polygon each): ZMP at each sample, optionally the CoM
projection at each sample, the terminal DCM, and the ZMP (and CoM) at the
next control tick ``t + control_period`` (the state the generator outputs,
which lies between the QP's samples). A layout owns the sparsity
patterns (fixed once built) and computes values in coordinate order;
:class:`~mpcwalk.qp.walking_qp.WalkingQP` decides when to recompute them.

The cost is multiplied by a constant ``cost_scale`` chosen at construction
so that the largest diagonal entry of ``P`` is 1. This does not move the
minimiser and keeps absolute solver tolerances meaningful.
"""

from abc import ABC, abstractmethod

import numpy as np

from mpcwalk.gait.contact_schedule import MAX_POLYGON_EDGES
from mpcwalk.models.cart_table import CartTable
from mpcwalk.qp.fixed_pattern import FixedPattern, stack_patterns
from mpcwalk.qp.kept import kept
from mpcwalk.qp.parameters import MpcParameters
from mpcwalk.qp.schedule_tables import SupportSequence
from mpcwalk.qp.shift import Block, shift_gather

E = MAX_POLYGON_EDGES
#: The zero state and the six unit states ``x0`` (3, 2), stacked (3, 2, 7): the bounds at
#: them give the bounds' affine map of the state (:mod:`mpcwalk.qp.affine_bounds`).
UNIT_STATES = np.zeros((3, 2, 7))
UNIT_STATES[np.arange(6) % 3, np.arange(6) // 3, np.arange(1, 7)] = 1.0
UNIT_STATES.setflags(write=False)
#: Products of the rows' matrices with a transform kept (:meth:`CondensedLayout.dense_inequalities`).
_KEPT_TRANSFORMS = 256
#: Cost matrices kept per distinct CoM weights (:meth:`Layout.P_data`).
_KEPT_COSTS = 64


class Layout(ABC):
    """Shared parts of both layouts (the sparse one: :mod:`mpcwalk.qp.sparse_layout`).

    Args:
        model: Cart-table model at the sampling period.
        parameters: Horizon, weights, margins.
        control_period: When given (and constraints are on), also constrain
            the state at ``t + control_period``, in [s].
    """

    #: Set by each layout: values of its equality rows, their dual blocks and the
    #: per-sample blocks of its primal vector.
    _eq_values: np.ndarray
    _eq_dual_blocks: list[Block]
    primal_blocks: list[Block]

    def __init__(
        self, model: CartTable, parameters: MpcParameters, control_period: float | None = None
    ) -> None:
        self.parameters = p = parameters
        self.N = N = parameters.horizon
        self.omega = model.lipm.omega
        self.model = model
        pm = model.prediction_matrices(N)
        self.Pps, self.Ppu = pm["Pps"], pm["Ppu"]
        self.Pvs, self.Pvu = pm["Pvs"], pm["Pvu"]
        self.Pas, self.Pau = pm["Pas"], pm["Pau"]
        self.Pzs, self.Pzu = pm["Pzs"], pm["Pzu"]
        self.Pxs = self.Pps + self.Pvs / self.omega  # DCM
        self.Pxu = self.Ppu + self.Pvu / self.omega
        self.C = model.C
        self.sample_C = np.broadcast_to(model.C, (N, 3))
        """ZMP output row of each sample, shape (N, 3) (all ``C`` at a constant height)."""
        self.eta: np.ndarray | None = None
        """``(z_c - z_p) / (g + z_c'')`` [s^2] of each sample and of the tick when the CoM
        height varies (:meth:`set_heights`), None at the model's constant height."""
        tick = control_period is not None and p.constrained
        self._transition_dt = None
        if control_period is not None and tick:
            A_dt, B_dt = CartTable.transition(control_period)
            self._transition_dt = (A_dt, B_dt)
            # (row acting on x0, coefficient of the first jerk) per tick row.
            self._tick = {
                "zmp_tick": (self.C @ A_dt, self.C @ B_dt),
                "com_tick": (A_dt[0], B_dt[0]),
            }
        self._nominal = (self.Pzs, self.Pzu, self.sample_C, getattr(self, "_tick", None))
        # (kind, number of polygons): E rows per polygon.
        self.groups: list[tuple[str, int]] = []
        if p.constrained:
            self.groups.append(("zmp", N))
        if p.constrain_com:
            self.groups.append(("com", N))
        if p.constrained and p.terminal_dcm:
            self.groups.append(("dcm", 1))
        if tick:
            self.groups.append(("zmp_tick", 1))
            if p.constrain_com:
                self.groups.append(("com_tick", 1))
        self.m_ineq = E * sum(nb for _, nb in self.groups)
        self.has_tick = tick

    def set_heights(self, eta: np.ndarray | None, eta_tick: float | None = None) -> bool:
        """ZMP rows for a CoM height that varies along the horizon (time-varying LIPM:
        ``p_i = c_i - eta_i c_i''``, ``eta_i = (z_c - z_p) / (g + z_c'')`` known at each
        sample ``i``, shape (N,), and ``eta_tick`` at the next tick); None: back to the
        model's constant height. Returns whether the rows changed (the caller then
        recomputes the matrices' values)."""
        if eta is None:
            if self.eta is None:
                return False
            self.Pzs, self.Pzu, self.sample_C, tick = self._nominal
            if tick is not None:
                self._tick = tick
            self.eta = None
            self._forget_cached()
            return True
        eta = np.asarray(eta, dtype=float)
        if self.eta is not None and np.array_equal(eta, self.eta):
            return False
        self.eta = eta.copy()
        C = np.zeros((self.N, 3))
        C[:, 0], C[:, 2] = 1.0, -eta
        self.sample_C = C
        self.Pzs = self.Pps - eta[:, None] * self.Pas
        self.Pzu = self.Ppu - eta[:, None] * self.Pau
        if self._transition_dt is not None:
            A_dt, B_dt = self._transition_dt
            c_tick = np.array([1.0, 0.0, -(eta[0] if eta_tick is None else eta_tick)])
            self._tick = {
                "zmp_tick": (c_tick @ A_dt, c_tick @ B_dt),
                "com_tick": (A_dt[0], B_dt[0]),
            }
        self._forget_cached()
        return True

    def _forget_cached(self) -> None:
        """Drop what was made from the ZMP rows' matrices (the heights changed them)."""
        for cached in ("_maps", "_transformed_rows", "_unit_free", "_P_by_weights"):
            self.__dict__.pop(cached, None)

    @abstractmethod
    def _entries(self, kind: str) -> tuple[np.ndarray, np.ndarray]:
        """Rows and columns of the inequality rows of ``kind``."""

    @abstractmethod
    def _values(self, kind: str, Ahp: np.ndarray) -> np.ndarray:
        """Values of the inequality rows of ``kind`` from the polygons' normals ``Ahp``."""

    @abstractmethod
    def _free(self, kind: str, x0: np.ndarray) -> np.ndarray:
        """Part of the constrained quantity of ``kind`` that the states ``x0`` (3, 2, B)
        alone give: (N, 2, B) per sample, (2, B) for the terminal DCM."""

    @abstractmethod
    def bounds(self, x0, seq: SupportSequence) -> tuple[np.ndarray, np.ndarray]:
        """``(l, u)`` of every row for the state ``x0`` (3, 2), or for ``B`` states at once:
        ``x0`` (3, 2, B), ``l`` and ``u`` (m, B)."""

    @abstractmethod
    def P_values(self, com_weights: np.ndarray) -> np.ndarray:
        """Cost matrix values in coordinate order."""

    def P_data(self, com_weights: np.ndarray) -> np.ndarray:
        """CSC values of ``P`` for the CoM weights of the samples (read-only), made once per
        distinct weights (with ``com_weight_single_support_only`` they follow the single
        supports along the horizon, a few patterns that come back every step) and heights."""

        def make() -> np.ndarray:
            data = self.P_pattern.data(self.P_values(com_weights))
            data.setflags(write=False)
            return data

        cache = self.__dict__.setdefault("_P_by_weights", {})
        return kept(cache, com_weights.tobytes(), make, _KEPT_COSTS)

    def _finish(
        self,
        n: int,
        m_eq: int,
        P_coords: tuple[np.ndarray, np.ndarray],
        eq_coords: list[tuple[np.ndarray, np.ndarray]],
    ) -> None:
        self.n, self.m_eq = n, m_eq
        self.m = m_eq + self.m_ineq
        blocks, row = list(eq_coords), m_eq
        for kind, nb in self.groups:
            rows, cols = self._entries(kind) if not kind.endswith("tick") else self._tick_entries()
            blocks.append((row + rows, cols))
            row += E * nb
        self.P_pattern = FixedPattern(*P_coords, (n, n))
        self.A_pattern = FixedPattern(*stack_patterns(blocks), (self.m, n))
        nominal = np.full(self.N, self.parameters.com_weight)
        self.cost_scale = 1.0
        values = self.P_values(nominal)
        on_diagonal = self.P_pattern.rows == self.P_pattern.cols
        self.cost_scale = 1.0 / np.max(np.abs(values[on_diagonal]))
        self.dual_blocks: list[Block] = list(self._eq_dual_blocks)
        row = m_eq
        for kind, nb in self.groups:
            per_sample = kind in ("zmp", "com")
            self.dual_blocks.append((row, (nb, E), 0 if per_sample else None))
            row += E * nb

    def _tick_entries(self):
        """Tick rows involve the first jerk of each axis (column ``a N``) only."""
        rows = np.broadcast_to(np.arange(E).reshape(E, 1), (E, 2))
        return rows, np.broadcast_to(np.arange(2) * self.N, (E, 2))

    def A_values(self, seq: SupportSequence) -> np.ndarray:
        """Constraint matrix values in coordinate order."""
        parts = [self._eq_values]
        for kind, _ in self.groups:
            if kind.endswith("tick"):
                parts.append((seq.tick_A * self._tick[kind][1]).ravel())
            else:
                parts.append(self._values(kind, seq.com_A if kind == "com" else seq.zmp_A).ravel())
        return np.concatenate(parts)

    def upper_bounds(self, x0: np.ndarray, seq: SupportSequence) -> np.ndarray:
        """Right-hand sides ``u`` of the inequality rows (``l = -inf``) for the state ``x0``
        (3, 2), or for ``B`` states at once, ``x0`` of shape (3, 2, B) and ``u`` of shape
        (m_ineq, B)."""
        p, parts = self.parameters, []
        batch = np.asarray(x0, dtype=float)
        single = batch.ndim == 2
        if single:
            batch = batch[..., None]
        for kind, _ in self.groups:
            margin = p.com_margin if kind.startswith("com") else p.zmp_margin
            if kind.endswith("tick"):
                free = np.einsum("k,kab->ab", self._tick[kind][0], batch)
                parts.append((seq.tick_b - margin)[:, None] - seq.tick_A @ free)
            elif kind == "dcm":
                free = self._free(kind, batch)
                parts.append((seq.zmp_b[-1] - margin)[:, None] - seq.zmp_A[-1] @ free)
            else:
                A, b = (seq.com_A, seq.com_b) if kind == "com" else (seq.zmp_A, seq.zmp_b)
                free = self._free(kind, batch)
                bound = (b - margin)[..., None] - A @ free
                parts.append(bound.reshape(-1, batch.shape[2]))
        u = np.concatenate(parts) if parts else np.zeros((0, batch.shape[2]))
        return u[:, 0] if single else u

    def shift(self, vector: np.ndarray, which: str, samples: float) -> np.ndarray:
        """Shift the per-sample blocks of a primal (``which="primal"``) or dual
        (``"dual"``) vector by ``samples`` sampling periods: linear
        interpolation, last sample held; other entries are copied. The
        gather indices are cached per shift value."""
        key = (which, round(float(samples), 9))
        cache = self.__dict__.setdefault("_shift_cache", {})
        if key not in cache:
            blocks = self.primal_blocks if which == "primal" else self.dual_blocks
            size = self.n if which == "primal" else self.m
            cache[key] = shift_gather(blocks, size, samples, self.N)
        i0, i1, w = cache[key]
        return (1.0 - w) * vector[i0] + w * vector[i1]


class CondensedLayout(Layout):
    """Decision variables: the jerks only, ``x = [U_x (N), U_y (N)]``."""

    formulation = "dense"

    def __init__(
        self, model: CartTable, parameters: MpcParameters, control_period: float | None = None
    ) -> None:
        super().__init__(model, parameters, control_period)
        N = self.N
        ii, jj = np.meshgrid(np.arange(N), np.arange(N), indexing="ij")
        axis = np.arange(2).reshape(2, 1, 1)
        P_coords = ((axis * N + ii).ravel(), (axis * N + jj).ravel())
        self._ti, self._tj = np.tril_indices(N)
        self._eq_values = np.zeros(0)
        self._eq_dual_blocks: list[Block] = []
        self._finish(2 * N, 0, P_coords, [])
        self.primal_blocks: list[Block] = [(0, (2, N), 1)]

    def _entries(self, kind: str):
        N, E_ = self.N, np.arange(E).reshape(1, E, 1, 1)
        a = np.arange(2).reshape(1, 1, 2, 1)
        if kind == "dcm":  # (E, 2, N): last sample, every jerk
            shape = (1, E, 2, N)
            return np.broadcast_to(E_, shape), np.broadcast_to(a * N + np.arange(N), shape)
        # (pair, E, 2): sample ti depends on jerk tj <= ti.
        ti, tj = self._ti.reshape(-1, 1, 1, 1), self._tj.reshape(-1, 1, 1, 1)
        shape = (len(self._ti), E, 2, 1)
        return np.broadcast_to(ti * E + E_, shape), np.broadcast_to(a * N + tj, shape)

    def _values(self, kind: str, Ahp: np.ndarray) -> np.ndarray:
        ti, tj = self._ti, self._tj
        if kind == "dcm":
            return Ahp[-1][:, :, None] * self.Pxu[-1][None, None, :]
        matrix = self.Pzu if kind == "zmp" else self.Ppu
        return Ahp[ti] * matrix[ti, tj][:, None, None]

    def dense_inequalities(
        self, seq: SupportSequence, transform: np.ndarray | None = None
    ) -> np.ndarray:
        """The inequality rows as a dense array, shape (m_ineq, n): the values of
        :meth:`A_values` where the pattern has them, zero elsewhere (built directly, without
        the compressed-column detour); with ``transform`` (N, N), the rows times
        ``blockdiag(transform, transform)`` (a row is a polygon normal times a row acting
        on one axis's jerks, so only those N x N products are made, once per transform)."""
        N, parts = self.N, []
        for kind, _ in self.groups:
            normals, matrix = self._row_factors(kind, seq)
            if transform is not None:
                matrix = self._transformed(kind, matrix, transform)
            rows = normals[..., None] * matrix[:, None, None, :]  # (k, E, 2, N)
            parts.append(rows.reshape(-1, 2 * N))
        dense = np.concatenate(parts) if parts else np.zeros((0, 2 * N))
        return dense + 0.0  # no negative zeros: the pattern's zeros are positive

    def _row_factors(self, kind: str, seq: SupportSequence) -> tuple[np.ndarray, np.ndarray]:
        """``(normals (k, E, 2), matrix (k, N))`` of the rows of ``kind``: row ``(i, r)``
        is ``normals[i, r, a] * matrix[i]`` on the jerks of axis ``a``."""
        if kind.endswith("tick"):  # the first jerk only
            first = np.zeros((1, self.N))
            first[0, 0] = self._tick[kind][1]
            return seq.tick_A[None], first
        if kind == "dcm":
            return seq.zmp_A[-1:], self.Pxu[-1:]
        return (seq.com_A, self.Ppu) if kind == "com" else (seq.zmp_A, self.Pzu)

    def _transformed(self, kind: str, matrix: np.ndarray, transform: np.ndarray) -> np.ndarray:
        """``matrix @ transform``, kept per kind and transform (a cost that cycles through a
        few values, as the static gait's, comes back to the same transforms); a kind's
        matrix changes only with the heights, which drop them all."""
        cache = self.__dict__.setdefault("_transformed_rows", {})
        # the entry holds the transform, so that its id stays its own
        key = (kind, id(transform))
        entry = kept(cache, key, lambda: (transform, matrix @ transform), _KEPT_TRANSFORMS)
        return entry[1]

    def _free(self, kind: str, x0: np.ndarray) -> np.ndarray:
        if x0 is UNIT_STATES:  # the same for every support sequence: made once
            cache = self.__dict__.setdefault("_unit_free", {})
            free = cache.get(kind)
            if free is None:
                free = cache[kind] = self._free(kind, x0.copy())
            return free
        if kind == "dcm":
            return np.einsum("k,kab->ab", self.Pxs[-1], x0)
        return np.einsum("ik,kab->iab", self.Pzs if kind == "zmp" else self.Pps, x0)

    def P_values(self, com_weights: np.ndarray) -> np.ndarray:
        p, s = self.parameters, 2.0 * self.cost_scale
        H = p.zmp_weight * self.Pzu.T @ self.Pzu + p.jerk_weight * np.eye(self.N)
        if p.velocity_weight:
            H += p.velocity_weight * self.Pvu.T @ self.Pvu
        if np.any(com_weights):
            H += self.Ppu.T @ (com_weights[:, None] * self.Ppu)
        H = 0.5 * s * (H + H.T)  # exactly symmetric despite round-off
        return np.concatenate([H.ravel()] * 2)

    def q(self, x0, zmp_ref, velocity_ref, com_ref, com_weights) -> np.ndarray:
        p, s = self.parameters, 2.0 * self.cost_scale
        if not np.any(com_weights):  # the tick's case: two products of precomputed maps
            state_map, reference_map = self._q_maps()
            g = state_map @ x0 - reference_map @ np.vstack([zmp_ref, velocity_ref])
            return g.T.ravel()
        g = p.zmp_weight * self.Pzu.T @ (self.Pzs @ x0 - zmp_ref)
        if p.velocity_weight:
            g += p.velocity_weight * self.Pvu.T @ (self.Pvs @ x0 - velocity_ref)
        if np.any(com_weights):
            g += self.Ppu.T @ (com_weights[:, None] * (self.Pps @ x0 - com_ref))
        return s * g.T.ravel()

    def _q_maps(self) -> tuple[np.ndarray, np.ndarray]:
        """``(state_map, reference_map)`` with ``g = state_map x0 - reference_map [Z; V]``
        the gradient of one axis without CoM terms (cost scale included), shapes (N, 3) and
        (N, 2N); computed once."""
        maps = self.__dict__.get("_maps")
        if maps is None:
            p, s = self.parameters, 2.0 * self.cost_scale
            state = p.zmp_weight * self.Pzu.T @ self.Pzs
            reference = [p.zmp_weight * self.Pzu.T, np.zeros((self.N, self.N))]
            if p.velocity_weight:
                state = state + p.velocity_weight * self.Pvu.T @ self.Pvs
                reference[1] = p.velocity_weight * self.Pvu.T
            maps = self.__dict__["_maps"] = (s * state, s * np.hstack(reference))
        return maps

    def bounds(self, x0, seq: SupportSequence) -> tuple[np.ndarray, np.ndarray]:
        upper = self.upper_bounds(x0, seq)
        return np.full(upper.shape, -np.inf), upper
