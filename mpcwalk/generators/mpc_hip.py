"""The hip strategy in the footstep-adaptive MPC: a LIPM with a flywheel (Pratt et al. 2006).

:class:`HipStrategyMpcGenerator` is :class:`~mpcwalk.generators.mpc_steps.FootstepMpcGenerator`
(footsteps, and with ``timing_adaptation`` the step timing, adapted by the QP and its
heuristics) whose QP, :class:`~mpcwalk.qp.flywheel_qp.FlywheelFootstepQP`, also plans the
torque the upper body applies about the CoM: the ZMP stays in the support while the CMP the
CoM accelerates from may leave it (:mod:`mpcwalk.models.flywheel`). Paper A names three
balance strategies, ankle, hip and step; this generator plans the last two together, the
first being the ZMP's freedom inside the sole.

The flywheel's state (the upper body's lean and momentum) is the generator's own: it is
integrated exactly with the first torque of each plan (the previous plan's torques while a
solve fails), and returned in :attr:`GeneratorOutput.flywheel` for the whole-body IK to
realise (a centroidal angular-momentum task and the torso's lean). ``GeneratorOutput.zmp`` is
the ZMP, the CMP minus ``tau / (m g)``.
"""

from dataclasses import replace
from typing import Any, ClassVar

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.mpc_steps import FootstepMpcGenerator
from mpcwalk.generators.pattern_generator import GeneratorOutput, Horizon
from mpcwalk.models.com_state import ComState
from mpcwalk.models.flywheel import FlywheelLimits, FlywheelState, flywheel_transition
from mpcwalk.qp.flywheel_qp import FlywheelFootstepQP, FlywheelParameters


def _limits(value: FlywheelLimits | dict | None) -> FlywheelLimits:
    if value is None:
        return FlywheelLimits.small_humanoid()
    if isinstance(value, FlywheelLimits):
        return value
    if isinstance(value, dict):
        try:
            return FlywheelLimits(**value)
        except TypeError as error:
            raise ConfigurationError(
                f"flywheel_limits takes mass, inertia, max_torque, max_momentum, max_angle "
                f"(and gravity): {error}."
            ) from None
    raise ConfigurationError(
        f"flywheel_limits must be a FlywheelLimits, a table of its fields or None (the small "
        f"humanoid's), got {type(value).__name__}."
    )


class HipStrategyMpcGenerator(FootstepMpcGenerator):
    """Footstep-adaptive MPC with the upper body as a flywheel (the hip strategy).

    Args:
        flywheel_limits: The upper body's limits (a
            :class:`~mpcwalk.models.flywheel.FlywheelLimits` or a table of its fields);
            None: the small humanoid's (:meth:`FlywheelLimits.small_humanoid`). A walk's
            controller passes its robot's
            (:func:`mpcwalk.ik.upper_body.upper_body_flywheel`).
        flywheel_scale: Share of the torque limit the MPC may use, >= 0 (0: the flywheel
            stays at rest, the generator is ``mpc-steps``).
        flywheel_samples: Intervals of the horizon with a torque variable
            (:class:`~mpcwalk.qp.flywheel_qp.FlywheelParameters`).
        flywheel_weights: ``(torque, momentum, lean)`` weights relative to the limits.
        **options: Those of :class:`~mpcwalk.generators.mpc_steps.FootstepMpcGenerator`.
    """

    name: ClassVar[str] = "mpc-hip"

    def __init__(
        self,
        *,
        flywheel_limits: FlywheelLimits | dict | None = None,
        flywheel_scale: float = 1.0,
        flywheel_samples: int = FlywheelParameters.samples,
        flywheel_weights: tuple[float, float, float] | list[float] | None = None,
        **options: Any,
    ) -> None:
        limits = _limits(flywheel_limits)
        if not (np.isfinite(flywheel_scale) and flywheel_scale >= 0.0):
            raise ConfigurationError(
                f"flywheel_scale must be a non-negative number (share of the torque limit), "
                f"got {flywheel_scale!r}."
            )
        pitch, roll = limits.max_torque
        self.flywheel_limits = replace(
            limits, max_torque=(flywheel_scale * pitch, flywheel_scale * roll)
        )
        weights = (
            (FlywheelParameters.torque_weight, FlywheelParameters.momentum_weight)
            + (FlywheelParameters.angle_weight,)
            if flywheel_weights is None
            else tuple(flywheel_weights)
        )
        if len(weights) != 3:
            raise ConfigurationError(
                f"flywheel_weights must be three numbers (torque, momentum, lean), got "
                f"{flywheel_weights!r}."
            )
        self.flywheel_parameters = FlywheelParameters(flywheel_samples, *weights)
        super().__init__(**options)
        self._flywheel_state = np.zeros((2, 2))  # rows lean, momentum; columns x, y
        self._torque_plan: tuple[np.ndarray, np.ndarray] | None = None  # knots, torques
        self._fly_horizon: Horizon | None = None

    def _make_qp(self, nb_footsteps: int) -> FlywheelFootstepQP:
        return FlywheelFootstepQP(
            self.lipm, self.parameters, nb_footsteps, self.flywheel_limits, self.flywheel_parameters
        )

    @property
    def flywheel_state(self) -> FlywheelState:
        """The flywheel now (lean, momentum; torque zero between ticks)."""
        return self._state_of(np.zeros(2))

    def _state_of(self, torque: np.ndarray) -> FlywheelState:
        lean, momentum = self._flywheel_state
        return FlywheelState(lean.copy(), momentum.copy(), np.asarray(torque, dtype=float))

    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        output = super()._reset(schedule, initial_state)
        self._flywheel_state = np.zeros((2, 2))
        self._torque_plan, self._fly_horizon = None, None
        return replace(output, flywheel=self.flywheel_state)

    def _step(self, measured: ComState | None) -> GeneratorOutput:
        qp = self.qp
        if not isinstance(qp, FlywheelFootstepQP):  # pragma: no cover - made by _reset
            raise ConfigurationError("mpc-hip stepped without its flywheel QP.")
        qp.flywheel_state = self._flywheel_state.copy()
        t = self.time
        output = super()._step(measured)
        result, dt = self.last_result, self.control_period
        solved = output.solve is not None and output.solve.success
        if solved and result is not None and result.x is not None:
            torques = qp.torques(result.x)
            self._torque_plan = (np.append(qp.time, qp.sample_times[: qp.M]), torques)
            if self._plan is not None:
                prediction = self._plan.prediction
                zmp = qp.zmp_prediction(prediction, result.x)
                self._fly_horizon = Horizon(prediction.times, prediction.com, zmp)
            torque = torques[0]
        else:
            torque = self._planned_torque(t)
        for a, inertia in enumerate(self.flywheel_limits.inertia):
            A, B = flywheel_transition(dt, inertia)
            self._flywheel_state[:, a] = A @ self._flywheel_state[:, a] + B * torque[a]
        return replace(
            output,
            zmp=output.zmp - torque / self.flywheel_limits.weight,
            horizon=self._fly_horizon if self._fly_horizon is not None else output.horizon,
            flywheel=self._state_of(torque),
        )

    def _planned_torque(self, t: float) -> np.ndarray:
        """The last plan's torque at ``t`` [s] (zero beyond it, or without a plan)."""
        if self._torque_plan is None:
            return np.zeros(2)
        knots, torques = self._torque_plan
        i = int(np.searchsorted(knots, t + 1e-12, side="right")) - 1
        return torques[i].copy() if 0 <= i < len(torques) else np.zeros(2)


__all__ = ["HipStrategyMpcGenerator"]
