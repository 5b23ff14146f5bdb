"""Contact schedule: phases, support feet and support polygons over time.

Time ``0`` is the start of the walk. The robot stands in double support for
``timing.initial_duration``, then step ``k`` occupies
``[t0 + k T, t0 + (k + 1) T)`` with ``t0 = initial_duration``: double support
until ``t_b``, single support until ``t_e``, double support until ``T``
(paper M eq. 4). After the last step the robot stands for
``timing.final_duration``.
"""

import bisect
import functools
from typing import Optional

import numpy as np

from mpcwalk.footsteps.footstep import FootGeometry, Footstep, FootstepPlan, Side
from mpcwalk.gait.contact_phases import Phase, phase_centers
from mpcwalk.gait.schedule_phases import PhaseBuilder
from mpcwalk.gait.support_polygons import MAX_POLYGON_EDGES, SupportPolygons
from mpcwalk.models.support_polygon import SupportPolygon

_KNOT_GAP = 1e-9  # [s] knot placed just before each breakpoint of the ZMP reference


class ContactSchedule:
    """Phases of a footstep plan with fast vectorised queries.

    Args:
        plan: Footsteps and timing.
        foot: Sole dimensions used for the support polygons.
        reuse: A schedule with the same sole whose support polygons are reused for the
            feet (and pairs of feet) at the same poses; building a schedule with a few
            footsteps moved (:meth:`with_steps`) then costs a fraction of a full build. With
            the same timing and number of steps, its phases before the first new step are
            taken and the others built as queries reach them
            (:class:`~mpcwalk.gait.schedule_phases.PhaseBuilder`): the same phases, the
            cost of those asked for.
    """

    def __init__(
        self,
        plan: FootstepPlan,
        foot: FootGeometry = FootGeometry(),
        *,
        reuse: Optional["ContactSchedule"] = None,
    ) -> None:
        self.plan = plan
        self.foot = foot
        reused = reuse if reuse is not None and reuse.foot == foot else None
        # the support polygons of the feet and pairs of feet, by pose (the reused schedule's
        # when at the same poses)
        self._polygons: SupportPolygons = SupportPolygons(
            foot, reuse=reused._polygons if reused is not None else None
        )
        self._stances = plan.stances()
        # the phases, built as queries reach them; those of the steps before the first one
        # that differs from the reused schedule's are the reused schedule's (their stances
        # hold the same feet)
        self._builder = PhaseBuilder(plan, self._stances, self._polygons)
        # the timing's instants, the builder's
        self.step_duration, self.t_b, self.t_e = (
            self._builder.step_duration,
            self._builder.t_b,
            self._builder.t_e,
        )
        self.walk_start, self.walk_end = self._builder.walk_start, self._builder.walk_end
        self.duration = self._builder.duration
        first = self._first_new_step(reused)
        source: ContactSchedule | None = reused if first > 0 else None
        if source is not None:
            self._builder.keep(source._builder, first)
        # the same timing and number of steps: the same phase times as the reused schedule's
        # (the other phases are built when asked for); else every phase now, for its times
        timed = reused if reused is not None and self._same_phase_times(reused) else None
        if timed is not None:
            self._phase_starts: np.ndarray = timed._phase_starts
            self._phase_start_list: list[float] = timed._phase_start_list
            self._phase_single: np.ndarray = timed._phase_single
        else:
            phases = self.phases
            self._phase_starts = np.array([ph.start for ph in phases])
            self._phase_start_list = [float(start) for start in self._phase_starts]
            self._phase_single = np.array([ph.single_support for ph in phases])
        self._phase_centers: np.ndarray | None = None
        # The ZMP reference is piecewise linear with breakpoints at phase
        # boundaries: tabulate it there (and just before each, in case it jumps,
        # as with no double support) so that queries are one interpolation.
        if timed is not None:
            self.zmp_breakpoints: np.ndarray = timed.zmp_breakpoints
        else:
            phases = self.phases
            bounds = np.unique(
                [0.0, self.duration] + [ph.start for ph in phases] + [ph.end for ph in phases]
            )
            #: Times where the ZMP reference may bend, (k,).
            self.zmp_breakpoints = np.unique(np.concatenate([bounds, bounds[1:] - _KNOT_GAP]))

    def with_steps(self, steps) -> "ContactSchedule":
        """The same schedule with other landing poses (same initial feet, timing and sole).

        Polygons of the feet that did not move are reused, and the phases of the moved
        steps are built when a query reaches them, so moving the footsteps of a 20-step plan
        from the next landing on costs a fraction of building the schedule anew.

        Args:
            steps: Landing poses, one per step, alternating sides.
        """
        plan = FootstepPlan(
            self.plan.initial_left, self.plan.initial_right, tuple(steps), self.plan.timing
        )
        return ContactSchedule(plan, self.foot, reuse=self)

    def _same_phase_times(self, other: "ContactSchedule") -> bool:
        """Whether ``other`` has the phases' times of this schedule (the same timing and
        number of steps: the phases are built from these alone)."""
        return other.plan.timing == self.plan.timing and other.plan.nb_steps == self.plan.nb_steps

    def _first_new_step(self, reused: Optional["ContactSchedule"]) -> int:
        """Index of the first step of this plan that is not the same footstep (the same
        object) as the reused schedule's, with the same initial feet and timing; 0 without
        a reused schedule (nothing to keep)."""
        if reused is None:
            return 0
        mine, theirs = self.plan, reused.plan
        if (
            mine.timing != theirs.timing
            or mine.initial_left is not theirs.initial_left
            or mine.initial_right is not theirs.initial_right
        ):
            return 0
        first = 0
        for step, other in zip(mine.steps, theirs.steps):
            if step is not other:
                break
            first += 1
        return first

    # ----------------------------------------------------------------- phases
    # (the waypoints and the ZMP reference's values are made on first use: a schedule
    # published by the footstep MPC may never be asked for them)
    @functools.cached_property
    def torso_waypoints(self) -> np.ndarray:
        """Waypoints ``x_t[k]`` of paper M's ZMP reference: the midpoint of the feet at each
        step boundary, shape (nb_steps + 1, 2), in [m]."""
        return np.array([0.5 * (st[Side.LEFT].xy + st[Side.RIGHT].xy) for st in self._stances])

    @functools.cached_property
    def support_positions(self) -> np.ndarray:
        """Waypoints ``x_s[k]`` of paper M's ZMP reference: the support foot of each step,
        shape (nb_steps, 2), in [m]."""
        stances, steps = self._stances, self.plan.steps
        return np.array([stances[k][step.side.other].xy for k, step in enumerate(steps)]).reshape(
            -1, 2
        )

    @functools.cached_property
    def zmp_breakpoint_values(self) -> np.ndarray:
        """The ZMP reference at :attr:`zmp_breakpoints`, shape (k, 2), in [m]."""
        return self._zmp_reference_exact(self.zmp_breakpoints)

    @property
    def phases(self) -> list[Phase]:
        """Every phase, in time order."""
        self._builder.build_all()
        return self._builder.phases

    @property
    def _rects(self) -> list[dict[Side, SupportPolygon]]:
        """The sole of each foot of each stance (every one built)."""
        self._builder.build_all()
        self._builder.soles(len(self._stances) - 1)
        return self._builder.rects

    @property
    def phase_centers(self) -> np.ndarray:
        """Support centre of each phase (support foot, or midpoint of the feet), shape
        (n_phases, 2), in [m]."""
        if self._phase_centers is None:
            self._phase_centers = phase_centers(self.phases)
        return self._phase_centers

    def leading_halfplanes(self, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Padded half-planes ``(A, b)`` of the first phases (read-only), shapes
        (n, MAX_POLYGON_EDGES, 2) and (n, MAX_POLYGON_EDGES), and the number of edges of
        each, (n,): at least the first ``count`` phases (or all), the later ones built only
        when asked for (the footstep MPC's horizon reaches a few steps ahead)."""
        return self._builder.arrays(count)

    # ----------------------------------------------------------------- queries
    def phase_index(self, times) -> np.ndarray:
        """Index into :attr:`phases` of each time (clamped to the schedule)."""
        idx = np.searchsorted(self._phase_starts, np.asarray(times, dtype=float), side="right") - 1
        return np.maximum(idx, 0)  # searchsorted gives at most len(phases): idx <= len - 1

    def phase_at(self, t: float) -> int:
        """Index into :attr:`phases` of the scalar time ``t`` [s] (clamped to the schedule);
        :meth:`phase_index` for one time, without numpy."""
        index = bisect.bisect_right(self._phase_start_list, t) - 1
        return 0 if index < 0 else index

    def phase(self, t: float) -> Phase:
        """Phase active at time ``t`` [s]."""
        index = self.phase_at(t)
        self._builder.build_until(index + 1)
        return self._builder.phases[index]

    def step_index(self, t: float) -> int:
        """Step active at ``t``: -1 before the walk, ``nb_steps`` after it."""
        if t < self.walk_start:
            return -1
        return min(int((t - self.walk_start) // self.step_duration), self.plan.nb_steps)

    def step_phase(self, t: float) -> float:
        """Normalised time ``phi = t / T`` within the current step, in [0, 1]."""
        k = self.step_index(t)
        if k < 0:
            return 0.0
        if k >= self.plan.nb_steps:
            return 1.0
        return (t - self.walk_start - k * self.step_duration) / self.step_duration

    def is_single_support(self, times) -> np.ndarray:
        """Boolean array: single support at each time."""
        return self._phase_single[self.phase_index(times)]

    def support_polygon(self, t: float) -> SupportPolygon:
        """Support polygon at time ``t``."""
        return self.phase(t).polygon

    def halfplanes(self, times):
        """Padded half-planes of the support polygon at each time.

        Returns:
            ``(A, b)`` of shapes (n, MAX_POLYGON_EDGES, 2) and
            (n, MAX_POLYGON_EDGES), ``A p <= b`` inside.
        """
        idx = self.phase_index(times)
        A, b, _ = self._builder.arrays(int(idx.max()) + 1 if idx.size else 0)
        return A[idx], b[idx]

    @property
    def phase_halfplanes(self) -> tuple[np.ndarray, np.ndarray]:
        """Padded half-planes of every phase's polygon, ``(A, b)`` of shapes
        (nb_phases, MAX_POLYGON_EDGES, 2) and (nb_phases, MAX_POLYGON_EDGES) (read-only
        views: computed once per schedule)."""
        A, b, _ = self._builder.arrays(len(self._phase_starts))
        return A, b

    def support_center(self, times) -> np.ndarray:
        """Centre of the support foot in single support, midpoint of the feet in
        double support; shape (n, 2), in [m]."""
        return self.phase_centers[self.phase_index(times)]

    def zmp_reference(self, times) -> np.ndarray:
        """Paper M's polygonal ZMP reference (eq. 6-8), shape (n, 2), in [m].

        In step ``k`` the ZMP moves linearly from ``x_t[k]`` to the support
        foot ``x_s[k]`` during ``[0, t_b)``, stays there until ``t_e`` and moves
        linearly to ``x_t[k+1]`` by ``T``. Before and after the walk it stays at
        the midpoint of the feet. Evaluated by interpolation between its
        breakpoints (exact but within 1 ns of a jump when ``r_ds = 0``).
        """
        t = np.asarray(times, dtype=float)
        out = np.stack(
            [
                np.interp(t, self.zmp_breakpoints, self.zmp_breakpoint_values[:, 0]),
                np.interp(t, self.zmp_breakpoints, self.zmp_breakpoint_values[:, 1]),
            ],
            axis=-1,
        )
        return out

    def _zmp_reference_exact(self, times) -> np.ndarray:
        """Paper M's polygonal ZMP reference (eq. 6-8), shape (n, 2), in [m].

        In step ``k`` the ZMP moves linearly from ``x_t[k]`` to the support
        foot ``x_s[k]`` during ``[0, t_b)``, stays there until ``t_e`` and moves
        linearly to ``x_t[k+1]`` by ``T``. Before and after the walk it stays at
        the midpoint of the feet.
        """
        t = np.atleast_1d(np.asarray(times, dtype=float))
        out = np.empty((len(t), 2))
        N, T = self.plan.nb_steps, self.step_duration
        rel = t - self.walk_start
        k = np.floor(rel / T).astype(int)
        before, after = rel < 0.0, k >= N
        out[before] = self.torso_waypoints[0]
        out[after] = self.torso_waypoints[N]
        walking = ~(before | after)
        if np.any(walking):
            kw = k[walking]
            tau = rel[walking] - kw * T
            xt0, xs, xt1 = (
                self.torso_waypoints[kw],
                self.support_positions[kw],
                self.torso_waypoints[kw + 1],
            )
            p = xs.copy()
            if self.t_b > 0.0:
                a = np.clip(tau / self.t_b, 0.0, 1.0)[:, None]
                m = tau < self.t_b
                p[m] = (xt0 + a * (xs - xt0))[m]
            if self.t_e < T:
                a = np.clip((tau - self.t_e) / (T - self.t_e), 0.0, 1.0)[:, None]
                m = tau >= self.t_e
                p[m] = (xs + a * (xt1 - xs))[m]
            out[walking] = p
        return out if np.ndim(times) else out[0]

    def reference_velocity(self, times) -> np.ndarray:
        """Average walking velocity of each step: ``(x_t[k+1] - x_t[k]) / T`` during
        step ``k``, zero before and after the walk; shape (n, 2), in [m]/[s]."""
        t = np.atleast_1d(np.asarray(times, dtype=float))
        N, T = self.plan.nb_steps, self.step_duration
        k = np.floor((t - self.walk_start) / T).astype(int)
        out = np.zeros((len(t), 2))
        walking = (k >= 0) & (k < N)
        kw = k[walking]
        out[walking] = (self.torso_waypoints[kw + 1] - self.torso_waypoints[kw]) / T
        return out if np.ndim(times) else out[0]

    def feet_on_ground(self, t: float) -> dict[Side, Footstep]:
        """Feet in contact at ``t`` (one in single support, two otherwise)."""
        return dict(self.phase(t).feet)

    def _stance_index(self, t: float) -> int:
        k = self.step_index(t)
        return max(k, 0) if k < self.plan.nb_steps else len(self._stances) - 1

    def stance(self, t: float) -> dict[Side, Footstep]:
        """Last landed pose of both feet at ``t`` (the swing foot: its lift pose)."""
        return dict(self._stances[self._stance_index(t)])


__all__ = ["MAX_POLYGON_EDGES", "ContactSchedule", "Phase"]
