"""One benchmark case: a problem, a formulation, a back-end, a tolerance level
and a start (cold or warm), solved and checked; one row of ``results.csv.gz``.

*Cold*: a new back-end object solves the problem (OSQP's setup and
factorisation included; for CasADi the symbolic construction of the conic
function is not timed, as in a controller that builds it once). *Warm*: a new
back-end object first solves the ``W`` ticks that precede the problem along
the walk (nominal states, each warm-started from the shifted solution of the
tick before, as in the controller), then the problem itself: only that last
solve is timed, and the case is a timeout if any of these solves exceeds the
time limit (the back-end could not follow the walk). The time is the
back-end call as :class:`~mpcwalk.qp.QPResult` reports it (vector and matrix
updates included; the QP's own update is excluded, it is the same for every
back-end). Residuals are recomputed here, the same way for every back-end,
on the OSQP form of the problem.
"""

import functools
import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.bench.solvers.backends.registry import make_backend
from mpcwalk.bench.solvers.problems.families import WalkingProblem, get_family
from mpcwalk.bench.solvers.tolerances import ToleranceLevel
from mpcwalk.qp.result import kkt_residuals

STARTS = ("cold", "warm")
#: Columns of ``results.csv.gz``, in order.
CSV_COLUMNS = (
    "problem",
    "set",
    "family",
    "walk",
    "horizon",
    "sampling_period",
    "tick",
    "time",
    "pushed",
    "formulation",
    "n",
    "m",
    "solver",
    "tolerance",
    "start",
    "runtime",
    "found",
    "primal_residual",
    "dual_residual",
    "duality_gap",
    "success",
    "timeout",
    "iterations",
    "status",
    "warmup_runtime",
)


@dataclass(frozen=True)
class SolverCase:
    """What one row of the results measures.

    Attributes:
        problem: The walking QP.
        formulation: ``"dense"`` or ``"sparse"``.
        backend: Back-end name.
        level: Tolerance level.
        start: ``"cold"`` or ``"warm"``.
        problem_set: ``"main"``, ``"sweep"`` or ``"main+sweep"``.
    """

    problem: WalkingProblem
    formulation: str
    backend: str
    level: ToleranceLevel
    start: str
    problem_set: str = "main"

    @property
    def group(self) -> tuple:
        """Cases that should time out together (same everything but the snapshot)."""
        return (self.formulation, self.backend, self.level.name, self.start, self.problem.horizon)

    @property
    def nb_solves(self) -> int:
        """Solves the case makes (warm-up ticks included)."""
        return 1 + (len(self.problem.warmup_times) if self.start == "warm" else 0)


def make_row(
    case: SolverCase,
    *,
    runtime: float,
    found: bool,
    primal: float | None = None,
    dual: float | None = None,
    gap: float | None = None,
    iterations: int | None = None,
    status: str = "",
    n: int | None = None,
    m: int | None = None,
    warmup_runtime: float | None = None,
    timeout: bool | None = None,
) -> dict:
    """One results row (a dict keyed by :data:`CSV_COLUMNS`); ``timeout``
    defaults to ``runtime`` over the level's time limit."""
    p, level = case.problem, case.level
    timeout = level.is_timeout(runtime) if timeout is None else bool(timeout)
    if n is None or m is None:
        n, m = qp_size(p.family, p.horizon, case.formulation, p.control_period)
    return {
        "problem": p.name,
        "set": case.problem_set,
        "family": p.family,
        "walk": p.walk,
        "horizon": p.horizon,
        "sampling_period": p.sampling_period,
        "tick": p.tick,
        "time": p.time,
        "pushed": p.pushed,
        "formulation": case.formulation,
        "n": n,
        "m": m,
        "solver": case.backend,
        "tolerance": level.name,
        "start": case.start,
        "runtime": float(runtime),
        "found": bool(found),
        "primal_residual": _num(primal),
        "dual_residual": _num(dual),
        "duality_gap": _num(gap),
        "success": level.is_success(found, primal, dual, gap, runtime) and not timeout,
        "timeout": timeout,
        "iterations": iterations,
        "status": status,
        "warmup_runtime": _num(warmup_runtime),
    }


@functools.lru_cache(maxsize=256)
def qp_size(family: str, horizon: int, formulation: str, control_period: float) -> tuple[int, int]:
    """Variables and constraint rows ``(n, m)`` of a family's QP (OSQP form)."""
    qp = get_family(family).build_qp(horizon, formulation, control_period)
    return qp.n, qp.m


def _num(value: float | None) -> float:
    return math.nan if value is None else float(value)


class CaseSolver:
    """Solves cases in one process, keeping one QP object per problem structure."""

    def __init__(self) -> None:
        self._qps: dict[tuple, object] = {}

    def qp(self, problem: WalkingProblem, formulation: str):
        """The (cached) QP object of ``problem``'s structure."""
        key = problem.qp_key + (formulation,)
        if key not in self._qps:
            family = get_family(problem.family)
            self._qps[key] = family.build_qp(problem.horizon, formulation, problem.control_period)
        return self._qps[key]

    def solve(self, case: SolverCase) -> dict:
        """Solve ``case``; any error becomes a failed row, never an exception."""
        try:
            return self._solve(case)
        except Exception as error:
            text = " ".join(f"{type(error).__name__}: {error}".split())[:160]
            return make_row(case, runtime=case.level.runtime, found=False, status=f"error: {text}")

    def _solve(self, case: SolverCase) -> dict:
        problem = case.problem
        qp = self.qp(problem, case.formulation)
        # Matrices handed to solvers are cached by the QP; qpsolvers' sip edits its
        # input in place (eliminate_zeros through a matrix sharing our arrays), which
        # leaves the cached matrix inconsistent: each case starts from fresh ones.
        cache = getattr(qp, "_cache", None)
        if isinstance(cache, dict):
            cache.clear()
        schedule = problem.schedule()
        family = get_family(problem.family)
        solver = make_backend(case.backend, case.level)
        solver.check(qp)
        shift = problem.control_period / problem.sampling_period
        warmup: list[float] = []
        if case.start == "warm":
            for t, state in zip(problem.warmup_times, problem.warmup_states):
                family.update_qp(qp, state, float(t), schedule)
                warmup.append(solver.solve(qp, shift=shift).solve_time)
                if case.level.is_timeout(warmup[-1]):  # the back-end cannot follow the walk
                    return make_row(
                        case,
                        runtime=warmup[-1],
                        found=False,
                        n=qp.n,
                        m=qp.m,
                        status="warm-up tick over the time limit",
                        timeout=True,
                    )
        family.update_qp(qp, problem.state, problem.time, schedule)
        result = solver.solve(qp, shift=shift)
        primal = dual = gap = None
        if result.success and result.x is not None:
            primal, dual, gap = kkt_residuals(qp.P, qp.q, qp.A, qp.l, qp.u, result.x, result.y)
        return make_row(
            case,
            runtime=result.solve_time,
            found=result.success,
            primal=primal,
            dual=dual,
            gap=gap,
            iterations=result.iterations,
            status=" ".join(str(result.status).split())[:80],
            n=qp.n,
            m=qp.m,
            warmup_runtime=float(np.median(warmup)) if warmup else None,
        )
