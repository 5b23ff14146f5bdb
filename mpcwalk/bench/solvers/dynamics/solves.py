"""The timed solves of the inverse-dynamics problem set: every back-end that takes its QP
(equalities and inequalities), cold and warm, at the benchmark's tolerance levels.

*Cold*: a new back-end object solves the snapshot. *Warm*: a new back-end object first
solves the ticks before it along the walk, each warm-started from the tick before when the
contacts did not change (as :class:`~mpcwalk.ik.inverse_dynamics.InverseDynamicsQP` does),
then the snapshot: only that last solve is timed. The time is the back-end call as its
:class:`~mpcwalk.qp.result.QPResult` reports it. A solve is judged as every other of the
benchmark (:meth:`~mpcwalk.bench.solvers.tolerances.ToleranceLevel.is_success`: the primal
and dual residuals and the duality gap recomputed here on the OSQP form, under the level's
tolerance and time limit); the row also gives the cost gap and the largest torque difference
to a reference solution (:data:`REFERENCE_BACKENDS`: an exact active-set solve), and the
largest residual of the floating base's six equations of motion [N, N m].
"""

import math
from typing import cast

import numpy as np
import scipy.sparse as sp

from mpcwalk.bench.solvers.backends.registry import (
    KNOWN_SLOW_BACKENDS,
    OPTI_BACKEND,
    benchmark_backends,
    make_backend,
    supports_warm_start,
)
from mpcwalk.bench.solvers.dynamics.capture import DynamicsProblem, DynamicsQPValues
from mpcwalk.bench.solvers.tolerances import ToleranceLevel, select_levels
from mpcwalk.ik.dynamics_program import (
    DEFAULT_DYNAMICS_SOLVER,
    DynamicsProgram,
    dynamics_solver_names,
)
from mpcwalk.qp.program import FixedPatternProgram
from mpcwalk.qp.result import QPResult, kkt_residuals
from mpcwalk.qp.solvers.base import QPSolver, failure
from mpcwalk.qp.solvers.registry import make_solver

#: The reference solution's back-end, the first one installed: dual active-set solvers,
#: exact up to round-off.
REFERENCE_BACKENDS = ("quadprog", "daqp-direct", "daqp")


def dynamics_backends(names: tuple[str, ...] | None = None) -> list[str]:
    """The back-ends of the inverse-dynamics stage: ``names`` (None: every one installed)
    that take its QP, the controller's default first."""
    takes = set(dynamics_solver_names())
    if names is None:
        names = (DEFAULT_DYNAMICS_SOLVER, *benchmark_backends(include_opti=False))
    chosen = [n for n in dict.fromkeys(names) if n in takes and n not in KNOWN_SLOW_BACKENDS]
    return [n for n in chosen if n != OPTI_BACKEND]


class DynamicsSolves:
    """Solves inverse-dynamics cases in one process, one program per QP size."""

    def __init__(self) -> None:
        self._programs: dict[tuple[int, int, int], DynamicsProgram] = {}

    def program(self, values: DynamicsQPValues) -> DynamicsProgram:
        """The program of ``values``' size, loaded with them."""
        n, m = len(values.q), len(values.l)
        key = (n, values.m_eq, m)
        program = self._programs.get(key)
        if program is None:
            program = self._programs[key] = DynamicsProgram(n, values.m_eq, m - values.m_eq)
        values.load(program)
        return program

    def run(self, cases: list[tuple[DynamicsProblem, str, ToleranceLevel, str]]) -> list[dict]:
        """The rows of ``cases`` ``(problem, back-end, level, start)``, in order."""
        references = {}
        rows = []
        for problem, backend, level, start in cases:
            if problem.name not in references:
                references[problem.name] = self.reference(problem)
            rows.append(self.solve(problem, backend, level, start, references[problem.name]))
        return rows

    def reference(self, problem: DynamicsProblem) -> np.ndarray | None:
        """The reference solution of ``problem`` (None: no reference back-end solved it)."""
        installed = dynamics_solver_names()
        for name in REFERENCE_BACKENDS:
            if name in installed:
                program = cast(FixedPatternProgram, self.program(problem.qp))
                result = make_solver(name).solve(program)
                if result.success and result.x is not None:
                    return np.array(result.x)
        return None

    def solve(
        self,
        problem: DynamicsProblem,
        backend: str,
        level: ToleranceLevel,
        start: str,
        reference: np.ndarray | None,
    ) -> dict:
        """One case; an error of the back-end becomes a failed row."""
        row = {
            "problem": problem.name,
            "robot": problem.robot,
            "phase": problem.phase,
            "pushed": problem.pushed,
            "n": problem.n,
            "m": problem.m,
            "m_eq": problem.qp.m_eq,
            "solver": backend,
            "tolerance": level.name,
            "start": start,
        }
        warmup: list[float] = []
        try:
            solver = make_backend(backend, level)
            previous = None
            if start == "warm":
                for values in problem.warmup:
                    result = self._tick(solver, values, previous)
                    previous = values.contacts
                    warmup.append(result.solve_time)
                    if not result.success:
                        solver.reset()
            result = self._tick(solver, problem.qp, previous)
        except Exception as error:
            text = " ".join(f"{type(error).__name__}: {error}".split())[:160]
            result = failure(backend, f"error: {text}", level.runtime)
        return row | _judge(problem, level, result, reference, warmup)

    def _tick(self, solver: QPSolver, values: DynamicsQPValues, previous) -> QPResult:
        program = cast(FixedPatternProgram, self.program(values))
        solver.check(program)
        return solver.solve(program, shift=0.0 if values.contacts == previous else 1.0)


def _judge(
    problem: DynamicsProblem,
    level: ToleranceLevel,
    result: QPResult,
    reference: np.ndarray | None,
    warmup: list[float],
) -> dict:
    """The measured columns of a row."""
    qp = problem.qp
    x = result.x
    found = bool(result.success and x is not None and np.all(np.isfinite(x)))
    primal = dual = gap = cost_gap = torque_error = base = math.nan
    if found:
        assert x is not None
        primal_, dual_, gap_ = kkt_residuals(
            sp.csc_matrix(qp.P), qp.q, sp.csc_matrix(qp.A), qp.l, qp.u, x, result.y
        )
        primal = primal_
        dual = math.nan if dual_ is None else dual_
        gap = math.nan if gap_ is None else gap_
        base = float(np.abs(problem.generalized_forces(x)[:6]).max())
        if reference is not None:
            cost_ref = qp.cost(reference)
            cost_gap = (qp.cost(x) - cost_ref) / (1.0 + abs(cost_ref))
            torque_error = float(np.abs(problem.torques(x) - problem.torques(reference)).max())
    success = level.is_success(
        found,
        None if math.isnan(primal) else primal,
        None if math.isnan(dual) else dual,
        None if math.isnan(gap) else gap,
        result.solve_time,
    )
    return {
        "runtime": float(result.solve_time),
        "found": found,
        "primal_residual": primal,
        "dual_residual": dual,
        "duality_gap": gap,
        "cost_gap": cost_gap,
        "torque_error": torque_error,
        "base_residual": base,
        "success": success,
        "timeout": level.is_timeout(result.solve_time),
        "status": " ".join(str(result.status).split())[:80],
        "warmup_runtime": float(np.median(warmup)) if warmup else math.nan,
    }


def dynamics_cases(
    problems: list[DynamicsProblem],
    backends: list[str],
    levels: tuple[str, ...],
    starts: tuple[str, ...],
    time_limit: float,
    seed: int = 0,
) -> list[tuple[DynamicsProblem, str, ToleranceLevel, str]]:
    """Every case (problem x back-end x level x start; warm only for back-ends that take a
    start), cold before warm, shuffled otherwise (seeded) so that a drift of the machine's
    load spreads over all back-ends."""
    chosen = select_levels(levels, time_limit)
    cases = [
        (problem, backend, level, start)
        for problem in problems
        for backend in backends
        for level in chosen.values()
        for start in starts
        if start == "cold" or supports_warm_start(backend)
    ]
    order = np.random.default_rng(seed).permutation(len(cases))
    shuffled = [cases[i] for i in order]
    return sorted(shuffled, key=lambda case: case[3] == "warm")


def run_dynamics_solves(cases) -> list[dict]:
    """The rows of ``cases`` (a function of the module: a timing actor runs it)."""
    return DynamicsSolves().run(cases)
