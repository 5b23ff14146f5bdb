"""Linear MPC pattern generator (Wieber 2006) over the cart-table model.

Each tick solves the walking QP of :mod:`mpcwalk.qp` from the current CoM
state (measured when given), applies the first jerk over one control period
(exact integration) and returns the new state with the predicted horizon. The
ZMP tracks paper M's polygonal reference (eq. 6-8) and is hard-constrained
in the support polygon of each sample.
"""

from typing import ClassVar

import numpy as np

from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.pattern_generator import GeneratorOutput
from mpcwalk.generators.receding_horizon import RecedingHorizonGenerator
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.parameters import MpcParameters
from mpcwalk.qp.walking_qp import WalkingQP


class MpcGenerator(RecedingHorizonGenerator):
    """Wieber-style linear MPC: ZMP tracking with ZMP constraints.

    Args:
        lipm: Pendulum model.
        control_period: Time between ticks, in [s].
        parameters: Horizon, weights, margins (default:
            :attr:`default_parameters`); keyword ``overrides`` replace fields
            of it, e.g. ``MpcGenerator(horizon=20, constrained=False)``.
        solver: None (default) picks ``"daqp-direct"`` for the dense formulation
            (DAQP's own workspace: the Hessian factorised once, vector-only updates,
            hot start from the previous working set; the fastest back-end measured on
            this problem, see ``mpcwalk bench ticks``) and ``"osqp-direct"`` for the
            sparse one; ``"osqp-direct"`` (warm-started OSQP, vector-only updates),
            ``"casadi"`` or
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
    until a solve succeeds again), and the output's
    :class:`~mpcwalk.generators.pattern_generator.SolveInfo` says
    ``fallback=True`` with the count of consecutive failures (see
    :mod:`mpcwalk.generators.receding_horizon`).
    """

    name: ClassVar[str] = "mpc"
    #: Measured on the small humanoid (``experiments/paper_m``): a forward push at the start of
    #: single support is survived up to 0.575 N s with 0.02 (0.425 N s with 0.05), a lateral
    #: one up to 0.31 N s (0.25 N s), and paper M's two pushes are walked through with 0.02
    #: but not with 0.05; larger shares make the servo references follow the robot's sag.
    observer_gain: ClassVar[float] = 0.02
    follows_new_footsteps: ClassVar[bool] = True
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

    #: The horizon and weights of a robot's walking defaults (``mpc_*`` fields of
    #: :class:`~mpcwalk.gait.gait_defaults.GaitDefaults`) -> (parameter, type).
    PRESET_KEYS: ClassVar[dict[str, tuple[str, type]]] = {
        "mpc_sampling_period": ("sampling_period", float),
        "mpc_horizon": ("horizon", int),
        "mpc_jerk_weight": ("jerk_weight", float),
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
        params = parameters if parameters is not None else self.default_parameters
        self.parameters = params.replace(**overrides) if overrides else params
        if solver is None:
            solver = "osqp-direct" if formulation == "sparse" else "daqp-direct"
        super().__init__(
            lipm=lipm,
            control_period=control_period,
            sampling_period=self.parameters.sampling_period,
            solver=solver,
            solver_settings=solver_settings,
            max_fallback_ticks=max_fallback_ticks,
        )
        tick = None
        if constrain_next_tick and not np.isclose(control_period, self.parameters.sampling_period):
            tick = control_period
        self.qp = WalkingQP(lipm, self.parameters, formulation, control_period=tick)
        self.solver.check(self.qp)

    @property
    def formulation(self) -> str:
        """``"dense"`` or ``"sparse"``."""
        return self.qp.formulation

    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        self._restart(initial_state)
        return self._output(0.0, self._state)

    def _step(self, measured: ComState | None) -> GeneratorOutput:
        t, schedule = self.time, self.current_schedule
        x0 = self._start_state(measured)
        velocity_reference = None
        if self.track_walking_velocity and self.parameters.velocity_weight:
            velocity_reference = self.qp.walking_velocity(t, schedule)
        self.qp.update(x0, t, schedule, velocity_reference=velocity_reference)
        Ts = self.parameters.sampling_period
        shift = 0.0 if self._plan is None else (t - self._plan.start) / Ts
        info = self._solve(self.qp, x0, shift)
        return self._output(
            t + self.control_period, self._state, horizon=self._horizon(), solve=info
        )

    def _advance(self, x0: np.ndarray, jerks: np.ndarray, t: float, dt: float) -> np.ndarray:
        """The first jerk of the new plan over one control period."""
        transition = self.__dict__.get("_transition")
        if transition is None or transition[0] != dt:
            transition = self.__dict__["_transition"] = (dt, *self.cart_table.transition(dt))
        _, A, B = transition
        return A @ x0 + B[:, None] * np.ravel(jerks[0])  # B (3,): the outer product
