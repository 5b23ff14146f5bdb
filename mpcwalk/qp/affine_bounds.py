"""The walking QP's bounds as an affine map of the initial state.

The bounds of the walking QP's rows are affine in the initial state ``s = x0.T.ravel()``
(the cart-table states of both axes): ``l = l0 + Kl s`` and ``u = u0 + Ku s``. The map is
made once per support sequence from the bounds at the zero state and the six unit states
(:data:`~mpcwalk.qp.layouts.UNIT_STATES`, one pass of :meth:`~mpcwalk.qp.layouts.Layout.bounds`), so that a
tick costs two products.
"""

import numpy as np

from mpcwalk.qp.layouts import UNIT_STATES, Layout
from mpcwalk.qp.schedule_tables import SupportSequence


def affine_bounds(layout: Layout, supports: SupportSequence) -> tuple:
    """``(l0, Kl, u0, Ku)`` of the bounds of ``layout``'s rows for ``supports``: ``l0`` and
    ``u0`` (m,) read-only, ``Kl`` and ``Ku`` (m, 6), a None matrix for bounds that do not
    depend on the state (the same operations as seven calls of ``bounds``, to the bit)."""
    lower, upper = layout.bounds(UNIT_STATES, supports)
    return (*_affine(lower), *_affine(upper))


def _affine(values: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
    """``(v0, K)`` of bounds ``values`` (m, 7) at the zero state and the six unit states:
    ``v0`` (read-only) and ``K`` (m, 6) with ``v = v0 + K s``, None when no bound depends
    on the state; an infinite bound stays infinite (its row of ``K`` is zero)."""
    v0 = values[:, 0].copy()
    v0.setflags(write=False)
    finite = np.isfinite(v0)
    if not finite.any():
        return v0, None
    if finite.all():
        K = values[:, 1:] - v0[:, None]
    else:
        K = np.zeros((len(v0), 6))
        K[finite] = values[finite, 1:] - v0[finite, None]
    return v0, K if K.any() else None
