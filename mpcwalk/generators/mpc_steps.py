"""Footstep-adaptive linear MPC (Herdt et al. 2010): the next footsteps are QP variables.

Each tick solves :class:`~mpcwalk.qp.footstep_qp.FootstepQP`: the CoM tracks the commanded
walking velocity (the average velocity of each step, Herdt's cost), the ZMP is pulled to the
centre of its support and kept inside it, and the footsteps landing within the horizon are
placed by the QP inside the reachability rectangle of the previous footstep (which keeps the
minimum feet separation). Sides, timing and yaws are the plan's, so every constraint is
linear. Departure from Herdt: a cost pulls each footstep towards the plan, so that an
undisturbed walk steps on it.

Support of a sample between feet A and B (``lam``: share of B; single support: A = B):
in double support ``lam`` runs from 0 to 1 (0.5 at the step boundary, where paper M's
reference passes the feet midpoint); before and after the walk it is 0.5. With both feet
fixed the ZMP stays in the hull of the soles (as the fixed-footstep MPC); with a footstep
variable, in the sole-sized rectangle of :func:`~mpcwalk.qp.footstep_qp.blended_rectangles`
centred at ``(1 - lam) A + lam B``, inside that hull for any positions. The ZMP cost pulls
to the same centre (paper M's polygonal reference, eq. 6-8, on the variable footsteps).

Footsteps given to the controller (:attr:`GeneratorOutput.schedule`): landed feet and the
support foot never move; the swing foot's landing is frozen ``freeze_before_landing``
before touch-down; a schedule is published when the next landing moved by more than
``publish_tolerance`` (with all the footsteps of that solve), so fixed feet always sit on
published positions and the generator and the controller agree on every support polygon.
"""

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from mpcwalk.exceptions import ConfigurationError, InfeasibleStep, NoSolutionFound
from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.footsteps.reachability import ReachabilityRectangle
from mpcwalk.footsteps.velocity_planner import LegLimits
from mpcwalk.gait.contact_schedule import MAX_POLYGON_EDGES, ContactSchedule
from mpcwalk.generators.pattern_generator import (
    ComState,
    GeneratorOutput,
    Horizon,
    PatternGenerator,
    SolveInfo,
)
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.footstep_parameters import FootstepMpcParameters, blended_rectangles
from mpcwalk.qp.footstep_qp import FootstepQP, SampleSupports, StepVariables
from mpcwalk.qp.result import QPResult
from mpcwalk.qp.solvers.registry import QpsolversSolver, make_solver, solver_names

_BOUNDARY_EPS = 1e-9  # [s] a sample on a phase boundary belongs to the new phase
_REACH_TOLERANCE = 1e-6  # [m], [rad] nominal steps may touch the rectangle's edges
FOOTSTEP_REFERENCES = ("relative", "absolute")


@dataclass(frozen=True)
class _Plan:
    """Jerk ``i`` of the last successful solve applies over ``[knots[i], knots[i + 1])``."""

    knots: np.ndarray  # (N + 1,) [s]: solve time, then the sample times
    jerks: np.ndarray  # (N, 2) [m/s^3]
    horizon: Horizon


class FootstepMpcGenerator(PatternGenerator):
    """Linear MPC that also places the next footsteps (Herdt et al. 2010).

    Args:
        lipm: Pendulum model.
        control_period: Time between ticks, in [s].
        parameters: Horizon and weights (default :attr:`default_parameters`); keyword
            ``overrides`` replace fields (``sampling_period``, ``horizon``,
            ``jerk_weight``... as for the ``mpc`` generator).
        reachability: Landings allowed relative to the previous footstep: a
            :class:`ReachabilityRectangle`, or :class:`LegLimits` (its rectangle); default
            ``LegLimits()``; ``mpcwalk.walking.runner.leg_limits(robot)`` gives a robot's (see
            :meth:`for_robot`).
        solver: A ``qpsolvers`` name. Default ``"quadprog"``: median tick 0.84 ms (solver
            0.18 ms) against 1.16 ms (0.47 ms) with ``"daqp"`` on a 10-step walk, same
            plans. The QP is dense and rebuilt every tick, so ``"osqp-direct"``, ``"kkt"``
            and CasADi do not apply.
        solver_settings: Keyword settings of the back-end.
        footstep_reference: ``"absolute"`` (default): the cost pulls each footstep towards
            its planned position (after a push the walk returns to the plan);
            ``"relative"``: towards its planned displacement from the previous footstep
            (Herdt-like: the walk goes on from where it stepped, but the velocity cost
            shortens every step a little, 1.2 mm per step at 0.1 m/s, and that adds up).
        freeze_before_landing: The swing foot's landing stops moving this long before
            touch-down, in [s].
        publish_tolerance: Smallest move of the next landing that publishes a new
            schedule, in [m].
        max_fallback_ticks: Consecutive failed solves tolerated (the previous plan is
            followed meanwhile, the measurement ignored), then NoSolutionFound.
        dcm_step_gain: Capture-point stepping on top of the QP: each footstep's target in
            the cost moves by this gain times the DCM error a closed-loop controller
            reports (:meth:`observe_dcm_error`), grown until the landing,
            ``error * exp(omega * (t_landing - t))``. The QP itself starts from the state
            the controller passes, which on position servos is only a small share of the
            measured error (see :mod:`mpcwalk.control.dcm_feedback`); this term lets the steps see
            the whole push. 0 leaves it out. Measured on the small humanoid's push sweep
            (``experiments/paper_m``): the median largest impulse survived is 0.600 N s with
            1 (default), 0.575 N s with 0.3, 0.550 N s with 0 (as the fixed-footstep
            ``mpc``); without the deadband a gain of 0.3 already fell on undisturbed walks.
        dcm_deadband: DCM errors up to this norm [m] are ignored by the capture-point term
            (undisturbed walking on the small humanoid: 4.3 mm at most; a 0.3 N s push:
            about 23 mm).

    Raises:
        InfeasibleStep: (at :meth:`reset`) a planned step outside the rectangle.
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
        freeze_before_landing: float = 0.1,
        publish_tolerance: float = 1e-3,
        max_fallback_ticks: int = 10,
        dcm_step_gain: float = 1.0,
        dcm_deadband: float = 0.005,
        **overrides,
    ) -> None:
        super().__init__(lipm=lipm, control_period=control_period)
        if not (np.isfinite(dcm_step_gain) and dcm_step_gain >= 0.0):
            raise ConfigurationError(
                f"dcm_step_gain must be a non-negative number, got {dcm_step_gain!r}; 1 "
                "moves each landing by the predicted DCM error, 0 ignores it."
            )
        self.dcm_step_gain = float(dcm_step_gain)
        if not (np.isfinite(dcm_deadband) and dcm_deadband >= 0.0):
            raise ConfigurationError(
                f"dcm_deadband must be a non-negative distance [m], got {dcm_deadband!r}."
            )
        self.dcm_deadband = float(dcm_deadband)
        self._dcm_error = np.zeros(2)
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
        if footstep_reference not in FOOTSTEP_REFERENCES:
            raise ConfigurationError(
                f"footstep_reference must be one of {', '.join(FOOTSTEP_REFERENCES)}, got "
                f"{footstep_reference!r}."
            )
        self.footstep_reference = footstep_reference
        for label, value in (
            ("freeze_before_landing", freeze_before_landing),
            ("publish_tolerance", publish_tolerance),
        ):
            if not np.isfinite(value) or value < 0.0:
                raise ConfigurationError(f"{label} must be a non-negative number, got {value!r}.")
        self.freeze_before_landing = float(freeze_before_landing)
        self.publish_tolerance = float(publish_tolerance)
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
        if not isinstance(self.solver, QpsolversSolver):
            names = [
                s
                for s in solver_names()
                if s not in ("osqp-direct", "kkt") and not s.startswith("casadi")
            ]
            raise ConfigurationError(
                f"Generator 'mpc-steps' solves its dense QP through qpsolvers; solver "
                f"'{solver}' is not one of them. Choose one of {', '.join(names)}."
            )
        self.cart_table = CartTable(lipm, self.parameters.sampling_period)
        self.qp: FootstepQP | None = None
        self.last_result: QPResult | None = None
        """Back-end result of the last tick."""
        self.nb_publications = 0
        """Schedules published since the last reset."""
        self._state = np.zeros((3, 2))
        self._plan: _Plan | None = None
        self._failures = 0

    @classmethod
    def robot_options(cls, robot) -> dict:
        """The robot's leg limits, and the horizon of its preset's ``[gait]`` table
        (``mpc_sampling_period``, ``mpc_horizon``; not ``mpc_jerk_weight``, whose scale
        differs in this cost)."""
        from mpcwalk.generators.mpc import MpcGenerator
        from mpcwalk.walking.runner import leg_limits  # the robot layer sits above the generators

        options = {
            key: value
            for key, value in MpcGenerator.robot_options(robot).items()
            if key != "jerk_weight"
        }
        options["reachability"] = leg_limits(robot)
        return options

    @classmethod
    def for_robot(cls, robot, **options) -> "FootstepMpcGenerator":
        """Generator with the robot's CoM height, leg limits and preset horizon (``options``
        override)."""
        return cls(
            **{"lipm": LIPM(com_height=robot.com_height), **cls.robot_options(robot), **options}
        )

    # ------------------------------------------------------------------ reset
    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        plan = schedule.plan
        self._nominal_schedule = schedule
        self._nb = nb = plan.nb_steps
        feet = [plan.initial_left, plan.initial_right, *plan.steps]
        self._feet = feet
        self._nominal = np.array([f.xy for f in feet]).reshape(-1, 2)
        self._positions = self._nominal.copy()
        self._yaws = np.array([f.yaw for f in feet])
        # Slots: 0 and 1 the initial left and right feet, 2 + k the landing of step k.
        # _sup[k]: the support foot of step k; _lift[k]: its swing foot before lift-off.
        init = {Side.LEFT: 0, Side.RIGHT: 1}
        sides = [s.side for s in plan.steps]
        self._sup = np.array([2 + k - 1 if k else init[sides[0].other] for k in range(nb)], int)
        self._lift = np.array([2 + k - 2 if k >= 2 else init[sides[k]] for k in range(nb)], int)
        self._bounds = [self.reachability.bounds(side) for side in sides]
        self._check_plan()
        self._landing = schedule.walk_start + np.arange(nb) * schedule.step_duration + schedule.t_e
        p = self.parameters
        nf = int(np.ceil(p.duration / schedule.step_duration)) + 1
        if self.qp is None or self.qp.nf != nf:
            self.qp = FootstepQP(self.lipm, p, nf)
        self._tabulate(schedule)
        self.solver.reset()
        self._state = initial_state.as_cart_table()
        self._plan, self._failures, self.last_result = None, 0, None
        self.nb_publications = 0
        return self._output(0.0, self._state)

    def _check_plan(self) -> None:
        """Every planned step must lie in the rectangle of its support foot."""
        for k in range(self._nb):
            p, slot = self._sup[k], 2 + k
            yaw = self._yaws[p]
            R = np.array([[np.cos(yaw), np.sin(yaw)], [-np.sin(yaw), np.cos(yaw)]])
            local = np.append(
                R @ (self._nominal[slot] - self._nominal[p]), wrap_angle(self._yaws[slot] - yaw)
            )
            lower, upper = self._bounds[k]
            if np.any(local < lower - _REACH_TOLERANCE) or np.any(local > upper + _REACH_TOLERANCE):
                raise InfeasibleStep(
                    f"Planned step {k} ({self._feet[slot].side.value} foot) lands at "
                    f"(x, y, yaw) = ({local[0]:.4f} m, {local[1]:.4f} m, {local[2]:.4f} rad) in "
                    f"its support foot's frame, outside the reachability rectangle "
                    f"({self.reachability.describe()}). Widen the rectangle (reachability=) "
                    "or plan the footsteps within it (VelocityPlanner with the same LegLimits)."
                )

    def _tabulate(self, schedule: ContactSchedule) -> None:
        """Half-planes of the schedule's phases, padded, with a mask of the real rows."""
        E = MAX_POLYGON_EDGES
        nph = len(schedule.phases)
        self._phase_A, self._phase_b = np.zeros((nph, E, 2)), np.zeros((nph, E))
        self._phase_rows = np.zeros((nph, E), bool)
        for i, phase in enumerate(schedule.phases):
            k = len(phase.polygon.b)
            self._phase_A[i, :k], self._phase_b[i, :k] = phase.polygon.A, phase.polygon.b
            self._phase_rows[i, :k] = True

    # ------------------------------------------------------------------ tick
    def _step(self, measured: ComState | None) -> GeneratorOutput:
        t, dt, qp = self.time, self.control_period, self.qp
        x0 = self._state if measured is None else measured.as_cart_table(self._state[2])
        times = qp.sample_times_at(t)
        steps_k, variable = self._variables(t, times[-1])
        supports = self._supports(qp.constraint_times(t), variable)
        steps = self._step_variables(steps_k, variable)
        qp.update(x0, t, self._nominal_schedule.reference_velocity(times), supports, steps)
        shift = (
            0.0
            if self._plan is None
            else float(np.searchsorted(self._plan.knots[1:], times[0] - _BOUNDARY_EPS))
        )
        result = self.solver.solve(qp, shift=shift)
        self.last_result = result
        published = None
        if result.success:
            jerks = qp.jerks(result.x)
            com, zmp = qp.predict(jerks)
            self._plan = _Plan(np.append(t, times), jerks, Horizon(times, com, zmp))
            self._failures = 0
            self._state = self._follow_plan(x0, t, dt)
            if len(steps_k):
                published = self._publish(steps_k, qp.footsteps(result.x)[: len(steps_k)])
        else:
            self._failures += 1
            if self._failures > self.max_fallback_ticks:
                raise NoSolutionFound(self.solver_name, result.status, problem=qp.problem())
            self._state = self._follow_plan(self._state, t, dt)
        info = SolveInfo(
            success=result.success,
            solver=self.solver_name,
            status=result.status,
            solve_time=result.solve_time,
            fallback=not result.success,
            consecutive_failures=self._failures,
        )
        horizon = None if self._plan is None else self._plan.horizon
        return self._output(t + dt, self._state, horizon=horizon, solve=info, schedule=published)

    def _variables(self, t: float, last_sample: float):
        """Steps whose landing is free this tick (not frozen, within the horizon), and the
        variable index of every slot (-1: fixed)."""
        free = (t < self._landing - self.freeze_before_landing - _BOUNDARY_EPS) & (
            self._landing <= last_sample + _BOUNDARY_EPS
        )
        steps_k = np.flatnonzero(free)
        variable = np.full(self._nb + 2, -1)
        variable[2 + steps_k] = np.arange(len(steps_k))
        return steps_k, variable

    def _slots(self, times: np.ndarray):
        """Feet A and B (slots) of each sample and the share ``lam`` of B in its support."""
        sched, nb = self._nominal_schedule, self._nb
        T, t_b, t_e = sched.step_duration, sched.t_b, sched.t_e
        rel = times + _BOUNDARY_EPS - sched.walk_start
        k = np.floor(rel / T).astype(int)
        n = len(times)
        A, B, lam = np.zeros(n, int), np.ones(n, int), np.full(n, 0.5)
        if nb:
            A[:], B[:] = self._lift[0], self._sup[0]  # before the walk: both initial feet
            after = k >= nb
            A[after], B[after] = self._sup[-1], 2 + nb - 1
            walk = (rel >= 0.0) & ~after
            kw = k[walk]
            tau = rel[walk] - kw * T
            a, b, w = self._sup[kw].copy(), self._sup[kw].copy(), np.zeros(len(kw))
            opening, closing = tau < t_b, tau >= t_e
            a[opening] = self._lift[kw[opening]]
            if t_b > 0.0:
                w[opening] = 0.5 + 0.5 * tau[opening] / t_b
            if t_e < T:
                b[closing] = 2 + kw[closing]
                w[closing] = 0.5 * (tau[closing] - t_e) / (T - t_e)
            A[walk], B[walk], lam[walk] = a, b, w
        return A, B, lam

    def _supports(self, times: np.ndarray, variable: np.ndarray) -> SampleSupports:
        """ZMP constraints and centres at ``times``: the published polygons where both
        feet are fixed, blended rectangles on the footstep variables elsewhere."""
        nf = self.qp.nf
        A, B, lam = self._slots(times)
        va, vb = variable[A], variable[B]
        pos = self._positions
        centres = np.where(va[:, None] < 0, (1.0 - lam)[:, None] * pos[A], 0.0) + np.where(
            vb[:, None] < 0, lam[:, None] * pos[B], 0.0
        )
        weights = np.zeros((len(times), nf + 1))  # last column: the fixed feet, dropped
        samples = np.arange(len(times))
        np.add.at(weights, (samples, np.where(va >= 0, va, nf)), 1.0 - lam)
        np.add.at(weights, (samples, np.where(vb >= 0, vb, nf)), lam)
        weights = weights[:, :nf]
        moving = np.flatnonzero((va >= 0) | (vb >= 0))
        idx = self.schedule.phase_index(times + _BOUNDARY_EPS)
        normals, offsets = self._phase_A[idx].copy(), self._phase_b[idx].copy()
        rows = self._phase_rows[idx].copy()
        if len(moving):
            n, half = blended_rectangles(
                self._yaws[A[moving]], self._yaws[B[moving]], lam[moving], self.schedule.foot
            )
            normals[moving] = 0.0
            offsets[moving] = 0.0
            rows[moving] = False
            normals[moving, :4] = n
            offsets[moving, :4] = half + np.einsum("kra,ka->kr", n, centres[moving])
            rows[moving, :4] = True
        return SampleSupports(normals, offsets, rows, weights, centres)

    def _step_variables(self, steps_k: np.ndarray, variable: np.ndarray) -> StepVariables:
        """Reference and reach of the footstep variables (steps ``steps_k``)."""
        nf = self.qp.nf
        active = np.zeros(nf, bool)
        M, r = np.eye(nf), np.zeros((nf, 2))
        pred = np.full(nf, -1)
        pred_xy, pred_yaw = np.zeros((nf, 2)), np.zeros(nf)
        lower, upper = np.full((nf, 2), -1.0), np.ones((nf, 2))
        initial = np.zeros((nf, 2))
        offset = np.zeros(2)
        if len(steps_k):
            offset = self._capture_offset(self.time, float(self._landing[steps_k[0]]))
        for j, k in enumerate(steps_k):
            p = self._sup[k]
            active[j] = True
            pred[j], pred_xy[j], pred_yaw[j] = variable[p], self._positions[p], self._yaws[p]
            lower[j], upper[j] = self._bounds[k][0][:2], self._bounds[k][1][:2]
            initial[j] = self._positions[2 + k]
            if self.footstep_reference == "absolute":
                r[j] = self._nominal[2 + k] + offset
            else:
                r[j] = self._nominal[2 + k] - self._nominal[p]
                if variable[p] >= 0:
                    M[j, variable[p]] = -1.0
                else:
                    r[j] += self._positions[p]
        return StepVariables(active, M, r, pred, pred_xy, pred_yaw, lower, upper, initial)

    def observe_dcm_error(self, error: np.ndarray) -> None:
        self._dcm_error = np.asarray(error, dtype=float)

    def _capture_offset(self, t: float, first_landing: float) -> np.ndarray:
        """Capture-point stepping: where the reported DCM error, beyond ``dcm_deadband``,
        will have grown by the next free landing if nothing is done,
        ``dcm_step_gain * error * exp(omega * (t_landing - t))``; every free footstep's
        target moves by it (the walk goes on from the displaced step)."""
        norm = float(np.linalg.norm(self._dcm_error))
        if not self.dcm_step_gain or norm <= self.dcm_deadband:
            return np.zeros(2)
        error = self._dcm_error * (1.0 - self.dcm_deadband / norm)
        growth = np.exp(self.lipm.omega * max(first_landing - t, 0.0))
        return self.dcm_step_gain * growth * error

    def _publish(self, steps_k: np.ndarray, footsteps: np.ndarray) -> ContactSchedule | None:
        """Publish a schedule with the new footsteps when the next landing moved by more
        than the tolerance (the ones after it may lag: they are published with it, and the
        next landing is the one frozen). Steps after the horizon keep their planned
        displacements from the last variable one, so that the published plan stays
        reachable (with the absolute reference the QP pulls them back once in the horizon)."""
        slots = 2 + steps_k
        if np.linalg.norm(footsteps[0] - self._positions[slots[0]]) <= self.publish_tolerance:
            return None
        positions = self._positions.copy()
        positions[slots] = footsteps
        last = slots[-1]  # later steps keep their planned displacements: reachable
        positions[last + 1 :] = self._nominal[last + 1 :] + (footsteps[-1] - self._nominal[last])
        steps = list(self.schedule.plan.steps)
        for k in np.flatnonzero(np.any(positions[2:] != self._positions[2:], axis=1)):
            steps[k] = steps[k].moved(position=[*positions[2 + k], steps[k].position[2]])
        self.schedule = self.schedule.with_steps(steps)
        self._positions = positions
        self._tabulate(self.schedule)
        self.nb_publications += 1
        return self.schedule

    def _follow_plan(self, state: np.ndarray, t: float, dt: float) -> np.ndarray:
        """Integrate the jerks of the last plan exactly over ``[t, t + dt]`` from ``state``
        (zero jerk without a plan; the last jerk is held after the horizon)."""
        if self._plan is None:
            return self.cart_table.integrate(state, np.zeros(2), dt)
        knots, jerks, end = self._plan.knots, self._plan.jerks, t + dt
        while t < end - 1e-12:
            i = np.searchsorted(knots, t + 1e-12, side="right") - 1
            i = int(np.clip(i, 0, len(jerks) - 1))
            boundary = knots[i + 1] if i + 1 < len(knots) else end
            step = min(end, boundary) - t if boundary > t + 1e-12 else end - t
            state = self.cart_table.integrate(state, jerks[i], step)
            t += step
        return state
