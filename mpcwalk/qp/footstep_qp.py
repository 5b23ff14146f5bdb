"""Walking MPC with the footstep positions as decision variables (Herdt et al. 2010).

Per horizontal axis the decision variables are the CoM jerks over ``N`` samples (the
cart-table model of :mod:`mpcwalk.qp.walking_qp`) and the positions of the next ``nf``
footsteps; the footstep yaws are known in advance, so every constraint is linear::

    x = [U_x (N), U_y (N), F_x (nf), F_y (nf)]

    minimise   velocity_weight ||V - V_ref||^2 + zmp_weight ||Z - (c0 + S F)||^2
               + jerk_weight ||U||^2 + footstep_weight ||M F - r||^2
    subject to n_r . Z_i - n_r . S_i F <= b_r          (ZMP of sample i in its support)
               lower <= R(yaw_p)^T (F_j - F_p) <= upper  (footstep j reachable from p)
               band_lower_j <= F_j <= band_upper_j       (on a terrain: on its tread)

``c0 + S F`` is the ZMP centre of each sample (its support foot, or a point moving from
one foot to the next in double support), affine in the footsteps. ``M F - r`` pulls the
footsteps towards a nominal plan (absolute positions, or displacements from the previous
footstep). :class:`~mpcwalk.qp.footstep_supports.FootstepSlots` says which footstep each
sample stands on; :class:`FootstepQP` only assembles the matrices. The
problem is dense (jerks condensed) and rebuilt with numpy every tick from precomputed
prediction products: the footstep columns change with the samples anyway.
"""

from collections.abc import Iterable, Iterator

import numpy as np
import qpsolvers

from mpcwalk.exceptions import ConfigurationError, NotReset
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.cost_factor import bordered_inverse_factor, inverse_cholesky
from mpcwalk.qp.footstep_bounds import band_rows, box_rows, reach_rows
from mpcwalk.qp.footstep_parameters import FootstepMpcParameters
from mpcwalk.qp.footstep_prediction import horizon_predictions
from mpcwalk.qp.footstep_supports import SampleSupports, StepVariables
from mpcwalk.qp.program import Prediction, predicted_states


class FootstepQP:
    """Dense QP of the footstep-adaptive MPC, rebuilt cheaply every tick.

    It answers :class:`~mpcwalk.qp.program.QuadraticProgram`: the qpsolvers back-ends of
    :mod:`mpcwalk.qp.solvers` solve it through :meth:`problem` (``formulation`` is
    ``"dense"``, there are no equality rows). Its matrices are rebuilt every tick
    (``fixed_pattern`` is False), so the back-ends that update a fixed sparsity pattern in
    place (``osqp-direct``, CasADi, ``kkt``) refuse it.

    Args:
        lipm: Pendulum model.
        parameters: Horizon and weights.
        nb_footsteps: Number ``nf`` of footstep variables (the most a horizon can hold).
    """

    formulation = "dense"
    fixed_pattern = False
    m_eq = 0
    plain_inequalities = True
    """:meth:`problem` is ``min 1/2 x'Px + q'x, G x <= h`` on the arrays of
    :meth:`dense_arrays` and nothing else (no bounds): the ``quadprog`` back-end hands them
    to quadprog as qpsolvers would, without the qpsolvers layer."""

    def __init__(self, lipm: LIPM, parameters: FootstepMpcParameters, nb_footsteps: int) -> None:
        if int(nb_footsteps) != nb_footsteps or nb_footsteps < 1:
            raise ConfigurationError(
                f"nb_footsteps must be a positive integer, got {nb_footsteps!r}."
            )
        p = self.parameters = parameters
        self.N, self.nf = N, nf = parameters.horizon, int(nb_footsteps)
        self.n = self.n_base = 2 * (N + nf)
        """Columns of the QP, and the footstep QP's own (a subclass may add columns after
        them: zero in the rows built here)."""
        self.m = 0
        self.terminal_rows = 0
        """Rows of the terminal DCM constraint in the last update (``capturability``)."""
        self.cost_scale = 1.0
        """Factor of the cost in the last update (its largest jerk or footstep diagonal
        entry of ``P`` is 1)."""
        self.lipm = lipm
        self.model = CartTable(lipm, p.sampling_period)
        self._predictions: dict = {}
        self._pred = self._prediction(p.sampling_period)
        # Columns of each axis: its jerks, then its footsteps.
        self._columns = [
            np.concatenate([a * N + np.arange(N), 2 * N + a * nf + np.arange(nf)]) for a in range(2)
        ]
        # The QP of the last update (empty before the first).
        self.P, self.q = np.zeros((self.n, self.n)), np.zeros(self.n)
        self.G, self.h = np.zeros((0, self.n)), np.zeros(0)
        self.x0: np.ndarray | None = None
        self.supports: SampleSupports | None = None
        """The supports of the last :meth:`update`."""
        self._sample_times: tuple[float, np.ndarray] | None = None  # of the last time asked
        self.sample_times = self.sample_times_at(0.0)
        self._initial_footsteps = np.zeros((nf, 2))
        self._reach_rows: tuple | None = None  # the reach rows, with the arrays they are of

    def sample_times_at(self, t: float) -> np.ndarray:
        """Sample times of a tick at ``t`` [s], shape (N,): the grid of multiples of the
        sampling period after ``t``. The grid does not slide with the ticks, so that the
        samples meet the contact phases the same way from one tick to the next (a sliding
        grid made the footsteps jitter by a few mm at the sampling frequency); the first
        interval lasts between one control period and one sampling period."""
        cached = self._sample_times
        if cached is not None and cached[0] == t:  # (the same tick asks more than once)
            return cached[1]
        Ts = self.parameters.sampling_period
        first = (np.floor(t / Ts + 1e-6) + 1.0) * Ts
        times = first + Ts * np.arange(self.N)
        times.setflags(write=False)
        self._sample_times = (t, times)
        return times

    def constraint_times(self, t: float) -> np.ndarray:
        """Times where the ZMP is constrained for a tick at ``t`` [s], shape (N P,):
        ``P = constraint_points`` per sampling interval, the last at the sample."""
        samples = self.sample_times_at(t)
        starts = np.concatenate([[t], samples[:-1]])
        P = self.parameters.constraint_points
        share = np.arange(1, P + 1) / P
        return (starts[:, None] + share[None, :] * (samples - starts)[:, None]).ravel()

    def first_points(self, t: float, later: Iterable[float]) -> Iterator[np.ndarray]:
        """The constraint points of the first interval (the first ``constraint_points`` of
        :meth:`constraint_times`) of the ticks at the ``later`` times [s] that have the
        samples of the tick at ``t``, up to the first that has not (made as they are
        iterated)."""
        first, P = self.sample_times_at(t)[0], self.parameters.constraint_points
        share = np.arange(1, P + 1) / P
        for time in later:
            if self.sample_times_at(time)[0] != first:
                return
            # the first row of constraint_times(time): the same operations on fewer points
            yield time + share * (first - time)

    def _prediction(self, first: float) -> dict:
        """Prediction matrices (``P?s`` (N, 3), ``P?u`` (N, N), as
        :meth:`CartTable.prediction_matrices`) when the first interval lasts ``first``
        [s] and the others one sampling period, with the jerk block of the cost."""
        key = round(first * 1e9)
        pred = self._predictions.get(key)
        if pred is not None:
            return pred
        pred = horizon_predictions(self.model, self.parameters, self.lipm.omega, first)
        self._predictions[key] = pred
        return pred

    def _with_heights(self, pred: dict, eta: np.ndarray, eta_points: np.ndarray) -> dict:
        """Prediction matrices with the ZMP rows of a time-varying CoM height."""
        p = self.parameters
        out = dict(pred)
        # what is made from the level rows is made again from these on demand
        for derived in ("weighted", "H_jerk_inverse_factor"):
            out.pop(derived, None)
        out["Pzs"] = pred["Pps"] - eta[:, None] * pred["Pas"]
        out["Pzu"] = pred["Ppu"] - eta[:, None] * pred["Pau"]
        out["Czs"] = pred["Cps"] - eta_points[:, None] * pred["Cas"]
        out["Czu"] = pred["Cpu"] - eta_points[:, None] * pred["Cau"]
        H = (
            p.zmp_weight * out["Pzu"].T @ out["Pzu"]
            + p.velocity_weight * pred["Pvu"].T @ pred["Pvu"]
            + p.jerk_weight * np.eye(self.N)
        )
        out["H_jerk"] = 0.5 * (H + H.T)
        return out

    def _weighted(self, pred: dict) -> tuple[np.ndarray, np.ndarray]:
        """``(zmp_weight Pzu^T, velocity_weight Pvu^T)`` of the prediction ``pred``, made
        once per prediction (kept in it)."""
        weighted = pred.get("weighted")
        if weighted is None:
            p = self.parameters
            weighted = pred["weighted"] = (
                p.zmp_weight * pred["Pzu"].T,
                p.velocity_weight * pred["Pvu"].T,
            )
        return weighted

    def update(
        self,
        x0: np.ndarray,
        t: float,
        velocity_reference: np.ndarray,
        supports: SampleSupports,
        steps: StepVariables,
        eta: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> None:
        """Assemble the QP of the tick at time ``t`` [s] from the CoM state ``x0`` (3, 2)
        (rows position [m], velocity [m/s], acceleration [m/s^2]), the reference velocity
        (N, 2) [m/s], the supports of the samples and the footstep variables; ``eta``: the
        time-varying LIPM's ``(z_c - z_p) / (g + z_c'')`` [s^2] at the samples (N,) and at
        the constraint points (:meth:`constraint_times`), None at the model's constant
        height."""
        x0 = np.asarray(x0, dtype=float)
        if x0.shape != (3, 2) or not np.isfinite(x0).all():
            raise ConfigurationError(
                "FootstepQP.update expects x0 of shape (3, 2) (rows position, velocity, "
                f"acceleration; columns x, y) with finite values, got shape {x0.shape}."
            )
        p, N, nf = self.parameters, self.N, self.nf
        times = self.sample_times_at(t)
        pred = self._prediction(times[0] - t)
        if eta is not None:
            pred = self._with_heights(pred, *eta)
        self._pred = pred
        last = p.constraint_points - 1
        S, M = supports.weights[last :: p.constraint_points], steps.reference_matrix
        centres = supports.centres[last :: p.constraint_points]
        wz, wf = p.zmp_weight, p.footstep_weight
        zmp_rows, velocity_rows = self._weighted(pred)
        H = np.empty((N + nf, N + nf))
        H[:N, :N] = pred["H_jerk"]
        H[:N, N:] = -zmp_rows @ S
        H[N:, :N] = H[:N, N:].T
        H[N:, N:] = wz * S.T @ S + wf * M.T @ M
        scale = self.cost_scale = 2.0 / H.diagonal().max()  # largest diagonal entry of P is 1
        self._H = H
        P, q = np.zeros((self.n, self.n)), np.zeros(self.n)
        zmp_free, vel_free = pred["Pzs"] @ x0, pred["Pvs"] @ x0  # (N, 2)
        scaled = scale * H
        for a in range(2):
            # P[np.ix_(cols, cols)] = scaled, block by block: the jerks and the footsteps
            # of axis a are two ranges of columns
            jerk, foot = slice(a * N, (a + 1) * N), slice(2 * N + a * nf, 2 * N + (a + 1) * nf)
            P[jerk, jerk] = scaled[:N, :N]
            P[jerk, foot] = scaled[:N, N:]
            P[foot, jerk] = scaled[N:, :N]
            P[foot, foot] = scaled[N:, N:]
            z_res = zmp_free[:, a] - centres[:, a]
            v_res = vel_free[:, a] - velocity_reference[:, a]
            q[jerk] = scale * (zmp_rows @ z_res + velocity_rows @ v_res)
            q[foot] = scale * (-wz * S.T @ z_res - wf * M.T @ steps.reference[:, a])
        self.P, self.q = P, q
        self.x0, self.time, self.sample_times = x0.copy(), float(t), times
        flat = np.flatnonzero(supports.rows)  # the ZMP rows: the real rows of every point
        blocks = self._step_rows(steps)
        blocks.append(self._extra_rows(supports))
        self.terminal_rows = 0
        if p.capturability:
            blocks.append(self._terminal_dcm_rows(x0, supports))
            self.terminal_rows = len(blocks[-1][1])
        # the ZMP rows made in G, then the others (the terminal ones last: without_terminal_rows)
        self.m = len(flat) + sum(len(bound) for _, bound in blocks)
        self.G, self.h = np.empty((self.m, self.n)), np.empty(self.m)
        self._zmp_rows(x0, supports, flat, self.G[: len(flat)], self.h[: len(flat)])
        row = len(flat)
        for block, bound in blocks:
            self.G[row : row + len(bound)] = block
            self.h[row : row + len(bound)] = bound
            row += len(bound)
        self.supports = supports
        self._initial_footsteps = np.asarray(steps.initial, dtype=float)

    def _constraints(self, x0, supports: SampleSupports, steps: StepVariables):
        """The ``(G, h)`` blocks of the ZMP, reach, box and band rows (:meth:`update`'s)."""
        flat = np.flatnonzero(supports.rows)
        G_zmp, h_zmp = np.empty((len(flat), self.n)), np.empty(len(flat))
        self._zmp_rows(x0, supports, flat, G_zmp, h_zmp)
        return [(G_zmp, h_zmp), *self._step_rows(steps)]

    def _zmp_rows(self, x0, supports: SampleSupports, flat, G_zmp, h_zmp) -> None:
        """Write the ZMP rows of the real rows ``flat`` (flat indices into
        ``supports.rows``, in order) into ``G_zmp`` and ``h_zmp``."""
        N, nf = self.N, self.nf
        point = flat // supports.rows.shape[1]
        normals = supports.normals.reshape(-1, 2).take(flat, axis=0)  # (m_z, 2)
        G_zmp[:, self.n_base :] = 0.0  # a subclass's columns
        Pzu, S = self._pred["Czu"].take(point, axis=0), supports.weights.take(point, axis=0)
        zmp_free = self._pred["Czs"].take(point, axis=0) @ x0
        for a in range(2):
            np.multiply(normals[:, a : a + 1], Pzu, out=G_zmp[:, a * N : (a + 1) * N])
            foot = G_zmp[:, 2 * N + a * nf : 2 * N + (a + 1) * nf]
            np.multiply(-normals[:, a : a + 1], S, out=foot)
        h_zmp[:] = (
            supports.offsets.reshape(-1).take(flat)
            - self.parameters.zmp_margin
            - np.einsum("ra,ra->r", normals, zmp_free)
        )

    def _step_rows(self, steps: StepVariables) -> list[tuple[np.ndarray, np.ndarray]]:
        """The footsteps' reach, box and band rows."""
        N, nf = self.N, self.nf
        reach: tuple[np.ndarray, ...] = (steps.active, steps.predecessor, steps.predecessor_yaw)
        reach += (steps.predecessor_xy, steps.lower, steps.upper)
        # the same read-only arrays (the slots keep them while the footsteps stay): the
        # same rows
        cached = self._reach_rows
        if cached is None or any(a is not b for a, b in zip(cached[0], reach)):
            cached = (reach, reach_rows(steps, self.n, N, nf))
            if not any(array.flags.writeable for array in reach):
                self._reach_rows = cached
        return [cached[1], box_rows(steps, self.n, N, nf), band_rows(steps, self.n, N, nf)]

    def _extra_rows(self, supports: SampleSupports) -> tuple[np.ndarray, np.ndarray]:
        """Rows a subclass adds after the ZMP, reach and band rows (and before the terminal
        DCM rows) of the tick just updated: none here."""
        return np.zeros((0, self.n)), np.zeros(0)

    def _terminal_dcm_rows(self, x0, supports: SampleSupports):
        """``normal . (xi_N - S_N F) <= offset``: the DCM at the last sample inside the
        support of the last constraint point (the last sample), affine in the jerks and the
        footsteps like the ZMP rows."""
        N, nf, last = self.N, self.nf, len(supports.rows) - 1
        rows = np.flatnonzero(supports.rows[last])
        normals = supports.normals[last, rows]  # (r, 2)
        S = supports.weights[last]
        G = np.zeros((len(rows), self.n))
        dcm_free = self._pred["Pds"] @ x0  # (2,)
        for a in range(2):
            G[:, a * N : (a + 1) * N] = normals[:, a : a + 1] * self._pred["Pdu"][None, :]
            G[:, 2 * N + a * nf : 2 * N + (a + 1) * nf] = -normals[:, a : a + 1] * S[None, :]
        h = supports.offsets[last, rows] - normals @ dcm_free
        return G, h

    def without_terminal_rows(self) -> None:
        """Drop the terminal DCM rows of the last :meth:`update` (the fallback when no plan
        meets them)."""
        if self.terminal_rows:
            self.G, self.h = self.G[: -self.terminal_rows], self.h[: -self.terminal_rows]
            self.m, self.terminal_rows = len(self.h), 0

    def terminal_dcm(self, x: np.ndarray) -> np.ndarray:
        """DCM at the last sample of a solution, shape (2,), in [m]."""
        return self._pred["Pds"] @ self.x0 + self._pred["Pdu"] @ self.jerks(x)

    def cost_factor(self) -> tuple[np.ndarray, np.ndarray]:
        """The cost matrix of the last :meth:`update` factorised from its blocks: ``(order,
        R_inv)`` with ``P[order][:, order] = R^T R``, ``R`` upper triangular, ``R_inv`` its
        inverse (what an active-set solver such as quadprog starts from).

        In the order of each axis's jerks then footsteps, ``P`` is the same block ``s H``
        twice (the axes share the cost). The jerks' block of ``H`` depends on the first
        interval alone: its factor is computed once per first interval, and each tick adds
        the footsteps' border (:func:`~mpcwalk.qp.cost_factor.bordered_inverse_factor`).

        Raises:
            numpy.linalg.LinAlgError: The footsteps' block is not positive definite.
        """
        self.require_update()
        N, nf = self.N, self.nf
        inverse_11 = self._pred.get("H_jerk_inverse_factor")
        if inverse_11 is None:
            inverse_11 = self._pred["H_jerk_inverse_factor"] = inverse_cholesky(
                self._pred["H_jerk"]
            )
        block = bordered_inverse_factor(inverse_11, self._H) / np.sqrt(self.cost_scale)
        inverse = np.zeros((self.n, self.n))
        inverse[: N + nf, : N + nf] = block
        inverse[N + nf : 2 * (N + nf), N + nf : 2 * (N + nf)] = block
        return np.concatenate(self._columns), inverse

    def problem(self, dense: bool = True) -> qpsolvers.Problem:
        """The QP in qpsolvers form ``min 1/2 x'Px + q'x, G x <= h`` (dense arrays; the
        ``dense`` flag of the solver interface is accepted, the matrices are dense anyway,
        converted to CSC when ``dense`` is False)."""
        self.require_update()
        if dense:
            return qpsolvers.Problem(self.P, self.q, self.G, self.h)
        import scipy.sparse as sp

        return qpsolvers.Problem(sp.csc_matrix(self.P), self.q, sp.csc_matrix(self.G), self.h)

    def dense_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(P, q, G, h)`` of the last :meth:`update` (the QP's own arrays)."""
        self.require_update()
        return self.P, self.q, self.G, self.h

    def require_update(self) -> None:
        """Raise NotReset before the first :meth:`update`."""
        if self.x0 is None:
            raise NotReset("FootstepQP.update(...) must be called before solving.")

    # ------------------------------------------------------------- solutions
    def jerks(self, x: np.ndarray) -> np.ndarray:
        """CoM jerks of a solution, shape (N, 2), in [m]/[s]^3."""
        return np.asarray(x)[: 2 * self.N].reshape(2, self.N).T

    def footsteps(self, x: np.ndarray) -> np.ndarray:
        """Footstep positions of a solution, shape (nf, 2), in [m]."""
        return np.asarray(x)[2 * self.N :].reshape(2, self.nf).T

    def predict(self, jerks: np.ndarray) -> Prediction:
        """Exact states at the samples of the last :meth:`update` for jerks (N, 2)."""
        self.require_update()
        pred = self._pred  # this tick's maps, and a copy of the jerks: the states made when read
        maps = tuple(pred[k] for k in ("Pps", "Ppu", "Pvs", "Pvu", "Pas", "Pau", "Pzs", "Pzu"))
        states = predicted_states(maps, self.x0, np.array(jerks, dtype=float))
        return Prediction(times=self.sample_times.copy(), states=states)

    def shift_primal(self, x: np.ndarray, samples: float) -> np.ndarray:
        """Warm start: jerks shifted by ``samples`` sampling periods (linear interpolation,
        last one held), footsteps at their current positions."""
        U = self.jerks(x)
        pos = np.clip(np.arange(self.N) + samples, 0.0, self.N - 1)
        U = np.stack([np.interp(pos, np.arange(self.N), U[:, a]) for a in range(2)], axis=1)
        return np.concatenate([U.T.ravel(), self._initial_footsteps.T.ravel()])
