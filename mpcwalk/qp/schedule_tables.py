"""Per-phase tables of a contact schedule, for fast per-tick lookups, and the sequence of
supports the walking QP's inequality rows use."""

from dataclasses import dataclass

import numpy as np

from mpcwalk.gait.contact_schedule import MAX_POLYGON_EDGES, ContactSchedule


@dataclass(frozen=True)
class ScheduleTables:
    """What the walking QP reads from a schedule, one row per phase.

    Attributes:
        polygon_id: Shape (nb_phases,); phases with the same support polygon
            (the double support closing step k and the one opening step
            k + 1) share an id, so the QP matrix is not rebuilt between them.
        A: Padded half-plane normals, shape (nb_phases, E, 2).
        b: Offsets, shape (nb_phases, E), in [m].
        single: Single support, shape (nb_phases,).
        centers: Support centre (support foot, or midpoint of the feet),
            shape (nb_phases, 2), in [m].
        knots: Breakpoints of the ZMP reference, shape (k,), in [s].
        zmp_knots: ZMP reference at the knots, shape (k, 2), in [m].
        next_single: First single-support phase at or after each phase
            (``nb_phases`` if none), shape (nb_phases,).
        step_velocities: Average walking velocity of each step, shape (nb_steps, 2), in
            [m/s] (``ContactSchedule.reference_velocity``).
        walk_start: Start of the first step, in [s].
        step_duration: Step duration, in [s].
    """

    polygon_id: np.ndarray
    A: np.ndarray
    b: np.ndarray
    single: np.ndarray
    centers: np.ndarray
    knots: np.ndarray
    zmp_knots: np.ndarray
    next_single: np.ndarray
    step_velocities: np.ndarray
    walk_start: float
    step_duration: float

    @staticmethod
    def from_schedule(schedule: ContactSchedule) -> "ScheduleTables":
        """Tables of ``schedule`` (one pass over its phases)."""
        phases = schedule.phases
        A, b = schedule.phase_halfplanes  # padded to MAX_POLYGON_EDGES rows, per phase
        same = np.all(A[1:] == A[:-1], axis=(1, 2)) & np.all(b[1:] == b[:-1], axis=1)
        polygon_id = np.arange(len(phases))
        for i in np.flatnonzero(same) + 1:
            polygon_id[i] = polygon_id[i - 1]
        single = np.array([ph.single_support for ph in phases])
        centers = schedule.phase_centers
        # Paper M's ZMP reference is piecewise linear: the schedule tabulates
        # it at its breakpoints; interpolate every tick.
        knots = schedule.zmp_breakpoints
        next_single = np.full(len(phases) + 1, len(phases))
        for j in range(len(phases) - 1, -1, -1):
            next_single[j] = j if single[j] else next_single[j + 1]
        waypoints, T = schedule.torso_waypoints, schedule.step_duration
        return ScheduleTables(
            polygon_id,
            A,
            b,
            single,
            centers,
            knots,
            schedule.zmp_reference(knots),
            next_single[:-1],
            (waypoints[1:] - waypoints[:-1]) / T,
            float(schedule.walk_start),
            float(T),
        )

    def com_phases(self, start: np.ndarray, end: np.ndarray) -> np.ndarray:
        """Phase whose polygon bounds the CoM at each sample.

        It is the first single-support phase met during the sampling period
        that follows the sample (phases ``start..end``), if any, else the
        phase at the sample. The foot of a single support lies inside the
        neighbouring double-support hulls, so the CoM is over it before single
        support begins, wherever the samples fall relative to the boundary;
        without this, a sliding sample grid finds the CoM "just in time" one
        tick and infeasible the next.

        Args:
            start: Phase index at each sample, shape (N,).
            end: Phase index one sampling period later, shape (N,).
        """
        first = self.next_single[start]
        return np.where(first <= end, first, start)

    def reference_velocity(self, times: np.ndarray) -> np.ndarray:
        """Same values as ``ContactSchedule.reference_velocity`` (the average walking
        velocity of each step, zero before and after the walk); shape (n, 2), in [m/s]."""
        k = np.floor((times - self.walk_start) / self.step_duration).astype(int)
        out = np.zeros((len(k), 2))
        walking = (k >= 0) & (k < len(self.step_velocities))
        out[walking] = self.step_velocities[k[walking]]
        return out

    def zmp_reference(self, times: np.ndarray) -> np.ndarray:
        """Same values as ``ContactSchedule.zmp_reference``, by interpolation;
        shape (n, 2), in [m]."""
        out = np.empty((len(times), 2))
        out[:, 0] = np.interp(times, self.knots, self.zmp_knots[:, 0])
        out[:, 1] = np.interp(times, self.knots, self.zmp_knots[:, 1])
        return out


@dataclass(frozen=True)
class SupportSequence:
    """Half-planes ``A p <= b`` used by the walking QP's inequality rows, ``E`` (=
    :data:`~mpcwalk.gait.contact_schedule.MAX_POLYGON_EDGES`) rows per polygon.

    Attributes:
        zmp_A: ZMP polygon normals at the samples, shape (N, E, 2).
        zmp_b: Offsets, shape (N, E), in [m]. The last sample's polygon also
            bounds the terminal DCM.
        com_A: CoM polygon normals at the samples, shape (N, E, 2).
        com_b: Offsets, shape (N, E), in [m].
        tick_A: Polygon normals at the next control tick, shape (E, 2).
        tick_b: Offsets, shape (E,), in [m].
    """

    zmp_A: np.ndarray
    zmp_b: np.ndarray
    com_A: np.ndarray
    com_b: np.ndarray
    tick_A: np.ndarray
    tick_b: np.ndarray

    @staticmethod
    def empty(N: int) -> "SupportSequence":
        """Placeholder of the right shapes (all zeros)."""
        E = MAX_POLYGON_EDGES
        A, b = np.zeros((N, E, 2)), np.zeros((N, E))
        return SupportSequence(A, b, A, b, A[0], b[0])
