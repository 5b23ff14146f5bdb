"""Direct, hot-started DAQP back-end (DAQP's own workspace API).

DAQP (a dual active-set solver) keeps its workspace between calls: the Cholesky factor of
the Hessian, the constraint matrix in its transformed space and the working set of the last
solve. On a QP whose matrices keep their values from tick to tick (the fixed-footstep
walking QP: ``P`` never changes, ``A`` only when the polygons over the horizon change),
each tick then only pushes the vectors: no refactorisation, and the solve starts from the
active set of the previous tick (hot start). Such a QP is handed to DAQP whitened: with
``P = R^T R`` factorised here (once per distinct ``P``, kept for the next time it comes
back), DAQP solves for ``v = R x`` with an identity cost, the gradient ``R^-T q`` and the
rows ``G R^-1``. A new ``A`` is then a product here (the walking QP makes its whitened rows
itself, ``whitened_inequalities``, from one axis's factor when its two axes share the cost;
other QPs, one small BLAS product per diagonal block of ``P``), where DAQP's own transform
of the rows takes several times longer, and a new ``P`` (the static gait's CoM weight moving
along the horizon) is a new ``A`` and gradient only: the working set is kept in both cases.
The residuals are taken in the whitened variables (``M v = G x``, ``R^T (v + f + M^T z) =
P x + q + G^T z``). QPs rebuilt every tick (the footstep-adaptive MPC's) are set up anew
each tick, with the shifted previous solution as the primal start.
A dense QP with equality rows that offers them (``dense_rows()``: the inverse dynamics') is
solved in one call, the equalities held in the working set for good (DAQP's sense 5).
"""

import functools
import time

import daqp
import numpy as np
import scipy.linalg

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.qp.kept import kept
from mpcwalk.qp.program import QuadraticProgram
from mpcwalk.qp.result import QPResult
from mpcwalk.qp.solvers.base import QPSolver, dense_residuals, failure, found

_INFINITY = 1e30  # DAQP's "no bound"


class DaqpSolver(QPSolver):
    """DAQP through its workspace (``daqp.Model``), hot-started.

    Only the dense formulation (a positive definite ``P``; inequality rows only, or
    equalities given by the program's ``dense_rows()``) applies.

    Args:
        settings: DAQP settings (``primal_tol``, ``dual_tol``, ``iter_limit``...), given to
            the workspace at each set-up.
    """

    name = "daqp-direct"

    def __init__(self, **settings) -> None:
        known = daqp.Model().settings  # DAQP ignores unknown keys silently: refuse them here
        unknown = sorted(set(settings) - set(known))
        if unknown:
            raise ConfigurationError(
                f"Solver '{self.name}' does not take the settings {', '.join(unknown)}; its "
                f"settings are {', '.join(known)}."
            )
        for key, value in settings.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ConfigurationError(
                    f"Solver '{self.name}' setting {key} must be a number, got {value!r}."
                )
        self.settings = settings
        self._model: daqp.Model | None = None
        self._qp: QuadraticProgram | None = None
        self._versions = (-1, -1)
        self._previous: np.ndarray | None = None
        self._lower = np.zeros(0)
        self._sense = np.zeros(0, dtype=np.int32)
        self._row_sense = np.zeros(0, dtype=np.int32)  # the rows of dense_rows(): m_eq first
        self._row_shape = (0, 0)
        self._whitening: _Whitening | None = None  # of the fixed QP's P (None: not whitened)
        self._whitenings = _Whitenings()
        self._rows = np.zeros((0, 0))  # the whitened rows DAQP holds

    def reset(self) -> None:
        self._model = self._qp = self._previous = self._whitening = None
        self._versions = (-1, -1)
        self._whitenings = _Whitenings()

    def check(self, qp: QuadraticProgram) -> None:
        if qp.formulation == "sparse" or (qp.m_eq and not hasattr(qp, "dense_rows")):
            raise ConfigurationError(
                f"Solver '{self.name}' needs a positive definite cost matrix and inequality "
                "rows only, but the sparse formulation's P is only semidefinite (states are "
                "not penalised in every direction); use formulation='dense' with it."
            )

    def _setup(self, P, q, G, h, primal_start=None) -> bool:
        m = len(h)
        if len(self._lower) != m:
            self._lower = np.full(m, -_INFINITY)
            self._sense = np.zeros(m, dtype=np.int32)
        model = daqp.Model()
        if self.settings:
            model.settings = dict(self.settings)
        exitflag, _ = model.setup(P, q, G, h, self._lower, self._sense, primal_start=primal_start)
        self._model = model if exitflag >= 0 else None
        return self._model is not None

    def solve(self, qp: QuadraticProgram, *, shift: float = 0.0) -> QPResult:
        self.check(qp)
        qp.require_update()
        if qp.m_eq:
            return self._solve_rows(qp)
        if qp.fixed_pattern:
            return self._solve_fixed(qp)
        # A QP rebuilt every tick: set up anew, from the shifted previous solution.
        start = time.perf_counter()
        P, q, G, h = qp.dense_arrays()  # DAQP reads bounds >= 1e30 (and inf) as none
        primal_start = None
        if self._previous is not None and self._qp is qp:
            primal_start = qp.shift_primal(self._previous, shift)
        self._qp, self._whitening = qp, None
        ready = self._setup(P, q, G, _writable(h), primal_start)
        return self._solved(ready, start, lambda x, z: dense_residuals(P, q, G, h, x, z))

    def _solve_fixed(self, qp) -> QPResult:
        """A QP whose matrices keep their values from tick to tick (see the module's
        documentation): whitened, hot-started; set up anew only for a new problem or a ``P``
        that is not positive definite."""
        start = time.perf_counter()
        versions = (qp.P_version, qp.A_version)
        # a QP that builds its rows times a factor itself (two identical axis blocks)
        structured = hasattr(qp, "whitened_inequalities")
        model = self._model if self._qp is qp else None
        W = self._whitening
        if model is None or versions[0] != self._versions[0]:
            W = self._whitenings.get(qp.dense_cost() if structured else qp.dense_arrays()[0])
            if W is None or self._whitening is None:  # DAQP factorises P itself
                model = None
        self._qp, self._whitening = qp, W
        if W is None:
            P, q, G, h = qp.dense_arrays()
            h = _writable(h)
            if model is None:
                ready = self._setup(P, q, G, h)
            elif versions != self._versions:  # new rows: the working set stays
                ready = model.update(A=G, f=q, bupper=h) >= 0
            else:  # (no rows: DAQP takes no empty bound vector)
                ready = model.update(f=q, bupper=h if len(h) else None) >= 0
            self._versions = versions
            return self._solved(ready, start, lambda x, z: dense_residuals(P, q, G, h, x, z))
        if structured:
            q, h = qp.q, _writable(qp.u)
        else:
            _, q, _, h = qp.dense_arrays()
            h = _writable(h)
        f = W.inverse.T @ q
        if model is None or versions != self._versions:  # new rows: the working set stays
            if structured and W.axis is not None:
                self._rows = qp.whitened_inequalities(W.axis)
            else:
                self._rows = W.rows(qp.dense_arrays()[2])
            if model is None:
                ready = self._setup(np.eye(len(q)), f, self._rows, h)
            else:
                ready = model.update(A=self._rows, f=f, bupper=h) >= 0
        else:  # (no rows: DAQP takes no empty bound vector)
            ready = model.update(f=f, bupper=h if len(h) else None) >= 0
        self._versions = versions
        M = self._rows

        def residuals(v, z):
            # in the whitened variables: M v = G x, R^T (v + f + M^T z) = P x + q + G^T z
            primal = float(max(0.0, np.max(M @ v - h))) if len(h) else 0.0
            binding = np.flatnonzero(z)  # M^T z over the rows with a multiplier
            dual = float(np.max(np.abs(W.factor.T @ (v + f + z[binding] @ M[binding]))))
            return primal, dual, float(abs(v @ v + f @ v + h @ z))

        return self._solved(ready, start, residuals, W.inverse)

    def _solved(self, ready: bool, start: float, residuals, back=None) -> QPResult:
        """Solve the problem set up (``ready``) and build the result: ``residuals(x, z)``
        in DAQP's variables, ``back`` the map from them to the QP's (None: the same)."""
        if not ready or self._model is None:
            self._model = self._previous = None
            return failure(self.name, "setup failed", time.perf_counter() - start)
        v, _, exitflag, info = self._model.solve()
        elapsed = time.perf_counter() - start
        if exitflag <= 0:
            self._model = self._previous = None  # start the next tick from scratch
            return failure(self.name, f"exitflag {exitflag}", elapsed)
        v = np.array(v, dtype=float)
        z = np.array(info["lam"], dtype=float)
        x = v if back is None else back @ v
        self._previous = x
        # computed when read (the rows and vectors they use are not changed in place)
        return self._found(x, z, elapsed, info, functools.partial(residuals, v, z))

    def _found(self, x, z, elapsed: float, info, residuals) -> QPResult:
        """The result of a solve DAQP found, with its (primal, dual, gap) residuals."""
        return found(self.name, x, z, elapsed, int(info["iterations"]), residuals)

    def _solve_rows(self, qp) -> QPResult:
        """A dense QP with equality rows (``dense_rows()``: ``lower <= A x <= upper``, the
        ``m_eq`` equalities first), its values new each tick (the inverse dynamics'): DAQP
        holds the equalities in its working set for good (sense 5: active, immutable)."""
        start = time.perf_counter()
        P, q, A, lower, upper = qp.dense_rows()
        shape = (len(upper), int(qp.m_eq))
        if self._row_sense.shape != (shape[0],) or self._row_shape != shape:
            self._row_sense = np.zeros(shape[0], dtype=np.int32)
            self._row_sense[: shape[1]] = 5
            self._row_shape = shape
        self._model = None
        x, _, exitflag, info = daqp.solve(P, q, A, upper, lower, self._row_sense, **self.settings)
        elapsed = time.perf_counter() - start
        if exitflag <= 0:
            return failure(self.name, f"exitflag {exitflag}", elapsed)
        x = np.asarray(x, dtype=float)
        z = np.asarray(info["lam"], dtype=float)
        Ax = A @ x
        primal = float(max(0.0, np.max(Ax - upper), np.max(lower - Ax)))
        dual = float(np.max(np.abs(P @ x + q + A.T @ z)))
        return self._found(x, z, elapsed, info, (primal, dual, None))


class _Whitening:
    """``R^-1`` of a positive definite ``P = R^T R`` (``R`` upper triangular), kept per
    diagonal block of ``P`` (the walking QP's two axes): the rows ``G R^-1`` are products of
    a block's columns with its own small factor, each small enough that the BLAS runs them
    on the calling thread (one product of the whole matrix woke BLAS threads, and their
    start-up reached milliseconds on a busy machine).

    Raises:
        numpy.linalg.LinAlgError: ``P`` is not positive definite.
    """

    _PRODUCT_SIZE = 256 * 32 * 32  # rows x columns x columns of one product, at most

    def __init__(self, P: np.ndarray) -> None:
        n = len(P)
        # block b ends after row i when no row up to i reaches a column after i
        nonzero = P != 0.0
        last = n - 1 - np.argmax(nonzero[:, ::-1], axis=1)
        ends = np.flatnonzero(np.maximum.accumulate(last) <= np.arange(n)) + 1
        self.inverse = np.zeros((n, n))
        """``R^-1``, shape (n, n)."""
        self.factor = np.zeros((n, n))
        """``R``, shape (n, n)."""
        self.blocks: list[tuple[slice, np.ndarray]] = []
        for start, stop in zip(np.concatenate([[0], ends[:-1]]), ends):
            lower = np.linalg.cholesky(P[start:stop, start:stop])
            inverse_lower, info = scipy.linalg.lapack.dtrtri(lower, lower=1)
            if info:  # pragma: no cover - a Cholesky factor has a positive diagonal
                raise np.linalg.LinAlgError("singular Cholesky factor")
            block = slice(int(start), int(stop))
            self.inverse[block, block] = inverse_lower.T
            self.factor[block, block] = lower.T
            self.blocks.append((block, self.inverse[block, block]))
        half = n // 2
        two_axes = [(b.start, b.stop) for b, _ in self.blocks] == [(0, half), (half, n)]
        self.axis: np.ndarray | None = (
            self.blocks[0][1]
            if two_axes and np.array_equal(P[:half, :half], P[half:, half:])
            else None
        )
        """The factor of one axis when ``P`` is two identical axis blocks (the walking QP's:
        the axes share the cost), else None."""

    def rows(self, G: np.ndarray) -> np.ndarray:
        """``G R^-1``."""
        out = np.empty_like(G)
        for columns, inverse in self.blocks:
            step = max(1, self._PRODUCT_SIZE // len(inverse) ** 2)
            for first in range(0, len(G), step):
                out[first : first + step, columns] = G[first : first + step, columns] @ inverse
        return out


class _Whitenings:
    """The whitenings of the last distinct cost matrices (a QP whose ``P`` cycles through a
    few values, as the static gait's, factorises each once)."""

    _SIZE = 64

    def __init__(self) -> None:
        self._by_matrix: dict[bytes, _Whitening | None] = {}

    def get(self, P: np.ndarray) -> _Whitening | None:
        """The whitening of ``P``, None when ``P`` is not positive definite."""

        def make() -> _Whitening | None:
            try:
                return _Whitening(P)
            except np.linalg.LinAlgError:
                return None

        return kept(self._by_matrix, P.tobytes(), make, self._SIZE)


def _writable(h: np.ndarray) -> np.ndarray:
    """``h`` as DAQP takes it (a writable buffer)."""
    return h if h.flags.writeable else h.copy()
