"""The footstep MPC's prediction matrices over its horizon, for one first interval.

The samples of :class:`~mpcwalk.qp.footstep_qp.FootstepQP` lie on a grid that does not slide
with the ticks: the first interval of a tick's horizon lasts between one control period and
one sampling period, the others one sampling period. :func:`horizon_predictions` gives, for
one first interval, the cart-table's states and ZMP at the samples and at the constraint
points as affine maps of the initial state and the jerks, the jerks' block of the cost and
the DCM at the last sample (the QP caches them per first interval).
"""

import numpy as np

from mpcwalk.models.cart_table import CartTable
from mpcwalk.qp.footstep_parameters import FootstepMpcParameters


def horizon_predictions(
    model: CartTable, parameters: FootstepMpcParameters, omega: float, first: float
) -> dict[str, np.ndarray]:
    """Prediction matrices (``P?s`` (N, 3), ``P?u`` (N, N), as
    :meth:`CartTable.prediction_matrices`; ``C?s``, ``C?u`` at the constraint points) when the
    first interval lasts ``first`` [s] and the others one sampling period of ``model``, with
    the jerks' block of the cost (``H_jerk``) and the DCM at the last sample (``Pds``,
    ``Pdu``; ``omega`` [1/s] is the pendulum's)."""
    p, N = parameters, parameters.horizon
    A1, B1 = CartTable.transition(first)
    A, B = model.A, model.B
    Xs, Xu = np.zeros((N, 3, 3)), np.zeros((N, 3, N))
    Xs[0], Xu[0, :, 0] = A1, B1
    for i in range(1, N):
        Xs[i] = A @ Xs[i - 1]
        Xu[i] = A @ Xu[i - 1]
        Xu[i, :, i] = B
    C = model.C
    pred = {
        "Pps": Xs[:, 0],
        "Ppu": Xu[:, 0],
        "Pvs": Xs[:, 1],
        "Pvu": Xu[:, 1],
        "Pas": Xs[:, 2],
        "Pau": Xu[:, 2],
        "Pzs": np.einsum("k,nkj->nj", C, Xs),
        "Pzu": np.einsum("k,nkj->nj", C, Xu),
    }
    # ZMP at the constraint points: from the state at the start of each interval.
    P = p.constraint_points
    # (states at the constraint points, then C of them: position and acceleration kept
    # for a time-varying ZMP row, see :meth:`FootstepQP._with_heights
    # <mpcwalk.qp.footstep_qp.FootstepQP._with_heights>`)
    Ss, Su = np.zeros((N, P, 3, 3)), np.zeros((N, P, 3, N))
    for i in range(N):
        length = first if i == 0 else p.sampling_period
        start_s = np.eye(3) if i == 0 else Xs[i - 1]
        start_u = np.zeros((3, N)) if i == 0 else Xu[i - 1]
        for j in range(P):
            Aj, Bj = CartTable.transition(length * (j + 1) / P)
            Ss[i, j] = Aj @ start_s
            Su[i, j] = Aj @ start_u
            Su[i, j, :, i] += Bj
    pred["Czs"] = np.einsum("k,npkj->npj", C, Ss).reshape(N * P, 3)
    pred["Czu"] = np.einsum("k,npkj->npj", C, Su).reshape(N * P, N)
    for name, row in (("Cp", 0), ("Ca", 2)):
        pred[name + "s"] = Ss[:, :, row].reshape(N * P, 3)
        pred[name + "u"] = Su[:, :, row].reshape(N * P, N)
    H = (
        p.zmp_weight * pred["Pzu"].T @ pred["Pzu"]
        + p.velocity_weight * pred["Pvu"].T @ pred["Pvu"]
        + p.jerk_weight * np.eye(N)
    )
    pred["H_jerk"] = 0.5 * (H + H.T)
    # DCM at the last sample, xi = c + c_dot / omega
    pred["Pds"] = pred["Pps"][-1] + pred["Pvs"][-1] / omega
    pred["Pdu"] = pred["Ppu"][-1] + pred["Pvu"][-1] / omega
    return pred


__all__ = ["horizon_predictions"]
