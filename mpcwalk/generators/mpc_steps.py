"""Footstep-adaptive linear MPC (Herdt et al. 2010): the next footsteps are QP variables.

Each tick solves :class:`~mpcwalk.qp.footstep_qp.FootstepQP`: the CoM tracks the commanded
walking velocity (each step's average, Herdt's cost), the ZMP is pulled to the centre of its
support and kept inside it, the footsteps landing within the horizon are placed inside the
reachability rectangle of the previous one (which keeps the feet apart) and, on a terrain,
inside the band of the tread each was placed on (``landing_bands``). Sides, timing and
yaws are the plan's: every constraint is linear. Departure from Herdt: a cost pulls each
footstep towards the plan, so that an undisturbed walk steps on it. The geometry is
:class:`~mpcwalk.qp.footstep_supports.FootstepSlots`'s; the solve, the plan and the fallback
are :mod:`mpcwalk.generators.receding_horizon`'s, the step timing adaptation
:mod:`mpcwalk.generators.step_timing_adaptation`'s.

Footsteps given to the controller (:attr:`GeneratorOutput.schedule`): landed feet and the
support foot never move; the swing foot's landing is frozen ``freeze_before_landing``
before touch-down (``late_adjustment``: 2 ticks, changes boxed by the swing's time left); a
new schedule when the next landing moved by more than ``publish_tolerance`` (all footsteps of
that solve), so fixed feet sit on published positions and every support polygon agrees.
"""

from dataclasses import replace
from typing import Any, ClassVar

import numpy as np

from mpcwalk.exceptions import ConfigurationError, NotReset
from mpcwalk.footsteps.landing_bands import LandingBands
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.footsteps.reachability import ReachabilityRectangle
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.height_profile import height_profile
from mpcwalk.gait.swing_retarget import SwingLimits
from mpcwalk.generators.pattern_generator import GeneratorOutput
from mpcwalk.generators.robot_traits import RobotTraits
from mpcwalk.generators.step_timing_adaptation import StepTimingAdaptation
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.footstep_parameters import FootstepMpcParameters
from mpcwalk.qp.footstep_qp import FootstepQP
from mpcwalk.qp.footstep_supports import FootstepSlots
from mpcwalk.qp.result import QPResult

_BOUNDARY_EPS = 1e-9  # [s] a sample on a phase boundary belongs to the new phase
FOOTSTEP_REFERENCES = ("relative", "absolute")
#: ``dcm_step_gain`` on a terrain when none is given: no capture-point term. Measured on the
#: G1 (5 stairs of 10 cm up and 5 down, T = 1.5 s): with the term, the DCM errors of the
#: steps (the estimated CoM velocity off by up to 0.47 m/s while the pelvis rolls, 0.04 m/s
#: on the flat floor) grew by up to 433 times into targets metres away; the swing foot's
#: landing jumped between its lateral bounds (16 cm apart) from tick to tick, the swing leg
#: whipped sideways, the unloaded stance foot turned by 17 deg in 0.3 s and the walk stopped
#: after 16 of 25 steps, turned by 69 deg; without it, 25/25, turned by 0.9 deg.
TERRAIN_DCM_STEP_GAIN = 0.0
#: ``dcm_step_gain`` of a torque-controlled walk when none is given (the walk's builder sets
#: it): no capture-point term. Measured on the small humanoid in torque mode, on the
#: estimated state: of five worlds of the robustness matrix where the term made the walk fall
#: (a turning command, sensor noise x2.2, 20 ms latency, weaker motors, a push), three walk
#: without it and none walks worse; forward pushes of 0.3 and 0.45 N s at mid-step fell with
#: it and were survived without it (eight pushes, none lost). With position servos the same
#: pushes are survived either way.
TORQUE_DCM_STEP_GAIN = 0.0


class FootstepMpcGenerator(StepTimingAdaptation):
    """Linear MPC that also places the next footsteps (Herdt et al. 2010).

    Args:
        lipm: Pendulum model.
        control_period: Time between ticks, in [s].
        parameters: Horizon and weights (default :attr:`default_parameters`); keyword
            ``overrides`` replace fields (``sampling_period``, ``horizon``,
            ``jerk_weight``... as for the ``mpc`` generator).
        reachability: Landings allowed relative to the previous footstep: a
            :class:`ReachabilityRectangle`, or :class:`LegLimits` (its rectangle); default
            ``LegLimits()``; :meth:`for_robot` takes the robot's.
        planned_strides: Accept the plan's strides beyond ``reachability`` (footsteps placed on
            a terrain: a tread or a stone further than a flat step), each step's bounds grown
            to hold its planned displacement; False refuses such a plan.
        landing_bands: Where each landing of the plan may move, one box per step (world x,
            y; :func:`~mpcwalk.footsteps.landing_bands.tread_bands`: on its tread, off the
            edges), bounds of the QP; None: anywhere within reach.
        solver: A back-end name. Default ``"quadprog"``. ``"quadprog-screened"``
            (quadprog on the rows near binding, then every row checked:
            :class:`~mpcwalk.qp.solvers.screened.ScreenedSolver`) gives the same plans to
            1e-12 m, one to three of a tick's 268 rows binding; ``mpcwalk bench ticks`` (a
            loaded 2-core machine): median tick 0.56 ms against 0.53 ms with ``"quadprog"``
            (which calls quadprog directly) and 0.75 ms with ``"daqp"``, with the flywheel
            of ``mpc-hip`` (420 rows) 1.22 against 1.18 ms; ``"daqp-direct"`` (set up anew
            each tick) plans within 2e-12 m of quadprog, 0.9 ms. It is not the default: a walk's closed loop carries a 1e-12 m difference in the plans
            into different falls on the edge of a robustness world (one of 32 flat worlds of
            the small humanoid), and quadprog's plans are those of the published results. The
            QP is dense and rebuilt every tick, so ``"osqp-direct"``, ``"kkt"`` and CasADi do
            not apply (their check refuses it).
        solver_settings: Keyword settings of the back-end.
        footstep_reference: ``"absolute"`` (default): the cost pulls each footstep towards
            its planned position (after a push the walk returns to the plan);
            ``"relative"``: towards its planned displacement from the previous footstep
            (Herdt-like: the walk goes on from where it stepped, but the velocity cost
            shortens every step a little, 1.2 mm per step at 0.1 m/s, and that adds up).
        freeze_before_landing: The swing foot's landing stops moving this long before
            touch-down, in [s] (default 0.1 s; two control periods with ``late_adjustment``).
        late_adjustment: Landing changes boxed by the swing's time left, the swing re-planned
            as a quintic (:mod:`~mpcwalk.gait.swing_retarget`); ``swing_limits``: their
            (velocity [m/s], acceleration [m/s^2]), default ``SwingLimits.for_walk``.
        publish_tolerance: Smallest move of the next landing that publishes a new
            schedule, in [m].
        max_fallback_ticks: Consecutive failed solves tolerated (the previous plan is
            followed meanwhile, the measurement ignored), then NoSolutionFound.
        dcm_step_gain: Capture-point stepping on top of the QP: each footstep's target in
            the cost moves by this gain times the DCM error a closed-loop controller
            reports (``step(measured, dcm_error=...)``), grown until the landing,
            ``error * exp(omega * (t_landing - t))``. The QP itself starts from the state
            the controller passes, which on position servos is only a small share of the
            measured error (see :mod:`mpcwalk.control.dcm_feedback`); this term lets the steps see
            the whole push. 0 leaves it out. Measured on the small humanoid's push sweep
            (``experiments/paper_m``): the median largest impulse survived is 0.600 N s with
            1 (default), 0.575 N s with 0.3, 0.550 N s with 0 (as the fixed-footstep
            ``mpc``); without the deadband a gain of 0.3 already fell on undisturbed walks.
            None (default): 1 on the flat floor, 0 on a terrain (``landing_bands`` given),
            :data:`TERRAIN_DCM_STEP_GAIN`: there the growth over the long steps of a
            climb (e^(omega T) = 300 for the G1 at T = 1.5 s) turns the transients of
            each step up or down into targets metres away, and the landings jump between
            their bounds from one tick to the next. A torque-controlled walk's builder
            gives :data:`TORQUE_DCM_STEP_GAIN` (0) unless the walk's options say otherwise.
        dcm_deadband: DCM errors up to this norm [m] are ignored by the capture-point term
            (undisturbed walking on the small humanoid: 4.3 mm at most; a 0.3 N s push:
            about 23 mm).
        timing_adaptation: Bring the swing foot's landing forward when the capture point
            predicted at the planned landing lies beyond the leg's reach (Khadiv 2016,
            Griffin 2017): the landing time within ``[swing start + min_swing, planned]``
            that leaves the capture point nearest the reachable region is taken, by
            moving the schedule's clock ahead (:attr:`time_offset`; every later phase comes
            that much earlier); the swing foot goes on from where it is.
        min_swing: Shortest swing [s] a landing brought forward keeps.
        max_hold: With ``timing_adaptation``, the longest [s] a lift-off may be put off: at
            the end of a double support, while the DCM error (the controller's) points
            towards the foot about to lift by more than ``hold_dcm_error`` [m], the
            schedule's clock stops (:attr:`time_offset` goes back one period per tick), so
            the robot keeps both feet down and the ZMP can use the lifting foot's sole (a
            push towards that foot; Khadiv 2016's step duration, longer as well as
            shorter). 0 leaves it out.
        hold_dcm_error: See ``max_hold``.

    Raises:
        InfeasibleStep: (at :meth:`reset`) a planned step outside the rectangle.
        ConfigurationError: A solver that cannot take the dense QP.
    """

    name: ClassVar[str] = "mpc-steps"
    #: As for ``mpc``; measured on the small humanoid with a push at the start of single
    #: support: 0.02 survives 0.575 N s forward and 0.35 N s sideways, 0.05 survives 0.475
    #: and 0.275 N s, 0.1 survives 0.15 N s sideways (the reference follows the robot's sag).
    observer_gain: ClassVar[float] = 0.02
    default_parameters: ClassVar[FootstepMpcParameters] = FootstepMpcParameters()
    """1.6 s at 0.05 s; weights velocity 1, ZMP 100, footsteps 100, jerk 1e-6. Measured on
    a 10-step walk at 0.1 m/s (CoM 0.23 m): steps within 1.7 mm of the plan, ZMP 25.8 mm
    inside the feet; a lateral kick of 0.1 / 0.15 / 0.2 m/s in single support moves the
    swing foot by 5.5 / 22 / 60 mm (the reach limit). A ZMP weight of 10 leaves the ZMP
    5.8 mm inside the feet and stepped to the limit for 0.15 m/s; a footstep weight of 10
    let the steps drift 4.5 mm from the plan."""

    #: The horizon of a robot's walking defaults (not ``mpc_jerk_weight``, whose scale
    #: differs in this cost) -> (parameter, type); :meth:`robot_options` adds its leg limits.
    PRESET_KEYS: ClassVar[dict[str, tuple[str, type]]] = {
        "mpc_sampling_period": ("sampling_period", float),
        "mpc_horizon": ("horizon", int),
    }

    def __init__(
        self,
        *,
        lipm: LIPM = LIPM(),
        control_period: float = 0.01,
        parameters: FootstepMpcParameters | None = None,
        reachability: ReachabilityRectangle | LegLimits | None = None,
        solver: str = "quadprog",
        solver_settings: dict | None = None,
        footstep_reference: str = "absolute",
        freeze_before_landing: float | None = None,
        late_adjustment: bool = False,
        swing_limits: tuple[float, float] | None = None,
        publish_tolerance: float = 1e-3,
        max_fallback_ticks: int = 10,
        dcm_step_gain: float | None = None,
        dcm_deadband: float = 0.005,
        timing_adaptation: bool = False,
        min_swing: float = 0.15,
        max_hold: float = 0.5,
        hold_dcm_error: float = 0.01,
        planned_strides: bool = False,
        landing_bands: LandingBands | None = None,
        **overrides,
    ) -> None:
        flags = {"timing_adaptation": timing_adaptation, "late_adjustment": late_adjustment}
        for label, flag in flags.items():
            if not isinstance(flag, bool):
                raise ConfigurationError(f"{label} must be True or False, got {flag!r}.")
        if not (np.isfinite(min_swing) and min_swing > 0.0):
            raise ConfigurationError(
                f"min_swing must be a positive duration [s], got {min_swing!r}."
            )
        self.timing_adaptation, self.min_swing = timing_adaptation, float(min_swing)
        for label, value in (
            ("max_hold", max_hold),
            ("hold_dcm_error", hold_dcm_error),
            ("dcm_deadband", dcm_deadband),
        ):
            if not (np.isfinite(value) and value >= 0.0):
                raise ConfigurationError(f"{label} must be a non-negative number, got {value!r}.")
        self.max_hold, self.hold_dcm_error = float(max_hold), float(hold_dcm_error)
        self.dcm_deadband = float(dcm_deadband)
        if dcm_step_gain is None:  # the flat floor's default, or the terrain's
            dcm_step_gain = 1.0 if landing_bands is None else TERRAIN_DCM_STEP_GAIN
        if not (np.isfinite(dcm_step_gain) and dcm_step_gain >= 0.0):
            raise ConfigurationError(
                f"dcm_step_gain must be a non-negative number, got {dcm_step_gain!r}; 1 "
                "moves each landing by the predicted DCM error, 0 ignores it."
            )
        self.dcm_step_gain = float(dcm_step_gain)
        params = parameters if parameters is not None else self.default_parameters
        self.parameters = params.replace(**overrides) if overrides else params
        if reachability is None:
            reachability = LegLimits()
        if isinstance(reachability, LegLimits):
            reachability = reachability.rectangle()
        if not isinstance(reachability, ReachabilityRectangle):
            raise ConfigurationError(
                "reachability must be a ReachabilityRectangle or LegLimits, got "
                f"{type(reachability).__name__}."
            )
        self.reachability = reachability
        self.planned_strides = bool(planned_strides)
        if landing_bands is not None and not isinstance(landing_bands, LandingBands):
            raise ConfigurationError(
                "landing_bands must be LandingBands (tread_bands(plan, terrain, reach)) or "
                f"None, got {type(landing_bands).__name__}."
            )
        self.landing_bands = landing_bands
        if footstep_reference not in FOOTSTEP_REFERENCES:
            raise ConfigurationError(
                f"footstep_reference must be one of {', '.join(FOOTSTEP_REFERENCES)}, got "
                f"{footstep_reference!r}."
            )
        self.footstep_reference = footstep_reference
        self.late_adjustment = late_adjustment
        self.swing_limits = None if swing_limits is None else SwingLimits(*swing_limits)
        if freeze_before_landing is None:
            freeze_before_landing = 2.0 * control_period if late_adjustment else 0.1
        for label, value in (
            ("freeze_before_landing", freeze_before_landing),
            ("publish_tolerance", publish_tolerance),
        ):
            if not np.isfinite(value) or value < 0.0:
                raise ConfigurationError(f"{label} must be a non-negative number, got {value!r}.")
        self.freeze_before_landing = float(freeze_before_landing)
        self.publish_tolerance = float(publish_tolerance)
        super().__init__(
            lipm=lipm,
            control_period=control_period,
            sampling_period=self.parameters.sampling_period,
            solver=solver,
            solver_settings=solver_settings,
            max_fallback_ticks=max_fallback_ticks,
        )
        # The footstep variables are known at reset; the back-end's check needs the class
        # of QP only (dense, rebuilt every tick).
        self.solver.check(FootstepQP(lipm, self.parameters, nb_footsteps=1))
        self.qp: FootstepQP | None = None
        self.nb_publications = 0
        """Schedules published since the last reset."""
        self.nb_retimed = 0
        """Landings brought forward since the last reset."""
        self.nb_not_capturable = 0
        """Ticks since the last reset where no plan met the capturability constraint (the
        plan without it was used)."""
        self.nb_held = 0
        """Ticks since the last reset where a lift-off was put off (``max_hold``)."""
        self._slots: FootstepSlots | None = None
        self._retimed_steps: set[int] = set()
        self._held: tuple[int, float] = (-1, 0.0)  # step whose lift-off is put off, how long

    @classmethod
    def robot_options(cls, robot: RobotTraits) -> dict[str, Any]:
        """The robot's leg limits (``reachability``), and the horizon of its walking
        defaults (``mpc_sampling_period``, ``mpc_horizon``)."""
        options = super().robot_options(robot)
        options["reachability"] = robot.leg_limits
        return options

    # ------------------------------------------------------------------ reset
    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        late = self.swing_limits or SwingLimits.for_walk(schedule, self.reachability)
        bands, strides = self.landing_bands, self.planned_strides
        slots = FootstepSlots(schedule, self.reachability, strides, late=late, bands=bands)
        slots.check_reachable()
        self._slots = slots
        p = self.parameters
        nf = int(np.ceil(p.duration / schedule.step_duration)) + 1
        if self.qp is None or self.qp.nf != nf:
            self.qp = self._make_qp(nf)
        self._restart(initial_state)
        self.nb_publications = self.nb_not_capturable = self.nb_retimed = self.nb_held = 0
        self._retimed_steps, self._held = set(), (-1, 0.0)
        return self._output(0.0, self._state)

    def _make_qp(self, nb_footsteps: int) -> FootstepQP:  # a QP of nb_footsteps footsteps
        return FootstepQP(self.lipm, self.parameters, nb_footsteps)

    # ------------------------------------------------------------------ tick
    def _step(self, measured: ComState | None) -> GeneratorOutput:
        t, qp, slots = self.time, self.qp, self._slots
        if qp is None or slots is None:  # pragma: no cover - step() checks reset()
            raise NotReset("FootstepMpcGenerator stepped before reset().")
        x0 = self._start_state(measured)
        published = None
        if self.timing_adaptation and self.schedule is not None:
            if self._hold_lift_off(t):  # the clock stops: both feet stay down
                self.time_offset -= self.control_period
                t = self.time
            k = self.schedule.step_index(t)
            advance = self._landing_advance(t, x0, k) if 0 <= k < slots.nb_steps else 0.0
            if advance > 0.0:  # the clock jumps: this landing and every later phase come earlier
                self.time_offset += advance
                self.nb_retimed += 1
                published = slots.current = slots.current.with_steps(slots.current.plan.steps)
                self.schedule = published
                t = self.time
        times = qp.sample_times_at(t)
        steps_k, variable = slots.free_steps(t, times[-1], self.freeze_before_landing)
        # within a sampling interval, the constraint points are the last tick's but the first
        # interval's; those of the next ticks are computed with them (their clock unchanged)
        fresh, points = qp.parameters.constraint_points, qp.constraint_times(t)
        later = ((self.tick + j) * self.control_period + self.time_offset for j in range(1, 10))
        upcoming = qp.first_points(t, later)
        supports = slots.supports(points, variable, qp.nf, fresh=fresh, upcoming=upcoming)
        offset = np.zeros(2)
        if len(steps_k):
            offset = self._capture_offset(t, float(slots.landing[steps_k[0]]))
        absolute = self.footstep_reference == "absolute"
        now = t + self.control_period if self.late_adjustment else None  # boxes the landings
        steps = slots.step_variables(
            steps_k, variable, qp.nf, absolute=absolute, offset=offset, now=now
        )
        eta = None
        profile = height_profile(slots.current, self.lipm.com_height)
        if not profile.is_level:  # the time-varying LIPM of the footsteps' heights
            g = self.lipm.gravity
            eta = (profile.eta(times, g), profile.eta(qp.constraint_times(t), g))
        qp.update(x0, t, slots.reference_velocity(times), supports, steps, eta)
        shift = (
            0.0
            if self._plan is None
            else float(np.searchsorted(self._plan.prediction.times, times[0] - _BOUNDARY_EPS))
        )
        info = self._solve(qp, x0, shift)
        result = self.last_result
        if info.success and len(steps_k) and result is not None and result.x is not None:
            footsteps = qp.footsteps(result.x)[: len(steps_k)]
            moved = slots.publish(steps_k, footsteps, self.publish_tolerance)
            if moved is not None:
                published = self.schedule = moved
                self.nb_publications += 1
        return self._output(
            self.time + self.control_period,
            self._state,
            horizon=self._horizon(),
            solve=info,
            schedule=published,
        )

    def _checked_solve(self, qp, shift: float) -> QPResult:
        """The core's checked solve; when the capturability rows make it fail, the plan
        without them (counted in :attr:`nb_not_capturable`, said in the status)."""
        result = super()._checked_solve(qp, shift)
        if result.success or not isinstance(qp, FootstepQP) or not qp.terminal_rows:
            return result
        qp.without_terminal_rows()
        self.nb_not_capturable += 1
        retry = super()._checked_solve(qp, shift)
        return replace(retry, status=f"{retry.status} (not capturable within the horizon)")

    def _capture_offset(self, t: float, first_landing: float) -> np.ndarray:
        """Capture-point stepping: where the DCM error of this tick (:attr:`dcm_error`),
        beyond ``dcm_deadband``, will have grown by the next free landing if nothing is
        done, ``dcm_step_gain * error * exp(omega * (t_landing - t))``; every free
        footstep's target moves by it (the walk goes on from the displaced step)."""
        norm = float(np.linalg.norm(self.dcm_error))
        if not self.dcm_step_gain or norm <= self.dcm_deadband:
            return np.zeros(2)
        error = self.dcm_error * (1.0 - self.dcm_deadband / norm)
        growth = np.exp(self.lipm.omega * max(first_landing - t, 0.0))
        return self.dcm_step_gain * growth * error
