"""ZMP preview control on the cart-table model (Kajita et al. 2003).

Per horizontal axis the cart-table state ``x = [c, c_dot, c_ddot]`` is driven
by the CoM jerk ``u``, held over each sampling period ``T``. The controller is
an LQR with preview of the future ZMP reference ``r``:

    u[k] = -Gi sum_{i<=k} (p[i] - r[i]) - Gx x[k] - sum_{j=1}^{N_L} Gd[j] r[k+j].

With integral action (Kajita's form) the gains come from the Riccati equation
of the augmented system ``[sum of ZMP errors; Delta x]`` with input
``Delta u`` and cost ``sum Qe e^2 + Delta x^T Qx Delta x + R Delta u^2``
(``Gd[1] = -Gi``). Without it (``Gi = 0``) the gains are those of the plain
infinite-horizon LQ tracking problem

    min sum_{j>=1} Qe (C x[k+j] - r[k+j])^2 + x[k+j]^T Qx x[k+j] + R u[k+j-1]^2

with the reference taken as zero beyond the preview window, which is exactly
the finite-horizon problem over ``N_L`` samples with terminal cost
``x^T (P - Qe C^T C - Qx) x`` on ``x[k+N_L]``: the linear MPC without
constraints gives the same first input. ``Qx`` weights the full state there,
so keep it at 0 for tracking.

The integral sum starts where it would be had the CoM rested above the
initial reference (bumpless start), which makes the integral version
independent of the world origin. The plain version is not exactly: the
truncated preview sum leaves ``Gx[0] + sum(Gd)`` slightly nonzero (1e-4 of
``Gx[0]`` with the defaults), so moving the whole walk by 11 m moves the
planned CoM by 0.9 mm relative to the feet.
"""

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.generators.pattern_generator import GeneratorOutput, Horizon, PatternGenerator
from mpcwalk.models.cart_table import CartTable
from mpcwalk.models.com_state import ComState
from mpcwalk.models.lipm import LIPM


@dataclass(frozen=True)
class PreviewGains:
    """Gains of the preview controller (the same for x and y).

    Attributes:
        Gi: Integral gain on the summed ZMP error, in [1/s^3]; 0 without
            integral action.
        Gx: State feedback gain, shape (3,).
        Gd: Preview gains on ``r[k+1] .. r[k+N_L]``, shape (N_L,), in [1/s^3].
        P: Riccati solution, shape (4, 4) with integral action, else (3, 3).
        closed_loop: State matrix under the feedback (same shape as ``P``).
        integral_action: Which design produced the gains.
    """

    Gi: float
    Gx: np.ndarray
    Gd: np.ndarray
    P: np.ndarray
    closed_loop: np.ndarray
    integral_action: bool

    @property
    def spectral_radius(self) -> float:
        """Largest eigenvalue modulus of :attr:`closed_loop` (< 1 when stable)."""
        return float(np.max(np.abs(np.linalg.eigvals(self.closed_loop))))


def compute_preview_gains(
    model: CartTable,
    nb_preview: int,
    *,
    zmp_weight: float = 1.0,
    jerk_weight: float = 1e-6,
    state_weight=0.0,
    integral_action: bool = True,
) -> PreviewGains:
    """Riccati and preview gains of Kajita's controller.

    Args:
        model: Discrete cart-table model (sampling period, CoM height).
        nb_preview: Number ``N_L`` of previewed reference samples.
        zmp_weight: ``Qe``, weight of the squared ZMP error, in [1/m^2].
        jerk_weight: ``R``, weight of the squared jerk (of its increment with
            integral action), in [s^6/m^2].
        state_weight: ``Qx``, scalar (times identity) or (3, 3) matrix.
        integral_action: Kajita's augmented design (True) or the plain LQR
            with preview (False).

    Returns:
        The gains.

    Raises:
        ConfigurationError: on non-positive weights or a Riccati failure.
    """
    Qx = np.asarray(state_weight, dtype=float)
    Qx = Qx * np.eye(3) if Qx.ndim == 0 else Qx
    if (
        Qx.shape != (3, 3)
        or not np.all(np.isfinite(Qx))
        or np.min(np.linalg.eigvalsh(0.5 * (Qx + Qx.T))) < -1e-12
    ):
        raise ConfigurationError(
            f"state_weight must be a non-negative scalar or a 3x3 positive semi-definite "
            f"matrix, got {state_weight!r}."
        )
    weights = np.array([zmp_weight, jerk_weight], dtype=float)
    if not (np.all(np.isfinite(weights)) and np.all(weights > 0.0)):
        raise ConfigurationError(
            f"zmp_weight and jerk_weight must be positive, got {zmp_weight!r} and "
            f"{jerk_weight!r} (Kajita 2003: 1 and 1e-6)."
        )
    if int(nb_preview) < 1:
        raise ConfigurationError(f"nb_preview must be at least 1, got {nb_preview!r}.")
    A, B, C = model.A, model.B.reshape(3, 1), model.C.reshape(1, 3)
    if integral_action:
        A = np.block([[np.ones((1, 1)), C @ A], [np.zeros((3, 1)), A]])
        B = np.vstack([C @ B, B])
        Q = scipy.linalg.block_diag(zmp_weight, Qx)
    else:
        Q = zmp_weight * C.T @ C + Qx
    R = np.array([[jerk_weight]])
    try:
        P = scipy.linalg.solve_discrete_are(A, B, Q, R)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ConfigurationError(
            f"The preview controller's Riccati equation has no stabilising solution ({exc}); "
            "check the weights and the sampling period."
        ) from None
    M = 1.0 / (jerk_weight + (B.T @ P @ B).item())
    K = M * (B.T @ P @ A).ravel()
    closed_loop = A - B @ K.reshape(1, -1)
    Gd = np.empty(int(nb_preview))
    if integral_action:
        Gi, Gx = float(K[0]), K[1:]
        X = -closed_loop.T @ P[:, :1]
        Gd[0] = -Gi
        for j in range(1, len(Gd)):
            Gd[j] = M * (B.T @ X).item()
            X = closed_loop.T @ X
    else:
        Gi, Gx = 0.0, K
        X = zmp_weight * C.T
        for j in range(len(Gd)):
            Gd[j] = -M * (B.T @ X).item()
            X = closed_loop.T @ X
    return PreviewGains(Gi, Gx, Gd, P, closed_loop, bool(integral_action))


class PreviewGenerator(PatternGenerator):
    """Kajita's ZMP preview control following the schedule's ZMP reference.

    The reference is :meth:`ContactSchedule.zmp_reference` (paper M's
    polygonal ZMP), held at its last value after the schedule. A measured
    state replaces the internal one (position and velocity, and acceleration
    when given) before the control is computed. The jerk is recomputed every
    ``sampling_period`` and held in between; the state is integrated exactly.

    Args:
        lipm: Pendulum model.
        control_period: Output period, in [s].
        sampling_period: Controller period, in [s]; an integer multiple of
            ``control_period`` (default: equal to it).
        preview_time: Preview window, in [s].
        zmp_weight: ``Qe``.
        jerk_weight: ``R``.
        state_weight: ``Qx`` (scalar or 3x3).
        integral_action: Kajita's integral form, or the plain LQR with
            preview (the MPC equivalent).
        predict_horizon: Attach the previewed reference (``Horizon.zmp``) and
            the predicted closed-loop CoM (``Horizon.com``) to each output.
    """

    name = "preview"
    follows_new_footsteps = True

    def __init__(
        self,
        *,
        lipm: LIPM = LIPM(),
        control_period: float = 0.01,
        sampling_period: float | None = None,
        preview_time: float = 1.6,
        zmp_weight: float = 1.0,
        jerk_weight: float = 1e-6,
        state_weight=0.0,
        integral_action: bool = True,
        predict_horizon: bool = True,
    ) -> None:
        super().__init__(lipm=lipm, control_period=control_period)
        Ts = self.control_period if sampling_period is None else float(sampling_period)
        ratio = Ts / self.control_period if np.isfinite(Ts) and Ts > 0.0 else 0.0
        if ratio < 1.0 - 1e-9 or abs(ratio - round(ratio)) > 1e-9:
            raise ConfigurationError(
                f"sampling_period must be a positive integer multiple of control_period "
                f"({self.control_period:g} s), got {sampling_period!r}."
            )
        if not np.isfinite(preview_time) or preview_time < Ts:
            raise ConfigurationError(
                f"preview_time must be at least one sampling period ({Ts:g} s), got "
                f"{preview_time!r}; Kajita 2003 uses 1.6 s."
            )
        self.ticks_per_sample = int(round(ratio))
        self.model = CartTable(lipm, Ts)
        self.nb_preview = int(round(preview_time / Ts))
        self.gains = compute_preview_gains(
            self.model,
            self.nb_preview,
            zmp_weight=zmp_weight,
            jerk_weight=jerk_weight,
            state_weight=state_weight,
            integral_action=integral_action,
        )
        self.predict_horizon = predict_horizon
        self._tick_A, self._tick_B = CartTable.transition(self.control_period)
        self._prediction = self._prediction_map() if predict_horizon else None
        self.state = np.zeros((3, 2))
        self.error_sum = np.zeros(2)
        self.jerk = np.zeros(2)
        self._horizon: Horizon | None = None

    @property
    def Gi(self) -> float:
        """Integral gain (0 without integral action)."""
        return self.gains.Gi

    @property
    def Gx(self) -> np.ndarray:
        """State feedback gain, shape (3,)."""
        return self.gains.Gx

    @property
    def Gd(self) -> np.ndarray:
        """Preview gains, shape (N_L,)."""
        return self.gains.Gd

    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        self.state = initial_state.as_cart_table()
        self.error_sum = np.zeros(2)
        if self.gains.integral_action:
            # Bumpless start: the integrator starts as if the CoM had rested
            # above the initial reference r0, so the law does not depend on
            # where the world origin is (Kajita's sum starts at zero, which
            # adds a jerk -(Gx[0] + sum Gd) r0 at the first tick).
            r0 = schedule.zmp_reference(0.0)
            self.error_sum = -(self.gains.Gx[0] + self.gains.Gd.sum()) * r0 / self.gains.Gi
        self.jerk = np.zeros(2)
        self._horizon = None
        return self._output(0.0, self.state)

    def _step(self, measured: ComState | None) -> GeneratorOutput:
        if measured is not None:
            self.state = measured.as_cart_table(default_acceleration=self.state[2])
        if self.tick % self.ticks_per_sample == 0:
            self._control(self.time)
        self.state = self._tick_A @ self.state + np.outer(self._tick_B, self.jerk)
        return self._output(self.time + self.control_period, self.state, horizon=self._horizon)

    def _control(self, t: float) -> None:
        """Jerk of the sampling period starting at ``t``."""
        g, Ts = self.gains, self.model.sampling_period
        times = t + Ts * np.arange(self.nb_preview + 1)
        refs = self.current_schedule.zmp_reference(times)
        if g.integral_action:
            self.error_sum += self.model.C @ self.state - refs[0]
        self.jerk = -g.Gi * self.error_sum - g.Gx @ self.state - g.Gd @ refs[1:]
        if self._prediction is not None:
            x_next = self.model.A @ self.state + np.outer(self.model.B, self.jerk)
            stacked = np.vstack([x_next, self.error_sum[None], refs[1:]])
            com = np.einsum("ij,jk->ik", self._prediction, stacked)
            self._horizon = Horizon(times=times[1:], com=com, zmp=refs[1:])

    def _prediction_map(self) -> np.ndarray:
        """Linear map from ``[x[k+1], error sum[k], r[k+1..k+N_L]]`` to the
        predicted closed-loop CoM positions ``c[k+1..k+N_L]`` (reference held
        at ``r[k+N_L]`` past the window); shape (N_L, 4 + N_L)."""
        g, m, NL = self.gains, self.model, self.nb_preview
        n = 4 + NL
        x = np.zeros((3, n))
        x[:, :3] = np.eye(3)
        s = np.zeros(n)
        s[3] = 1.0
        out = np.zeros((NL, n))
        window = np.minimum(np.arange(NL)[:, None] + np.arange(1, NL + 1)[None], NL - 1)
        for j in range(NL):  # x holds x[k+1+j] as a function of the inputs
            out[j] = x[0]
            if j == NL - 1:
                break
            if g.integral_action:
                s = s + m.C @ x
                s[4 + j] -= 1.0
            u = -g.Gi * s - g.Gx @ x
            np.subtract.at(u, 4 + window[j], g.Gd)
            x = m.A @ x + np.outer(m.B, u)
        return out
