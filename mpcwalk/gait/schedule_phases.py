"""The phases of a contact schedule, built step by step as they are asked for.

:class:`~mpcwalk.gait.contact_schedule.ContactSchedule` holds a :class:`PhaseBuilder`:
the phases of the initial stance, of each step in turn and of the final stance, each with
its support polygon (:class:`~mpcwalk.gait.support_polygons.SupportPolygons`) and its
padded half-planes. A schedule built from another one (a publication of the
footstep-adaptive MPC moves the landings from the next one on) takes the other's phases of
the steps before its first new step and builds the others when a query reaches them: the
MPC asks for the phases of its horizon only, and a publication costs those. Each phase is
built from its stance alone, in the order of the steps, so a phase built late is the phase
built at once.
"""

import numpy as np

from mpcwalk.footsteps.footstep import FootstepPlan, Side
from mpcwalk.gait.contact_phases import Phase
from mpcwalk.gait.support_polygons import MAX_POLYGON_EDGES, SupportPolygons, pose_key
from mpcwalk.models.support_polygon import SupportPolygon


class PhaseBuilder:
    """The phases of a plan built in order, on demand.

    Args:
        plan: Footsteps and timing.
        stances: ``plan.stances()``.
        polygons: The polygons of the schedule's feet and pairs of feet.
    """

    def __init__(self, plan: FootstepPlan, stances: list, polygons: SupportPolygons) -> None:
        self.plan, self.stances, self.polygons = plan, stances, polygons
        timing = plan.timing
        self.step_duration = timing.step_duration
        self.t_b = timing.single_support_begin
        self.t_e = timing.single_support_end
        self.walk_start = timing.initial_duration
        self.walk_end = self.walk_start + plan.nb_steps * self.step_duration
        self.duration = self.walk_end + timing.final_duration
        self.phases: list[Phase] = []
        """The phases built so far, in time order."""
        self.keys: list[tuple] = []  # pose key of each phase's polygon
        self.padded: list[tuple[np.ndarray, np.ndarray]] = []  # its padded half-planes
        self.rects: list[dict[Side, SupportPolygon]] = []  # the sole of each foot, per stance
        self.next_step = -1  # the initial stance's phase comes first, then step k's
        self._arrays: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    @property
    def complete(self) -> bool:
        """Whether every phase is built."""
        return self.next_step > self.plan.nb_steps

    def keep(self, source: "PhaseBuilder", first: int) -> None:
        """Take ``source``'s phases of the steps before ``first`` (their stances are this
        plan's) that it has built, and its soles of the stances up to ``first``; the others
        are built here (the same, from the same stances)."""
        until = min(first, source.next_step)
        kept = 0
        for phase in source.phases:
            if phase.step_index >= until:
                break
            kept += 1
        self.phases = source.phases[:kept]
        self.keys = source.keys[:kept]
        self.padded = source.padded[:kept]
        self.rects = source.rects[: first + 1]
        # the polygons of the last kept steps, for a later schedule's phases at the same
        # poses (one built anew is the same: a sole or a hull moved from its shape)
        for key, phase in zip(self.keys[-8:], self.phases[-8:]):
            self.polygons.keep(key, phase.polygon)
        self.next_step = until

    def build_steps(self, until: int) -> None:
        """Build the phases of the steps before ``until`` (and of the initial stance)."""
        while self.next_step < until and self.build_next():
            pass

    def build_until(self, count: int) -> None:
        """Build phases until there are ``count`` (or all)."""
        while len(self.phases) < count and self.build_next():
            pass

    def build_all(self) -> None:
        """Build every phase."""
        while self.build_next():
            pass

    def build_next(self) -> bool:
        """Build the phases of the next step (the initial stance's first, the final
        stance's last); False when every phase is built."""
        k, nb = self.next_step, self.plan.nb_steps
        if k > nb:
            return False
        if k < 0:
            if self.walk_start > 0.0:
                self._double(0.0, self.walk_start, -1, 0)
        elif k < nb:
            self._step(k)
        else:
            self._double(self.walk_end, max(self.duration, self.walk_end), nb, nb)
        self.next_step = k + 1
        if self.complete:
            self.polygons.forget_reused()
        return True

    def _step(self, k: int) -> None:
        """The phases of step ``k``: double support, single support, double support."""
        T = self.step_duration
        t0 = self.walk_start + k * T
        support = self.plan.steps[k].side.other
        if self.t_b > 0.0:
            self._double(t0, t0 + self.t_b, k, k)
        foot = self.stances[k][support]
        polygon = self.soles(k)[support]
        self._append(
            pose_key(foot),
            Phase(t0 + self.t_b, t0 + self.t_e, k, True, support, {support: foot}, polygon),
        )
        if self.t_e < T:
            self._double(t0 + self.t_e, t0 + T, k, k + 1)

    def _double(self, start: float, end: float, k: int, stance_index: int) -> None:
        """A double support on the stance ``stance_index``."""
        st = self.stances[stance_index]
        key = tuple(pose_key(f) for f in st.values())
        poly = self.polygons.polygon(key, lambda: self.polygons.hull(st))
        self._append(key, Phase(start, end, k, False, None, dict(st), poly))

    def _append(self, key: tuple, phase: Phase) -> None:
        self.keys.append(key)
        self.phases.append(phase)
        self.padded.append(self.polygons.padded_halfplanes(key, phase.polygon))

    def soles(self, k: int) -> dict[Side, SupportPolygon]:
        """The soles of stance ``k`` (those of the stances before it made first)."""
        while len(self.rects) <= k:
            st = self.stances[len(self.rects)]
            self.rects.append({side: self.polygons.rect(f) for side, f in st.items()})
        return self.rects[k]

    def arrays(self, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Padded half-planes ``(A, b)`` of the phases, shapes (n, MAX_POLYGON_EDGES, 2)
        and (n, MAX_POLYGON_EDGES) (read-only), and each one's number of edges (n,), for
        the first ``n >= count`` phases (every phase built so far, at least ``count`` of
        them, or all)."""
        self.build_until(count)
        arrays = self._arrays
        if arrays is None or len(arrays[0]) != len(self.phases):
            A = np.array([a for a, _ in self.padded]).reshape(-1, MAX_POLYGON_EDGES, 2)
            b = np.array([b for _, b in self.padded]).reshape(-1, MAX_POLYGON_EDGES)
            edges = np.fromiter((len(ph.polygon.b) for ph in self.phases), int, len(self.phases))
            for array in (A, b, edges):
                array.setflags(write=False)
            arrays = self._arrays = (A, b, edges)
        return arrays


__all__ = ["PhaseBuilder"]
