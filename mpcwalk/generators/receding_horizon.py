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

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from mpcwalk.exceptions import ConfigurationError, NoSolutionFound
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.gait.gait_defaults import GaitDefaults
from mpcwalk.generators.pattern_generator import Horizon, PatternGenerator, SolveInfo
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.program import Prediction, QuadraticProgram
from mpcwalk.qp.result import QPResult
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
    def robot_options(cls, *, gait: GaitDefaults, leg_limits: LegLimits) -> dict[str, Any]:
        """The robot's walking defaults named in :attr:`PRESET_KEYS`, where it sets them."""
        options = {}
        for key, (name, cast) in cls.PRESET_KEYS.items():
            value = getattr(gait, key)
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
        result = self.solver.solve(qp, shift=shift)
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

    def _horizon(self) -> Horizon | None:
        """Predicted trajectory of the current plan, None before the first solve."""
        if self._plan is None:
            return None
        prediction = self._plan.prediction
        return Horizon(prediction.times, prediction.com, prediction.zmp)

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
            i = np.searchsorted(knots, t + _TIME_EPS, side="right") - 1
            i = int(np.clip(i, 0, len(jerks) - 1))
            boundary = knots[i + 1] if i + 1 < len(knots) else end
            step = min(end, boundary) - t if boundary > t + _TIME_EPS else end - t
            state = self.cart_table.integrate(state, jerks[i], step)
            t += step
        return state
