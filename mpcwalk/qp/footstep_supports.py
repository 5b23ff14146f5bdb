"""Where the samples of the footstep-adaptive MPC stand: footstep slots, supports, reach.

The footsteps of a walk are numbered as slots: 0 and 1 the initial left and right feet,
``2 + k`` the landing of step ``k``. Step ``k`` is made from the support foot
``support[k]`` by the swing foot that lifts from ``lift[k]``.

Support of a sample between slots A and B (``lam``: share of B; single support: A = B): in
double support ``lam`` runs from 0 to 1 (0.5 at the step boundary, where paper M's
reference passes the feet midpoint); before and after the walk it is 0.5. With both feet
fixed the ZMP stays in the hull of the soles (as the fixed-footstep MPC); with a footstep
variable, in the sole-sized rectangle of
:func:`~mpcwalk.qp.footstep_parameters.blended_rectangles` centred at
``(1 - lam) A + lam B``, inside that hull for any positions. The ZMP cost pulls to the
same centre (paper M's polygonal reference, eq. 6-8, on the variable footsteps).
:class:`FootstepSlots` turns this into the :class:`SampleSupports` and
:class:`StepVariables` that :meth:`FootstepQP.update
<mpcwalk.qp.footstep_qp.FootstepQP.update>` takes.
"""

from collections.abc import Iterable

import numpy as np

from mpcwalk.exceptions import ConfigurationError, InfeasibleStep
from mpcwalk.footsteps.footstep import Side, wrap_angle
from mpcwalk.footsteps.landing_bands import LandingBands
from mpcwalk.footsteps.reachability import ReachabilityRectangle
from mpcwalk.gait.contact_schedule import MAX_POLYGON_EDGES, ContactSchedule
from mpcwalk.gait.swing_retarget import SwingLimits
from mpcwalk.qp.footstep_parameters import blended_rectangles
from mpcwalk.qp.footstep_variables import SampleSupports, StepVariables, identity_matrix

_BOUNDARY_EPS = 1e-9  # [s] a sample on a phase boundary belongs to the new phase
_REACH_TOLERANCE = 1e-6  # [m], [rad] nominal steps may touch the rectangle's edges


class FootstepSlots:
    """The footsteps of one walk as slots of the footstep-adaptive MPC.

    Args:
        schedule: The walk's nominal schedule (footsteps, sides, yaws and timing).
        reachability: Landings allowed relative to the support foot.
        planned_strides: Grow each step's bounds to hold its planned displacement.
        late: Swing limits of the late step adjustment (None: no box on the landings; see
            :meth:`step_variables`).
        bands: Where each landing may move (the top it was placed on), one band per step of
            the schedule's plan; None: anywhere within reach.

    Attributes:
        nominal: Planned positions of the slots, shape (nb_steps + 2, 2), in [m].
        positions: Positions as last published, shape (nb_steps + 2, 2), in [m].
        yaws: Yaw of each slot, shape (nb_steps + 2,), in [rad].
        support: Slot of the support foot of each step, shape (nb_steps,).
        lift: Slot the swing foot of each step lifts from, shape (nb_steps,).
        landing: Landing time of each step, shape (nb_steps,), in [s].
        current: The schedule with the published positions.
    """

    def __init__(
        self,
        schedule: ContactSchedule,
        reachability: ReachabilityRectangle,
        planned_strides: bool = False,
        late: SwingLimits | None = None,
        bands: LandingBands | None = None,
    ) -> None:
        self.late = late
        plan = schedule.plan
        if bands is not None and len(bands) != plan.nb_steps:
            raise ConfigurationError(
                f"The landing bands hold {len(bands)} landings and the plan {plan.nb_steps} "
                "steps: make them from the same plan (tread_bands(plan, terrain, reach))."
            )
        self.bands = bands
        self.planned_strides = bool(planned_strides)
        self.nominal_schedule = schedule
        self.reachability = reachability
        self.nb_steps = nb = plan.nb_steps
        self.feet = [plan.initial_left, plan.initial_right, *plan.steps]
        self.nominal = np.array([f.xy for f in self.feet]).reshape(-1, 2)
        self.positions = self.nominal.copy()
        self.yaws = np.array([f.yaw for f in self.feet])
        init = {Side.LEFT: 0, Side.RIGHT: 1}
        sides = [s.side for s in plan.steps]
        self.support = np.array([2 + k - 1 if k else init[sides[0].other] for k in range(nb)], int)
        self.lift = np.array([2 + k - 2 if k >= 2 else init[sides[k]] for k in range(nb)], int)
        self.bounds = [
            self._bounds_holding(reachability.bounds(side), k) for k, side in enumerate(sides)
        ]
        self.landing = schedule.walk_start + np.arange(nb) * schedule.step_duration + schedule.t_e
        self.current = schedule
        self._later_supports: tuple | None = None  # the points after the fresh ones
        self._reach_rows: tuple | None = None  # the footstep variables' reach
        self._reference_velocity: tuple | None = None  # at the last samples
        self._tabulate(schedule)

    def _bounds_holding(self, bounds, k: int):
        """The rectangle's ``(lower, upper)`` of step ``k`` grown to hold its planned
        displacement (x, y, yaw) from its support foot when ``planned_strides`` (a planner that
        places footsteps on a terrain strides beyond the flat rectangle, onto a tread or a
        stone; the generator adapts the step about it); else the rectangle as it is."""
        lower, upper = (np.array(b, dtype=float) for b in bounds)
        p, slot = self.support[k], 2 + k
        yaw = self.yaws[p]
        R = np.array([[np.cos(yaw), np.sin(yaw)], [-np.sin(yaw), np.cos(yaw)]])
        local = np.append(
            R @ (self.nominal[slot] - self.nominal[p]), wrap_angle(self.yaws[slot] - yaw)
        )
        if not self.planned_strides:
            return lower, upper  # the flat rectangle (check_reachable refuses what leaves it)
        return np.minimum(lower, local), np.maximum(upper, local)

    def check_reachable(self) -> None:
        """Every planned step must lie in the rectangle of its support foot.

        Raises:
            InfeasibleStep: A planned step outside the rectangle.
        """
        for k in range(self.nb_steps):
            p, slot = self.support[k], 2 + k
            yaw = self.yaws[p]
            R = np.array([[np.cos(yaw), np.sin(yaw)], [-np.sin(yaw), np.cos(yaw)]])
            local = np.append(
                R @ (self.nominal[slot] - self.nominal[p]), wrap_angle(self.yaws[slot] - yaw)
            )
            lower, upper = self.bounds[k]
            if np.any(local < lower - _REACH_TOLERANCE) or np.any(local > upper + _REACH_TOLERANCE):
                raise InfeasibleStep(
                    f"Planned step {k} ({self.feet[slot].side.value} foot) lands at "
                    f"(x, y, yaw) = ({local[0]:.4f} m, {local[1]:.4f} m, {local[2]:.4f} rad) in "
                    f"its support foot's frame, outside the reachability rectangle "
                    f"({self.reachability.describe()}). Widen the rectangle (reachability=) "
                    "or plan the footsteps within it (VelocityPlanner with the same LegLimits)."
                )

    def _tabulate(self, schedule: ContactSchedule, count: int = 0) -> None:
        """Half-planes of the schedule's first phases (at least ``count``; those the
        schedule has built; none for -1), padded, with a mask of the real rows."""
        E = MAX_POLYGON_EDGES
        A, b, edges = np.zeros((0, E, 2)), np.zeros((0, E)), np.zeros(0, int)
        if count >= 0:
            A, b, edges = schedule.leading_halfplanes(count)
        # the schedule's padded half-planes, the padding rows zero and masked out
        rows = np.arange(MAX_POLYGON_EDGES)[None, :] < edges[:, None]
        self._phase_A = np.where(rows[..., None], A, 0.0)
        self._phase_b = np.where(rows, b, 0.0)
        self._phase_rows = rows

    def free_steps(
        self, t: float, last_sample: float, freeze_before_landing: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """Steps whose landing is free at ``t`` [s] (not frozen ``freeze_before_landing``
        [s] before touch-down, landing by ``last_sample`` [s]), and the variable index of
        every slot (-1: fixed)."""
        free = (t < self.landing - freeze_before_landing - _BOUNDARY_EPS) & (
            self.landing <= last_sample + _BOUNDARY_EPS
        )
        steps_k = np.flatnonzero(free)
        variable = np.full(self.nb_steps + 2, -1)
        variable[2 + steps_k] = np.arange(len(steps_k))
        return steps_k, variable

    def reference_velocity(self, times: np.ndarray) -> np.ndarray:
        """The nominal schedule's reference velocity at the sample ``times`` [s], shape
        (n, 2), in [m/s] (read-only): the last call's while the times are the same (the
        ticks of one sampling interval share their samples)."""
        key = times.tobytes()
        cached = self._reference_velocity
        if cached is None or cached[0] != key:
            velocity = self.nominal_schedule.reference_velocity(times)
            velocity.setflags(write=False)
            cached = self._reference_velocity = (key, velocity)
        return cached[1]

    def slots(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Feet A and B (slots) of each sample and the share ``lam`` of B in its support."""
        sched, nb = self.nominal_schedule, self.nb_steps
        T, t_b, t_e = sched.step_duration, sched.t_b, sched.t_e
        rel = times + _BOUNDARY_EPS - sched.walk_start
        k = np.floor(rel / T).astype(int)
        n = len(times)
        A, B, lam = np.zeros(n, int), np.ones(n, int), np.full(n, 0.5)
        if nb:
            A[:], B[:] = self.lift[0], self.support[0]  # before the walk: both initial feet
            after = k >= nb
            A[after], B[after] = self.support[-1], 2 + nb - 1
            walk = (rel >= 0.0) & ~after
            kw = k[walk]
            tau = rel[walk] - kw * T
            a, b, w = self.support[kw].copy(), self.support[kw].copy(), np.zeros(len(kw))
            opening, closing = tau < t_b, tau >= t_e
            a[opening] = self.lift[kw[opening]]
            if t_b > 0.0:
                w[opening] = 0.5 + 0.5 * tau[opening] / t_b
            if t_e < T:
                b[closing] = 2 + kw[closing]
                w[closing] = 0.5 * (tau[closing] - t_e) / (T - t_e)
            A[walk], B[walk], lam[walk] = a, b, w
        return A, B, lam

    def supports(
        self,
        times: np.ndarray,
        variable: np.ndarray,
        nf: int,
        *,
        fresh: int | None = None,
        upcoming: Iterable[np.ndarray] = (),
    ) -> SampleSupports:
        """ZMP constraints and centres at ``times`` [s] for ``nf`` footstep variables: the
        published polygons where both feet are fixed, blended rectangles on the footstep
        variables elsewhere.

        ``fresh``: only the first ``fresh`` times may be new: the points after them are
        taken from the previous call when their times, ``variable``, ``nf`` and the
        published footsteps are the same, and so are the first ones when they are among
        the ``upcoming`` ones given then (every point is computed on its own, so the result
        is the one computed anew). The ticks of one sampling interval share every
        constraint point but those of the first interval; ``upcoming``: those of the next
        ticks of the interval (``fresh`` times each; iterated only when the points after
        the first ones are new). None computes every point.
        """
        if fresh is None:
            return self._supports(times, variable, nf)
        later, first = times[fresh:], times[:fresh]
        key = (later.tobytes(), variable.tobytes(), nf, id(self.positions), id(self.current))
        cached = self._later_supports
        if cached is None or cached[0] != key:
            heads = [first, *(head for head in upcoming if len(head) == fresh)]
            both = self._supports(np.concatenate([*heads, later]), variable, nf)
            firsts = {
                h.tobytes(): both.between(j * fresh, (j + 1) * fresh) for j, h in enumerate(heads)
            }
            # the key's objects are held with it: their ids are not reused meanwhile
            cached = self._later_supports = (
                key,
                both.between(len(heads) * fresh, len(both.rows)),
                firsts,
                (self.positions, self.current),
            )
        head = cached[2].get(first.tobytes())
        if head is None:
            head = self._supports(first, variable, nf)
        return head.joined(cached[1])

    def _supports(self, times: np.ndarray, variable: np.ndarray, nf: int) -> SampleSupports:
        """:meth:`supports`, every point computed."""
        A, B, lam = self.slots(times)
        va, vb = variable[A], variable[B]
        pos = self.positions
        centres = np.where(va[:, None] < 0, (1.0 - lam)[:, None] * pos[A], 0.0) + np.where(
            vb[:, None] < 0, lam[:, None] * pos[B], 0.0
        )
        weights = np.zeros((len(times), nf + 1))  # last column: the fixed feet, dropped
        samples = np.arange(len(times))
        # each sample once per statement: plain fancy-indexed sums (as np.add.at)
        weights[samples, np.where(va >= 0, va, nf)] += 1.0 - lam
        weights[samples, np.where(vb >= 0, vb, nf)] += lam
        weights = weights[:, :nf]
        moving = np.flatnonzero((va >= 0) | (vb >= 0))
        idx = self.current.phase_index(times + _BOUNDARY_EPS)
        if len(idx) and idx.max() >= len(self._phase_rows):  # phases the tables lack
            self._tabulate(self.current, int(idx.max()) + 1)
        # (take copies)
        normals, offsets = self._phase_A.take(idx, axis=0), self._phase_b.take(idx, axis=0)
        rows = self._phase_rows.take(idx, axis=0)
        if len(moving):
            blended, half = blended_rectangles(
                self.yaws[A[moving]], self.yaws[B[moving]], lam[moving], self.current.foot
            )
            normals[moving, :4] = blended
            normals[moving, 4:] = 0.0
            offsets[moving, :4] = half + np.einsum("kra,ka->kr", blended, centres[moving])
            offsets[moving, 4:] = 0.0
            rows[moving, :4] = True
            rows[moving, 4:] = False
        return SampleSupports(normals, offsets, rows, weights, centres)

    def step_variables(
        self,
        steps_k: np.ndarray,
        variable: np.ndarray,
        nf: int,
        *,
        absolute: bool,
        offset: np.ndarray,
        now: float | None = None,
    ) -> StepVariables:
        """Reference and reach of the footstep variables (steps ``steps_k``).

        Args:
            steps_k: Steps whose landings are variables, in variable order.
            variable: Variable index of every slot (-1: fixed).
            nf: Number of footstep variables of the QP.
            absolute: Pull each footstep to its planned position moved by ``offset``;
                False: to its planned displacement from its support foot.
            offset: Move of the absolute references, shape (2,), in [m].
            now: Time [s] of the re-plan the footsteps go to (the output's), None: no box;
                with ``late`` swing limits, each landing is boxed about its published position by
                :meth:`~mpcwalk.gait.swing_retarget.SwingLimits.landing_change_bound` of the
                time left until it.
        """
        count = len(steps_k)
        active, pred, pred_xy, pred_yaw, lower, upper, initial = self._reach(steps_k, variable, nf)
        r = np.zeros((nf, 2))
        slots, support = 2 + steps_k, self.support[steps_k]
        if absolute:  # M = I, one read-only array for every tick
            M = identity_matrix(nf)
            r[:count] = self.nominal[slots] + offset
        else:
            M = np.eye(nf)
            r[:count] = self.nominal[slots] - self.nominal[support]
            chained = variable[support] >= 0
            M[np.flatnonzero(chained), variable[support[chained]]] = -1.0
            fixed = np.flatnonzero(~chained)
            r[fixed] += self.positions[support[fixed]]
        half = None
        if self.late is not None and now is not None:
            half = np.full((nf, 2), np.inf)
            box = self.late.landing_change_bound(self.landing[steps_k] - now)
            half[: len(steps_k)] = np.asarray(box, dtype=float)[:, None]
        band_lower = band_upper = None
        if self.bands is not None:
            band_lower, band_upper = np.full((nf, 2), -np.inf), np.full((nf, 2), np.inf)
            band_lower[: len(steps_k)] = self.bands.lower[steps_k]
            band_upper[: len(steps_k)] = self.bands.upper[steps_k]
        return StepVariables(
            active,
            M,
            r,
            pred,
            pred_xy,
            pred_yaw,
            lower,
            upper,
            initial,
            half,
            band_lower,
            band_upper,
        )

    def _reach(self, steps_k: np.ndarray, variable: np.ndarray, nf: int) -> tuple:
        """``(active, predecessor, predecessor_xy, predecessor_yaw, lower, upper, initial)``
        of :class:`StepVariables` for the steps ``steps_k``: the last call's arrays (read-only)
        while the steps, ``variable``, ``nf`` and the published footsteps are the same (they
        change when a landing is frozen or a schedule published, not from tick to tick)."""
        key = (steps_k.tobytes(), variable.tobytes(), nf, id(self.positions))
        cached = self._reach_rows
        if cached is not None and cached[0] == key:
            return cached[1]
        active = np.zeros(nf, bool)
        pred = np.full(nf, -1)
        pred_xy, pred_yaw = np.zeros((nf, 2)), np.zeros(nf)
        lower, upper = np.full((nf, 2), -1.0), np.ones((nf, 2))
        initial = np.zeros((nf, 2))
        for j, k in enumerate(steps_k):
            p = self.support[k]
            active[j] = True
            pred[j], pred_xy[j], pred_yaw[j] = variable[p], self.positions[p], self.yaws[p]
            lower[j], upper[j] = self.bounds[k][0][:2], self.bounds[k][1][:2]
            initial[j] = self.positions[2 + k]
        arrays = (active, pred, pred_xy, pred_yaw, lower, upper, initial)
        for array in arrays:
            array.setflags(write=False)
        # the positions are held with the key: their id is not reused meanwhile
        self._reach_rows = (key, arrays, self.positions)
        return arrays

    def publish(
        self, steps_k: np.ndarray, footsteps: np.ndarray, tolerance: float
    ) -> ContactSchedule | None:
        """The schedule with the new footsteps when the next landing moved by more than
        ``tolerance`` [m] (the ones after it may lag: they are published with it, and the
        next landing is the one frozen), else None. Steps after the horizon keep their
        planned displacements from the last variable one, so that the published plan stays
        reachable (with the absolute reference the QP pulls them back once in the horizon),
        moved into their :attr:`bands` (a later landing stays on its tread)."""
        slots = 2 + steps_k
        if np.linalg.norm(footsteps[0] - self.positions[slots[0]]) <= tolerance:
            return None
        positions = self.positions.copy()
        positions[slots] = footsteps
        last = slots[-1]  # later steps keep their planned displacements: reachable
        positions[last + 1 :] = self.nominal[last + 1 :] + (footsteps[-1] - self.nominal[last])
        if self.bands is not None:  # ... within their bands
            later = np.arange(last + 1, len(positions))
            positions[later] = self.bands.clip(later - 2, positions[later])
        steps = list(self.current.plan.steps)
        for k in np.flatnonzero(np.any(positions[2:] != self.positions[2:], axis=1)):
            steps[k] = steps[k].moved(position=[*positions[2 + k], steps[k].position[2]])
        self.current = self.current.with_steps(steps)
        self.positions = positions
        self._tabulate(self.current, -1)  # none: the phases are tabulated as they are reached
        return self.current


__all__ = ["FootstepSlots", "SampleSupports", "StepVariables"]
