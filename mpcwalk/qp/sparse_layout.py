"""The sparse layout of the walking QP: jerks and states as variables, the dynamics as
equality rows (see :mod:`mpcwalk.qp.layouts` for the problem and the condensed layout)."""

import numpy as np

from mpcwalk.models.cart_table import CartTable
from mpcwalk.qp.fixed_pattern import stack_patterns
from mpcwalk.qp.layouts import E, Layout
from mpcwalk.qp.parameters import MpcParameters
from mpcwalk.qp.schedule_tables import SupportSequence
from mpcwalk.qp.shift import Block


class SparseLayout(Layout):
    """Decision variables: jerks and states, ``x = [U_x, U_y, X_x, X_y]``
    with ``X_a`` the states ``[c, c_dot, c_ddot]`` at samples 1..N (3N
    values per axis); the dynamics are equality rows."""

    formulation = "sparse"

    def __init__(
        self, model: CartTable, parameters: MpcParameters, control_period: float | None = None
    ) -> None:
        super().__init__(model, parameters, control_period)
        N = self.N
        a = np.arange(2).reshape(2, 1, 1)
        i = np.arange(N).reshape(1, N, 1)
        k = np.arange(3).reshape(1, 1, 3)
        X = self._X
        eq_row = a * 3 * N + 3 * i + k  # (2, N, 3)
        Ak, Am = np.nonzero(model.A)
        ident = (eq_row, X(a, i, k))
        ra = a[..., None] * 3 * N + 3 * i[:, 1:, :, None] + Ak.reshape(1, 1, -1, 1)
        transition = (ra, X(a[..., None], i[:, :-1, :, None], Am.reshape(1, 1, -1, 1)))
        inp = (eq_row, np.broadcast_to(a * N + i, eq_row.shape))
        self._eq_values = np.concatenate(
            [
                np.ones(6 * N),
                np.tile(-model.A[Ak, Am], 2 * (N - 1)),
                np.tile(-model.B, 2 * N),
            ]
        )
        self._eq_dual_blocks: list[Block] = [(0, (2, N, 3), 1)]
        # Cost: jerk diagonal, then a full 3x3 block per (axis, sample).
        u_idx = np.arange(2 * N)
        km = np.arange(3)
        P_rows = X(a[..., None], i[..., None], km.reshape(1, 1, 3, 1))
        P_cols = X(a[..., None], i[..., None], km.reshape(1, 1, 1, 3))
        P_coords = stack_patterns([(u_idx, u_idx), (P_rows + 0 * P_cols, P_cols + 0 * P_rows)])
        self._finish(8 * N, 6 * N, P_coords, [ident, transition, inp])
        self.primal_blocks: list[Block] = [(0, (2, N), 1), (2 * N, (2, N, 3), 1)]

    def _X(self, a, i, k):
        """Column of state component ``k`` of axis ``a`` at sample ``i + 1``."""
        return 2 * self.N + a * 3 * self.N + 3 * i + k

    def _entries(self, kind: str):
        N = self.N
        a, r = np.arange(2).reshape(1, 1, 2, 1), np.arange(E).reshape(1, E, 1, 1)
        i = np.arange(N).reshape(N, 1, 1, 1)
        if kind == "dcm":  # (E, 2, 2): position and velocity at the last sample
            cols = self._X(a, N - 1, np.array([0, 1])) + 0 * r
            return np.broadcast_to(r, cols.shape), cols
        comps = np.array([0, 2]) if kind == "zmp" else np.array([0])
        cols = self._X(a, i, comps) + 0 * r
        return np.broadcast_to(i * E + r, cols.shape), cols

    def _values(self, kind: str, Ahp: np.ndarray) -> np.ndarray:
        if kind == "dcm":
            return Ahp[-1][..., None] * np.array([1.0, 1.0 / self.omega])
        if kind == "zmp":
            if self.eta is None:
                return Ahp[..., None] * self.C[[0, 2]]
            return Ahp[..., None] * self.sample_C[:, None, None, [0, 2]]
        return Ahp

    def _free(self, kind: str, x0: np.ndarray) -> np.ndarray:
        batch = x0.shape[2:]
        return np.zeros((2, *batch)) if kind == "dcm" else np.zeros((self.N, 2, *batch))

    def P_values(self, com_weights: np.ndarray) -> np.ndarray:
        p, s, N = self.parameters, 2.0 * self.cost_scale, self.N
        if self.eta is None:
            block = p.zmp_weight * np.outer(self.C, self.C)
            block[1, 1] += p.velocity_weight
            blocks = np.broadcast_to(block, (2, N, 3, 3)).copy()
        else:
            per_sample = p.zmp_weight * np.einsum("ij,ik->ijk", self.sample_C, self.sample_C)
            per_sample[:, 1, 1] += p.velocity_weight
            blocks = np.broadcast_to(per_sample, (2, N, 3, 3)).copy()
        blocks[:, :, 0, 0] += com_weights[None, :]
        return s * np.concatenate([np.full(2 * N, p.jerk_weight), blocks.ravel()])

    def q(self, x0, zmp_ref, velocity_ref, com_ref, com_weights) -> np.ndarray:
        p, s, N = self.parameters, 2.0 * self.cost_scale, self.N
        gx = -p.zmp_weight * zmp_ref.T[..., None] * (self.C if self.eta is None else self.sample_C)
        if p.velocity_weight:
            gx[:, :, 1] -= p.velocity_weight * velocity_ref.T
        if com_ref is not None:  # None: no CoM term (zero weights)
            gx[:, :, 0] -= com_weights[None, :] * com_ref.T
        return s * np.concatenate([np.zeros(2 * N), gx.ravel()])

    def bounds(self, x0, seq: SupportSequence) -> tuple[np.ndarray, np.ndarray]:
        x0 = np.asarray(x0, dtype=float)
        batch = x0.shape[2:]
        states = np.zeros((2, self.N, 3, *batch))
        states[:, 0] = np.einsum("kl,la...->ak...", self.model.A, x0)
        eq = states.reshape(6 * self.N, *batch)
        u_ineq = self.upper_bounds(x0, seq)
        lower = np.full((self.m_ineq, *batch), -np.inf)
        return np.concatenate([eq, lower]), np.concatenate([eq, u_ineq])
