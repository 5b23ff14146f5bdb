"""The receding-horizon core the QP generators share: solve, plan, fallback.

Each tick a receding-horizon generator rewrites its QP
(:class:`~mpcwalk.qp.program.QuadraticProgram`) from the current CoM state and hands it to
its back-end (:mod:`mpcwalk.qp.solvers`). A solved QP becomes the plan: its CoM jerks and
the states they predict (:class:`~mpcwalk.qp.program.Prediction`, the output's horizon),
and the generator moves its state one control period along it. A failed solve does not
stop the walk: the generator keeps integrating the jerks of the last plan from its own
state (the measured state is ignored until a solve succeeds again) and says so in the
output's :class:`~mpcwalk.generators.pattern_generator.SolveInfo`, for at most
``max_fallback_ticks`` ticks in a row; then it raises
:class:`~mpcwalk.exceptions.NoSolutionFound`, after which
:meth:`~mpcwalk.generators.pattern_generator.PatternGenerator.coast` continues the
reference if the caller must go on.
"""

import time
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from mpcwalk._checks import checked_number
from mpcwalk.exceptions import ConfigurationError, NoSolutionFound
from mpcwalk.generators.pattern_generator import Horizon, PatternGenerator, SolveInfo
from mpcwalk.generators.robot_traits import RobotTraits
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.program import Prediction, QuadraticProgram
from mpcwalk.qp.result import QPResult
from mpcwalk.qp.solvers.base import failure
from mpcwalk.qp.solvers.registry import make_solver

_TIME_EPS = 1e-12  # [s] times closer than this are the same instant


@dataclass(frozen=True)
class _Plan:
    """The last successful solve: jerk ``i`` applies over ``[knots[i], knots[i + 1])``,
    the knots being the solve time then the sample times of the prediction (the last jerk
    is held after the horizon)."""

    start: float  # [s] time of the solve
    jerks: np.ndarray  # (N, 2) [m/s^3]
    prediction: Prediction

    @property
    def knots(self) -> np.ndarray:
        """Solve time, then the sample times, shape (N + 1,), in [s]."""
        return np.append(self.start, self.prediction.times)


class RecedingHorizonGenerator(PatternGenerator):
    """Base class of the QP generators: back-end, plan, fallback and robot defaults.

    Args:
        lipm: Pendulum model.
        control_period: Time between ticks, in [s].
        sampling_period: Sampling period of the QP's horizon, in [s].
        solver: Back-end name (:func:`~mpcwalk.qp.solvers.registry.make_solver`).
        solver_settings: Keyword settings of the back-end.
        max_fallback_ticks: Consecutive failed solves tolerated; during them the previous
            plan keeps being followed, then NoSolutionFound.
    """

    #: Keys of a robot's :class:`~mpcwalk.gait.gait_defaults.GaitDefaults` -> (this
    #: generator's keyword, type), taken when the preset sets them (:meth:`robot_options`).
    PRESET_KEYS: ClassVar[dict[str, tuple[str, type]]] = {}

    @classmethod
    def robot_options(cls, robot: RobotTraits) -> dict[str, Any]:
        """The robot's walking defaults named in :attr:`PRESET_KEYS`, where it sets them."""
        options = {}
        for key, (name, cast) in cls.PRESET_KEYS.items():
            value = getattr(robot.gait, key)
            if value is not None:
                options[name] = cast(value)
        return options

    def __init__(
        self,
        *,
        lipm: LIPM,
        control_period: float,
        sampling_period: float,
        solver: str,
        solver_settings: dict | None,
        max_fallback_ticks: int,
    ) -> None:
        super().__init__(lipm=lipm, control_period=control_period)
        if (
            isinstance(max_fallback_ticks, bool)
            or int(max_fallback_ticks) != max_fallback_ticks
            or max_fallback_ticks < 0
        ):
            raise ConfigurationError(
                f"max_fallback_ticks must be a non-negative integer, got {max_fallback_ticks!r}."
            )
        self.max_fallback_ticks = int(max_fallback_ticks)
        sampling_period = checked_number("sampling_period", sampling_period, low=0.0, unit="s")
        if self.control_period > sampling_period + 1e-12:
            raise ConfigurationError(
                f"The control period ({self.control_period:g} s) must be at most the QP's "
                f"sampling period ({sampling_period:g} s): the generator plays the first "
                "sampling period of each plan; use a shorter control period."
            )
        self.solver_name = solver
        self.solver = make_solver(solver, **(solver_settings or {}))
        self.cart_table = CartTable(lipm, sampling_period)
        self.last_result: QPResult | None = None
        """Back-end result of the last tick (residuals, iterations)."""
        self._state = np.zeros((3, 2))
        self._plan: _Plan | None = None
        self._failures = 0

    def _restart(self, initial_state: ComState) -> None:
        """Forget the plan, the failures and the back-end's warm start; start from
        ``initial_state``."""
        self.solver.reset()
        self._state = initial_state.as_cart_table()
        self._plan = None
        self._failures = 0
        self.last_result = None

    def _start_state(self, measured: ComState | None) -> np.ndarray:
        """Cart-table state the tick starts from: the measured one (its acceleration, when
        unknown, the generator's), else the generator's own."""
        return self._state if measured is None else measured.as_cart_table(self._state[2])

    def _solve(self, qp: QuadraticProgram, x0: np.ndarray, shift: float) -> SolveInfo:
        """Solve ``qp`` (updated from ``x0`` at :attr:`time`) and move the generator's state
        one control period on: from ``x0`` along the new plan, or from its own state along
        the last plan when the solve failed.

        Args:
            qp: The QP as updated for this tick.
            x0: Cart-table state the QP starts from, shape (3, 2).
            shift: Sampling periods since the previous solve (the back-end's warm start).

        Raises:
            NoSolutionFound: More than ``max_fallback_ticks`` failed solves in a row.
        """
        t, dt = self.time, self.control_period
        result = self._checked_solve(qp, shift)
        self.last_result = result
        if result.success and result.x is not None:
            jerks = qp.jerks(result.x)
            self._plan = _Plan(t, jerks, qp.predict(jerks))
            self._failures = 0
            self._state = self._advance(x0, jerks, t, dt)
        else:
            self._failures += 1
            if self._failures > self.max_fallback_ticks:
                raise NoSolutionFound(self.solver_name, result.status, problem=qp.problem())
            self._state = self._follow_plan(self._state, t, dt)
        return SolveInfo(
            success=result.success,
            solver=self.solver_name,
            status=result.status,
            solve_time=result.solve_time,
            fallback=not result.success,
            consecutive_failures=self._failures,
        )

    @property
    def jerk_limit(self) -> float:
        """Largest CoM jerk [m/s^3] a solution may ask for: ``omega^2 (2 m/s + 10 m /
        sampling period)``, a ZMP jumping by ten metres between two samples (no support
        polygon is a hundredth of that) at a CoM speed of 2 m/s. Beyond it the solution is
        garbage (the largest jerks of the suite's pushed walks are a tenth of it)."""
        omega2 = self.lipm.omega**2
        return omega2 * (2.0 + 10.0 / self.cart_table.sampling_period)

    def _checked_solve(self, qp: QuadraticProgram, shift: float) -> QPResult:
        """The back-end's result, checked at the boundary: a back-end that raises, or a
        "success" with a non-finite or absurd solution (jerks beyond :attr:`jerk_limit`, a
        prediction that is not finite) is a failed solve, never a crash."""
        start = time.perf_counter()
        try:
            result = self.solver.solve(qp, shift=shift)
        except Exception as error:  # a back-end's failure is a failed solve
            return failure(self.solver_name, f"raised {type(error).__name__}: {error}", 0.0)
        if not isinstance(result, QPResult):
            elapsed = time.perf_counter() - start
            return failure(self.solver_name, f"returned {type(result).__name__}", elapsed)
        if not result.success or result.x is None:
            return result
        problem = _implausible(qp, np.asarray(result.x), self.jerk_limit)
        if problem is None:
            return result
        self.solver.reset()  # its warm start is the garbage
        return failure(self.solver_name, f"implausible solution: {problem}", result.solve_time)

    def _horizon(self) -> Horizon | None:
        """Predicted trajectory of the current plan, None before the first solve."""
        if self._plan is None:
            return None
        prediction = self._plan.prediction  # its states are made when the horizon's are read
        return Horizon(prediction.times, states=lambda: (prediction.com, prediction.zmp))

    def _advance(self, x0: np.ndarray, jerks: np.ndarray, t: float, dt: float) -> np.ndarray:
        """State one control period after a successful solve at ``t`` [s] from ``x0``, with
        ``jerks`` (N, 2) the new plan's: along the plan (generators whose first interval may
        be shorter than a control period); the MPC with a sliding grid applies the first."""
        return self._follow_plan(x0, t, dt)

    def _follow_plan(self, state: np.ndarray, t: float, dt: float) -> np.ndarray:
        """Integrate the jerks of the last plan exactly over ``[t, t + dt]`` [s] from
        ``state`` (zero jerk without a plan; the last jerk is held after the horizon)."""
        if self._plan is None:
            return self.cart_table.integrate(state, np.zeros(2), dt)
        knots, jerks, end = self._plan.knots, self._plan.jerks, t + dt
        while t < end - _TIME_EPS:
            i = int(np.searchsorted(knots, t + _TIME_EPS, side="right")) - 1
            i = min(max(i, 0), len(jerks) - 1)
            boundary = knots[i + 1] if i + 1 < len(knots) else end
            step = min(end, boundary) - t if boundary > t + _TIME_EPS else end - t
            state = self.cart_table.integrate(state, jerks[i], step)
            t += step
        return state


def _implausible(qp: QuadraticProgram, x: np.ndarray, jerk_limit: float) -> str | None:
    """Why the solution ``x`` of ``qp`` cannot be used, or None."""
    if x.ndim != 1 or not np.isfinite(x).all():
        return "not a finite vector"
    try:
        jerks = qp.jerks(x)
    except (ValueError, IndexError) as error:
        return f"wrong size ({error})"
    largest = float(np.max(np.abs(jerks))) if jerks.size else 0.0
    if largest > jerk_limit:
        return f"CoM jerk {largest:.3g} m/s^3 beyond the physical bound {jerk_limit:.3g} m/s^3"
    return None
