"""Linear MPC pattern generator (Wieber 2006) over the cart-table model.

Each tick solves the walking QP of :mod:`mpcwalk.qp` from the current CoM
state (measured when given), applies the first jerk over one control period
(exact integration) and returns the new state with the predicted horizon. The
ZMP tracks paper M's polygonal reference (eq. 6-8) and is hard-constrained
in the support polygon of each sample.
"""

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from mpcwalk.exceptions import ConfigurationError, NoSolutionFound
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.pattern_generator import (
    ComState,
    GeneratorOutput,
    Horizon,
    PatternGenerator,
    SolveInfo,
)
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.parameters import MpcParameters
from mpcwalk.qp.result import QPResult
from mpcwalk.qp.solvers.registry import make_solver
from mpcwalk.qp.walking_qp import Prediction, WalkingQP


@dataclass(frozen=True)
class _Plan:
    """Jerks of the last successful solve, applied from ``start`` [s]."""

    start: float
    jerks: np.ndarray  # (N, 2) [m/s^3]
    prediction: Prediction | None


class MpcGenerator(PatternGenerator):
    """Wieber-style linear MPC: ZMP tracking with ZMP constraints.

    Args:
        lipm: Pendulum model.
        control_period: Time between ticks, in [s].
        parameters: Horizon, weights, margins (default:
            :attr:`default_parameters`); keyword ``overrides`` replace fields
            of it, e.g. ``MpcGenerator(horizon=20, constrained=False)``.
        solver: None (default) picks ``"daqp"`` for the dense formulation (the
            fastest back-end measured on this problem, see ``mpcwalk bench
            ticks``) and ``"osqp-direct"`` for the sparse one; ``"osqp-direct"``
            (warm-started OSQP, vector-only updates), ``"casadi"`` or
            ``"casadi-<plugin>"``, ``"kkt"`` (unconstrained QPs only) or any
            ``qpsolvers`` name (``"daqp"``, ``"proxqp"``, ``"quadprog"``...).
        formulation: ``"dense"`` (condensed) or ``"sparse"``.
        solver_settings: Keyword settings of the back-end (e.g. ``eps_abs``).
        max_fallback_ticks: Consecutive failed solves tolerated; during them
            the previous plan keeps being followed, then NoSolutionFound.
        constrain_next_tick: Also keep the ZMP (and CoM) at the next output
            time ``t + control_period`` in its support polygon: the output
            then never leaves the polygon between samples (open loop). Off
            by default: that row and the first sample depend on the first
            jerk only, so a measured state off the plan (or coarse sampling)
            can make the QP infeasible.

    A failed solve does not raise: the previous jerk sequence keeps being
    integrated from the generator's own state (the measured state is ignored
    until a solve succeeds again), and the output's :class:`SolveInfo` says
    ``fallback=True`` with the count of consecutive failures.
    """

    name: ClassVar[str] = "mpc"
    #: Measured on the small humanoid (``experiments/paper_m``): a forward push at the start of
    #: single support is survived up to 0.575 N s with 0.02 (0.425 N s with 0.05), a lateral
    #: one up to 0.31 N s (0.25 N s), and paper M's two pushes are walked through with 0.02
    #: but not with 0.05; larger shares make the servo references follow the robot's sag.
    observer_gain: ClassVar[float] = 0.02
    #: Defaults: 1.6 s horizon sampled at 0.05 s, jerk/ZMP weight ratio 1e-7.
    #: Measured on 20-step walks at paper M's timing (double support of
    #: 2 x 0.05 s): sampling at 0.1 s (ratio 1e-6) lets the executed ZMP leave
    #: the foot by about 5 mm at the start of single support (0.05 m/s
    #: sideways) and tracks the reference within 11-12 mm RMS; 0.05 s with a
    #: ratio of 1e-7 keeps straight and turning walks 13-15 mm inside the
    #: feet (sideways at 0.1 m/s: 4.7 mm outside for one tick at the start of
    #: single support) and tracks within 5-8 mm RMS.
    #: The velocity term tracks the average walking velocity of each step (Herdt
    #: 2010); False: it damps the CoM velocity towards zero.
    track_walking_velocity: ClassVar[bool] = True

    default_parameters: ClassVar[MpcParameters] = MpcParameters(
        sampling_period=0.05,
        horizon=32,
        zmp_weight=1.0,
        jerk_weight=1e-7,
        zmp_margin=0.0,
        velocity_weight=3e-3,
    )
    """Defaults: 1.6 s at 50 ms. The small weight on tracking the average walking
    velocity (Herdt 2010) keeps the receding-horizon loop stable for tall robots:
    without it the finite horizon does not see the divergence of the CoM and the
    MPC diverges for a CoM height of 1.09 m (measured), while it changes the
    small humanoid's plan by less than 0.1 mm of ZMP margin."""

    #: Keys of a robot preset's ``[gait]`` table -> (parameter, type).
    PRESET_KEYS: ClassVar[dict] = {
        "mpc_sampling_period": ("sampling_period", float),
        "mpc_horizon": ("horizon", int),
        "mpc_jerk_weight": ("jerk_weight", float),
    }

    @classmethod
    def robot_options(cls, robot) -> dict:
        """The horizon and weights of the robot preset's ``[gait]`` table (``mpc_*`` keys)."""
        gait = robot.preset.gait
        return {
            name: cast(gait[key]) for key, (name, cast) in cls.PRESET_KEYS.items() if key in gait
        }

    def __init__(
        self,
        *,
        lipm: LIPM = LIPM(),
        control_period: float = 0.01,
        parameters: MpcParameters | None = None,
        solver: str | None = None,
        formulation: str = "dense",
        solver_settings: dict | None = None,
        max_fallback_ticks: int = 10,
        constrain_next_tick: bool = False,
        **overrides,
    ) -> None:
        super().__init__(lipm=lipm, control_period=control_period)
        params = parameters if parameters is not None else self.default_parameters
        self.parameters = params.replace(**overrides) if overrides else params
        if (
            isinstance(max_fallback_ticks, bool)
            or int(max_fallback_ticks) != max_fallback_ticks
            or max_fallback_ticks < 0
        ):
            raise ConfigurationError(
                f"max_fallback_ticks must be a non-negative integer, got {max_fallback_ticks!r}."
            )
        self.max_fallback_ticks = int(max_fallback_ticks)
        if solver is None:
            solver = "osqp-direct" if formulation == "sparse" else "daqp"
        self.solver_name = solver
        tick = None
        if constrain_next_tick and not np.isclose(control_period, self.parameters.sampling_period):
            tick = control_period
        self.qp = WalkingQP(lipm, self.parameters, formulation, control_period=tick)
        self.solver = make_solver(solver, **(solver_settings or {}))
        self.solver.check(self.qp)
        self.cart_table = CartTable(lipm, self.parameters.sampling_period)
        self.last_result: QPResult | None = None
        """Back-end result of the last tick (residuals, iterations)."""
        self._state = np.zeros((3, 2))
        self._plan: _Plan | None = None
        self._failures = 0

    @property
    def formulation(self) -> str:
        """``"dense"`` or ``"sparse"``."""
        return self.qp.formulation

    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        self.solver.reset()
        self._state = initial_state.as_cart_table()
        self._plan = None
        self._failures = 0
        self.last_result = None
        return self._output(0.0, self._state)

    def _step(self, measured: ComState | None) -> GeneratorOutput:
        t, dt = self.time, self.control_period
        x0 = self._state if measured is None else measured.as_cart_table(self._state[2])
        velocity_reference = None
        if self.track_walking_velocity and self.parameters.velocity_weight:
            velocity_reference = self.schedule.reference_velocity(t + self.qp.sample_offsets)
        self.qp.update(x0, t, self.schedule, velocity_reference=velocity_reference)
        Ts = self.parameters.sampling_period
        shift = 0.0 if self._plan is None else (t - self._plan.start) / Ts
        result = self.solver.solve(self.qp, shift=shift)
        self.last_result = result
        if result.success:
            jerks = self.qp.jerks(result.x)
            self._plan = _Plan(t, jerks, self.qp.predict(jerks))
            self._failures = 0
            self._state = self.cart_table.integrate(x0, jerks[0], dt)
        else:
            self._failures += 1
            if self._failures > self.max_fallback_ticks:
                raise NoSolutionFound(self.solver_name, result.status, problem=self.qp.problem())
            self._state = self._follow_previous_plan(t, dt)
        plan = self._plan
        horizon = None
        if plan is not None and plan.prediction is not None:
            horizon = Horizon(plan.prediction.times, plan.prediction.com, plan.prediction.zmp)
        info = SolveInfo(
            success=result.success,
            solver=self.solver_name,
            status=result.status,
            solve_time=result.solve_time,
            fallback=not result.success,
            consecutive_failures=self._failures,
        )
        return self._output(t + dt, self._state, horizon=horizon, solve=info)

    def _follow_previous_plan(self, t: float, dt: float) -> np.ndarray:
        """Integrate the previous jerk sequence over ``[t, t + dt]`` from the
        generator's own state (zero jerk when there is no plan yet)."""
        if self._plan is None:
            return self.cart_table.integrate(self._state, np.zeros(2), dt)
        Ts, plan, state = self.parameters.sampling_period, self._plan, self._state
        end = t + dt
        while t < end - 1e-12:
            i = int(np.floor((t - plan.start) / Ts + 1e-9))
            boundary = plan.start + (i + 1) * Ts
            if boundary <= t + 1e-12:
                i, boundary = i + 1, boundary + Ts
            step = min(end, boundary) - t
            jerk = plan.jerks[min(max(i, 0), len(plan.jerks) - 1)]
            state = self.cart_table.integrate(state, jerk, step)
            t += step
        return state
