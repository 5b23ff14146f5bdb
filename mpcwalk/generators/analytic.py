"""Paper M's closed-form CoM: a boundary value problem per step (eq. 6-18).

For each step ``k`` of duration ``T`` the ZMP follows the polygonal reference
of eq. 6-8 (from the torso waypoint ``x_t[k]`` to the support foot ``x_s[k]``
during ``[0, t_b)``, held until ``t_e``, then on to ``x_t[k+1]``), and the CoM
is the LIPM solution that meets ``c(0) = x_t[k]`` and ``c(T) = x_t[k+1]``
(eq. 9). The x and y axes are solved independently.

Only positions are imposed at the step boundaries, so the CoM *velocity*
jumps from one step to the next (and from rest into the first step): each step
is a separate boundary value problem, as in the paper. Position and
acceleration stay continuous (at a boundary ``c = p`` so ``c_ddot = 0``). This
generator is the paper's baseline and keeps that behaviour on purpose.
"""

from dataclasses import dataclass
from typing import List, Optional

import numpy as np

from ..exceptions import ConfigurationError
from ..gait.contact_schedule import ContactSchedule
from ..models.lipm import LIPM
from .pattern_generator import ComState, GeneratorOutput, Horizon, PatternGenerator


def _sinh_over(x: float) -> float:
    """``sinh(x) / x`` with its limit 1 at 0."""
    return 1.0 if x == 0.0 else float(np.sinh(x) / x)


@dataclass(frozen=True)
class ClosedFormStep:
    """Closed-form CoM and ZMP of one step (paper M eq. 6-18).

    Boundary values may be scalars or arrays of any common shape ``s`` (e.g.
    (2,) for x and y); evaluations at times of shape ``n`` return arrays of
    shape ``n + s``. Times are relative to the start of the step, in [s]; the
    formulas are meant for ``[0, T]`` (outside, the first and last pieces
    extend).

    Attributes:
        x_t0: Torso waypoint ``x_t[k]`` at the step start, in [m].
        x_s: Support foot position ``x_s[k]``, in [m].
        x_t1: Torso waypoint ``x_t[k+1]`` at the step end, in [m].
        T: Step duration, in [s].
        t_b: Start of single support, in [s].
        t_e: End of single support, in [s].
        omega: LIPM natural frequency, in [1/s].
        m_d1: ZMP slope on ``[0, t_b)`` (eq. 6), in [m]/[s].
        m_d2: ZMP slope on ``[t_e, T]`` (eq. 7), in [m]/[s].
        k_d1: Eq. 15, in [m].
        k_d2: Eq. 16, in [m].
        C1: Coefficient of ``e^{omega t}`` (eq. 17), in [m].
        C2: Coefficient of ``e^{-omega t}`` (eq. 18), in [m].
    """

    x_t0: np.ndarray
    x_s: np.ndarray
    x_t1: np.ndarray
    T: float
    t_b: float
    t_e: float
    omega: float
    m_d1: np.ndarray
    m_d2: np.ndarray
    k_d1: np.ndarray
    k_d2: np.ndarray
    C1: np.ndarray
    C2: np.ndarray

    def _pieces(self, times):
        t = np.asarray(times, dtype=float)
        tt = t.reshape(t.shape + (1,) * np.ndim(self.x_t0))
        return tt, tt < self.t_b, tt >= self.t_e

    def zmp(self, times) -> np.ndarray:
        """ZMP reference ``p(t)`` (eq. 8), in [m]."""
        tt, first, last = self._pieces(times)
        p = np.where(first, self.x_t0 + self.m_d1 * tt, self.x_s)
        return np.where(last, self.x_s + self.m_d2 * (tt - self.t_e), p)

    def _homogeneous(self, tt, order: int):
        """``d^order/dt^order`` of ``C1 e^{wt} + C2 e^{-wt}``, overflow-free."""
        w, T = self.omega, self.T
        e1 = np.exp(-w * T)
        C1_at_T = (self.k_d2 - self.k_d1 * e1) / (1.0 - e1 * e1)  # C1 e^{wT}
        grow = C1_at_T * np.exp(w * (tt - T))
        decay = self.C2 * np.exp(-w * tt)
        return w**order * (grow + (-1) ** order * decay)

    def _c2(self, tt, first, last, order: int):
        """``d^order/dt^order`` of eq. 13."""
        w = self.omega
        f = (np.sinh, np.cosh)[order % 2]
        a = -(self.m_d1 / w) * w**order * f(w * (tt - self.t_b))
        b = -(self.m_d2 / w) * w**order * f(w * (tt - self.t_e))
        return np.where(first, a, 0.0) + np.where(last, b, 0.0)

    def com(self, times) -> np.ndarray:
        """CoM position ``c(t) = p + C1 e^{wt} + C2 e^{-wt} + c2`` (eq. 11-13), in [m]."""
        tt, first, last = self._pieces(times)
        return self.zmp(times) + self._homogeneous(tt, 0) + self._c2(tt, first, last, 0)

    def com_velocity(self, times) -> np.ndarray:
        """Analytic ``c_dot(t)``, in [m]/[s]."""
        tt, first, last = self._pieces(times)
        p_dot = np.where(first, self.m_d1, 0.0) + np.where(last, self.m_d2, 0.0)
        return p_dot + self._homogeneous(tt, 1) + self._c2(tt, first, last, 1)

    def com_acceleration(self, times) -> np.ndarray:
        """Analytic ``c_ddot(t)`` (the ZMP is piecewise linear), in [m]/[s]^2."""
        tt, first, last = self._pieces(times)
        return self._homogeneous(tt, 2) + self._c2(tt, first, last, 2)

    def state(self, times) -> np.ndarray:
        """Position, velocity and acceleration stacked on a new axis 1, in SI units.

        Returns:
            Shape ``n + (3,) + s``, e.g. (n, 3, 2) for times (n,) and 2D
            boundary values.
        """
        return np.stack(
            [self.com(times), self.com_velocity(times), self.com_acceleration(times)],
            axis=np.ndim(times),
        )


def closed_form_step(x_t0, x_s, x_t1, T: float, t_b: float, t_e: float,
                     omega: float) -> ClosedFormStep:
    """Solve paper M's boundary value problem for one step (eq. 6-18).

    ``t_b = 0`` (or ``t_e = T``) is the no-double-support limit: the ZMP then
    jumps to the support foot at the step start (or leaves it at the end) and
    eq. 15 (16) is replaced by its finite limit ``k_d1 = x_t0 - x_s``
    (``k_d2 = x_t1 - x_s``).

    Args:
        x_t0: Torso waypoint at the step start ``x_t[k]``, scalar or array, in [m].
        x_s: Support foot position ``x_s[k]``, same shape, in [m].
        x_t1: Torso waypoint at the step end ``x_t[k+1]``, same shape, in [m].
        T: Step duration, in [s].
        t_b: Single support begin, ``0 <= t_b <= t_e``, in [s].
        t_e: Single support end, ``t_e <= T``, in [s].
        omega: ``sqrt(g / z_c)``, in [1/s].

    Returns:
        The closed form, to evaluate at any times.

    Raises:
        ConfigurationError: on non-finite values, ``T <= 0``, ``omega <= 0``
            or times out of order.
    """
    try:
        x_t0, x_s, x_t1 = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x_t0, x_s, x_t1)))
        T, t_b, t_e, omega = (float(v) for v in (T, t_b, t_e, omega))
    except (TypeError, ValueError) as exc:
        raise ConfigurationError(
            f"closed_form_step expects numbers or arrays of one shape for x_t0, x_s, "
            f"x_t1 and numbers for T, t_b, t_e, omega ({exc})."
        ) from None
    if not all(np.all(np.isfinite(v)) for v in (x_t0, x_s, x_t1, T, t_b, t_e, omega)):
        raise ConfigurationError("closed_form_step got a non-finite input; pass finite numbers.")
    if T <= 0.0 or omega <= 0.0:
        raise ConfigurationError(
            f"closed_form_step needs T > 0 and omega > 0, got T={T!r}, omega={omega!r}."
        )
    if not 0.0 <= t_b <= t_e <= T:
        raise ConfigurationError(
            f"closed_form_step needs 0 <= t_b <= t_e <= T, got t_b={t_b!r}, t_e={t_e!r}, "
            f"T={T!r}; use t_b = r_ds T / 2 and t_e = T - r_ds T / 2 with r_ds in [0, 1)."
        )
    w, ds_end = omega, T - t_e
    m_d1 = (x_s - x_t0) / t_b if t_b > 0.0 else np.zeros_like(x_s)          # eq. 6
    m_d2 = (x_t1 - x_s) / ds_end if ds_end > 0.0 else np.zeros_like(x_s)    # eq. 7
    # eq. 15-16 written as slope * duration * sinh(w d)/(w d): finite as d -> 0.
    k_d1 = -(x_s - x_t0) * _sinh_over(w * t_b)
    k_d2 = (x_t1 - x_s) * _sinh_over(w * ds_end)
    # eq. 17-18 divided through by e^{wT} (no overflow for long steps).
    e1, e2 = np.exp(-w * T), np.exp(-2.0 * w * T)
    C1 = (k_d2 * e1 - k_d1 * e2) / (1.0 - e2)
    C2 = (k_d1 - k_d2 * e1) / (1.0 - e2)
    return ClosedFormStep(x_t0, x_s, x_t1, T, t_b, t_e, w, m_d1, m_d2, k_d1, k_d2, C1, C2)


class AnalyticGenerator(PatternGenerator):
    """Paper M's closed-form CoM, step by step, open loop.

    Before the first step and after the last one the CoM rests above the
    midpoint of the feet (``x_t[0]``, ``x_t[N]``); ``initial_state`` and the
    measured state are ignored (the boundary conditions are the paper's).

    Args:
        lipm: Pendulum model (CoM height, gravity).
        control_period: Output period, in [s].
        horizon_time: Length of :attr:`GeneratorOutput.horizon`, in [s];
            None: the rest of the current step (what the paper plans at once;
            no horizon while standing); 0: no horizon.
    """

    name = "analytic"

    def __init__(self, *, lipm: LIPM = LIPM(), control_period: float = 0.01,
                 horizon_time: Optional[float] = None) -> None:
        super().__init__(lipm=lipm, control_period=control_period)
        if horizon_time is not None and (not np.isfinite(horizon_time) or horizon_time < 0.0):
            raise ConfigurationError(
                f"horizon_time must be None or a non-negative number of seconds, got "
                f"{horizon_time!r}."
            )
        self.horizon_time = horizon_time
        self.steps: List[ClosedFormStep] = []

    def _reset(self, schedule: ContactSchedule, initial_state: ComState) -> GeneratorOutput:
        xt, xs = schedule.torso_waypoints, schedule.support_positions
        self.steps = [
            closed_form_step(xt[k], xs[k], xt[k + 1], schedule.step_duration,
                             schedule.t_b, schedule.t_e, self.lipm.omega)
            for k in range(schedule.plan.nb_steps)
        ]
        return self._make_output(0.0)

    def _step(self, measured: Optional[ComState]) -> GeneratorOutput:
        return self._make_output((self.tick + 1) * self.control_period)

    def evaluate(self, times) -> np.ndarray:
        """CoM state of the whole walk at any times.

        Args:
            times: Shape (n,), in [s] since the start of the schedule.

        Returns:
            Shape (n, 3, 2): position [m], velocity [m]/[s] and acceleration
            [m]/[s]^2 of the CoM (x, y) at each time.
        """
        sched = self.schedule
        t = np.atleast_1d(np.asarray(times, dtype=float))
        out = np.zeros((len(t), 3, 2))
        N, T = len(self.steps), sched.step_duration
        k = np.floor((t - sched.walk_start) / T).astype(int)
        out[:, 0] = sched.torso_waypoints[np.clip(k, 0, N)]
        out[k >= N, 0] = sched.torso_waypoints[N]
        for i in np.unique(k[(k >= 0) & (k < N)]):
            sel = k == i
            out[sel] = self.steps[i].state(t[sel] - sched.walk_start - i * T)
        return out

    def _make_output(self, t: float) -> GeneratorOutput:
        state = self.evaluate([t])[0]
        return self._output(t, state, horizon=self._horizon(t))

    def _horizon(self, t: float) -> Optional[Horizon]:
        sched = self.schedule
        if self.horizon_time is None:
            k = sched.step_index(t)
            if not 0 <= k < len(self.steps):
                return None
            end = sched.walk_start + (k + 1) * sched.step_duration
        else:
            end = t + self.horizon_time
        n = int(np.floor((end - t) / self.control_period + 1e-9))
        if n < 1:
            return None
        times = t + self.control_period * np.arange(1, n + 1)
        states = self.evaluate(times)
        zmp = states[:, 0] - states[:, 2] / self.lipm.omega**2
        return Horizon(times=times, com=states[:, 0], zmp=zmp)
