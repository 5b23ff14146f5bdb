"""Shifting a QP's per-sample vectors by a fraction of the horizon (warm starts)."""

import numpy as np

#: (start, shape, sample axis) of a block of a primal or dual vector.
Block = tuple[int, tuple[int, ...], int | None]


def shift_gather(blocks: list[Block], size: int, samples: float, N: int):
    """Index arrays ``(i0, i1, w)`` with ``shifted = (1 - w) v[i0] + w v[i1]``."""
    i0, i1, w = np.arange(size), np.arange(size), np.zeros(size)
    pos = np.arange(N) + samples
    base = np.floor(pos)
    s0 = np.clip(base.astype(int), 0, N - 1)
    s1 = np.clip(s0 + 1, 0, N - 1)
    frac = np.where(base >= N - 1, 0.0, np.clip(pos - base, 0.0, 1.0))
    for start, shape, axis in blocks:
        if axis is None:
            continue
        index = np.moveaxis(np.arange(int(np.prod(shape))).reshape(shape), axis, 0)
        dst = start + index
        i0[dst] = start + index[s0]
        i1[dst] = start + index[s1]
        w[dst] = frac.reshape((N,) + (1,) * (index.ndim - 1))
    return i0, i1, w


__all__ = ["Block", "shift_gather"]
