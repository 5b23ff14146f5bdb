"""Cart-table model (Kajita 2003): the LIPM with CoM jerk as input.

Per horizontal axis the state is ``x = [c, c_dot, c_ddot]`` and the input is
the CoM jerk ``u``. With the jerk held constant over a sampling period ``T``
the discretisation is exact:

    x[k+1] = A x[k] + B u[k],       p[k] = C x[k],

    A = [[1, T, T^2/2], [0, 1, T], [0, 0, 1]],  B = [T^3/6, T^2/2, T],
    C = [1, 0, -z_c/g].
"""

from dataclasses import dataclass, field

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.models.lipm import LIPM


def _check_period(sampling_period: float) -> None:
    if not np.isfinite(sampling_period) or sampling_period <= 0.0:
        raise ConfigurationError(
            f"sampling_period must be a positive duration in seconds, got {sampling_period!r}."
        )


@dataclass(frozen=True)
class CartTable:
    """Discrete cart-table model of one horizontal axis.

    Attributes:
        lipm: Underlying pendulum (CoM height, gravity).
        sampling_period: Discretisation period ``T``, in [s].
    """

    lipm: LIPM
    sampling_period: float
    A: np.ndarray = field(init=False, repr=False)
    """State transition matrix, shape (3, 3)."""
    B: np.ndarray = field(init=False, repr=False)
    """Input (jerk) matrix, shape (3,)."""
    C: np.ndarray = field(init=False, repr=False)
    """ZMP output row, shape (3,): ``p = C @ x``."""

    def __post_init__(self) -> None:
        _check_period(self.sampling_period)
        A, B = self.transition(self.sampling_period)
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "B", B)
        object.__setattr__(
            self, "C", np.array([1.0, 0.0, -self.lipm.com_height / self.lipm.gravity])
        )

    @staticmethod
    def transition(duration: float):
        """Exact transition ``(A, B)`` of the triple integrator over ``duration``.

        Returns:
            ``A`` of shape (3, 3) and ``B`` of shape (3,).
        """
        T = float(duration)
        A = np.array([[1.0, T, 0.5 * T**2], [0.0, 1.0, T], [0.0, 0.0, 1.0]])
        B = np.array([T**3 / 6.0, 0.5 * T**2, T])
        return A, B

    def zmp(self, state: np.ndarray) -> np.ndarray:
        """ZMP of states with the axis state on the first dimension.

        Args:
            state: Shape (3,) or (3, ...) (e.g. (3, 2) for both axes).
        """
        return np.tensordot(self.C, np.asarray(state), axes=(0, 0))

    def integrate(self, state: np.ndarray, jerk, duration: float) -> np.ndarray:
        """Exact integration under constant jerk over an arbitrary duration.

        Args:
            state: Shape (3,) or (3, n_axes).
            jerk: Scalar or shape (n_axes,), in [m]/[s]^3.
            duration: In [s].
        """
        A, B = self.transition(duration)
        state = np.asarray(state, dtype=float)
        if state.ndim == 1:
            return A @ state + B * jerk
        return A @ state + np.outer(B, np.asarray(jerk, dtype=float))

    def prediction_matrices(self, nb_steps: int):
        """Condensed prediction over ``nb_steps`` samples (Wieber 2006).

        For a stack of jerks ``U = [u_0 .. u_{N-1}]`` and initial state ``x0``:
        ``X_pos = Pps x0 + Ppu U``, ``X_vel = Pvs x0 + Pvu U``,
        ``X_acc = Pas x0 + Pau U``, ``Z = Pzs x0 + Pzu U``, where row ``i`` is
        the quantity at sample ``i + 1``.

        Returns:
            Dict with keys ``"Pps", "Ppu", "Pvs", "Pvu", "Pas", "Pau", "Pzs",
            "Pzu"``; the ``*s`` matrices have shape (N, 3), the ``*u`` ones
            (N, N).
        """
        N = int(nb_steps)
        if N < 1:
            raise ConfigurationError(f"nb_steps must be at least 1, got {nb_steps!r}.")
        Xs = np.zeros((N, 3, 3))
        Xu = np.zeros((N, 3, N))
        Ak = np.eye(3)
        cols = np.zeros((N, 3))  # A^j B
        for j in range(N):
            cols[j] = Ak @ self.B
            Ak = self.A @ Ak
            Xs[j] = Ak
        for i in range(N):
            for j in range(i + 1):
                Xu[i, :, j] = cols[i - j]
        out = {
            "Pps": Xs[:, 0, :],
            "Ppu": Xu[:, 0, :],
            "Pvs": Xs[:, 1, :],
            "Pvu": Xu[:, 1, :],
            "Pas": Xs[:, 2, :],
            "Pau": Xu[:, 2, :],
        }
        out["Pzs"] = np.einsum("k,nkj->nj", self.C, Xs)
        out["Pzu"] = np.einsum("k,nkj->nj", self.C, Xu)
        return out
