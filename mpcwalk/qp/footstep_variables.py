"""What one tick of the footstep-adaptive MPC hands its QP: the supports of the constraint
points (:class:`SampleSupports`) and the footstep variables (:class:`StepVariables`), as
:class:`~mpcwalk.qp.footstep_supports.FootstepSlots` makes them and
:meth:`FootstepQP.update <mpcwalk.qp.footstep_qp.FootstepQP.update>` takes them."""

import functools
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SampleSupports:
    """ZMP constraints and ZMP centres at the constraint points, affine in the footsteps.

    The constraint points are :meth:`FootstepQP.constraint_times
    <mpcwalk.qp.footstep_qp.FootstepQP.constraint_times>` (``n = N P`` with ``P`` points
    per interval; every ``P``-th is a sample). Point ``i`` requires
    ``normals[i, r] . (Z_i - S_i F) <= offsets[i, r]`` for the rows ``r`` where
    ``rows[i, r]``; its ZMP centre is ``centres[i] + S_i F`` (used at the samples only).

    Attributes:
        normals: Outward unit normals, shape (n, E, 2).
        offsets: Shape (n, E), in [m].
        rows: Which rows are real (not padding), shape (n, E), bool.
        weights: ``S``: share of each footstep variable in the point's support, (n, nf).
        centres: Fixed part ``c0`` of the ZMP centre, shape (n, 2), in [m].
    """

    normals: np.ndarray
    offsets: np.ndarray
    rows: np.ndarray
    weights: np.ndarray
    centres: np.ndarray

    def between(self, start: int, stop: int) -> "SampleSupports":
        """The points ``start`` to ``stop`` (excluded), views of this one's arrays."""
        return SampleSupports(
            self.normals[start:stop],
            self.offsets[start:stop],
            self.rows[start:stop],
            self.weights[start:stop],
            self.centres[start:stop],
        )

    def joined(self, later: "SampleSupports") -> "SampleSupports":
        """The points of this, then those of ``later`` (of the same footstep variables)."""
        return SampleSupports(
            np.concatenate([self.normals, later.normals]),
            np.concatenate([self.offsets, later.offsets]),
            np.concatenate([self.rows, later.rows]),
            np.concatenate([self.weights, later.weights]),
            np.concatenate([self.centres, later.centres]),
        )


@dataclass(frozen=True)
class StepVariables:
    """Footstep variables of one tick: which are used, their reference, their reach.

    Attributes:
        active: Shape (nf,), bool; inactive variables are pinned at 0 by the cost only.
        reference_matrix: ``M``, shape (nf, nf).
        reference: ``r``, shape (nf, 2), in [m]: the cost pulls ``M F`` towards it.
        predecessor: Variable index of the footstep each one is reached from (the support
            foot of its step), or -1 when that foot is fixed; shape (nf,), int.
        predecessor_xy: Position of a fixed predecessor, shape (nf, 2), in [m].
        predecessor_yaw: Yaw of the predecessor, shape (nf,), in [rad].
        lower: Lowest landing in the predecessor's frame (x, y), shape (nf, 2), in [m].
        upper: Highest landing, shape (nf, 2), in [m].
        initial: Current positions (warm start of the footstep entries), (nf, 2), in [m].
        box: Half-widths of a box about ``initial`` (world x, y) each landing stays in, shape
            (nf, 2), in [m] (late step adjustment: what the swing's time left allows); None
            or inf: no box.
        band_lower: Smallest world x, y of each landing, shape (nf, 2), in [m] (the tread it
            was placed on, :class:`~mpcwalk.footsteps.landing_bands.LandingBands`); None or
            -inf: unbounded.
        band_upper: Largest world x, y of each landing, shape (nf, 2), in [m]; None or inf:
            unbounded.
    """

    active: np.ndarray
    reference_matrix: np.ndarray
    reference: np.ndarray
    predecessor: np.ndarray
    predecessor_xy: np.ndarray
    predecessor_yaw: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    initial: np.ndarray
    box: np.ndarray | None = None
    band_lower: np.ndarray | None = None
    band_upper: np.ndarray | None = None


@functools.cache
def identity_matrix(n: int) -> np.ndarray:
    """The identity of size ``n``, read-only (the reference matrix of absolute footstep
    references, one array for every tick)."""
    eye = np.eye(n)
    eye.setflags(write=False)
    return eye


__all__ = ["SampleSupports", "StepVariables", "identity_matrix"]
