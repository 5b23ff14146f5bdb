"""Paper M's closed form of one step: the ZMP's polygon and the CoM that meets the torso
waypoints at both ends of the step (eq. 6-18), to evaluate at any times.
:class:`~mpcwalk.generators.analytic.AnalyticGenerator` chains one per step.
"""

import math
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError


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
    extend). The evaluation sums the large terms of the double-support pieces
    analytically, so it stays accurate for long double supports (see
    :meth:`_free`).

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
        first = (tt < self.t_b) & (self.t_b > 0.0)
        last = (tt >= self.t_e) & (self.t_e < self.T)
        return tt, first, last

    def zmp(self, times) -> np.ndarray:
        """ZMP reference ``p(t)`` (eq. 8), in [m]."""
        tt, first, last = self._pieces(times)
        p = np.where(first, self.x_t0 + self.m_d1 * tt, self.x_s)
        return np.where(last, self.x_s + self.m_d2 * (tt - self.t_e), p)

    def _free(self, times, order: int) -> np.ndarray:
        """``d^order/dt^order`` of ``c - p = C1 e^{wt} + C2 e^{-wt} + c2(t)``.

        Evaluated without cancellation: in the double-support pieces the
        large terms ``k_d1 e^{-wt}`` (resp. ``k_d2 e^{w(t-T)}``) of the
        homogeneous part and ``c2`` are summed analytically, e.g. on
        ``[0, t_b)``: ``k_d1 e^{-wt} + c2 = -(m_d1 / 2w) (e^{w(t-t_b)} -
        e^{-w(t+t_b)})``. Same function as eq. 11-13, accurate for long
        double supports (``omega t_b >> 1``) too.
        """
        tt, first, last = self._pieces(times)
        w, T, n = self.omega, self.T, order
        sign = (-1.0) ** n
        e1 = np.exp(-w * T)
        den = 1.0 - e1 * e1
        kd1_decay = self.k_d1 * np.exp(-w * tt)  # k_d1 e^{-wt}
        kd2_grow = self.k_d2 * np.exp(w * (tt - T))  # k_d2 e^{w(t-T)}
        grow_rest = -self.k_d1 * np.exp(w * (tt - 2.0 * T)) / den
        decay_rest = -self.k_d2 * np.exp(-w * (tt + T)) / den
        # C1 e^{wt} = grow and C2 e^{-wt} = decay (eq. 17-18 divided by e^{wT}).
        grow = kd2_grow / den + grow_rest
        decay = kd1_decay / den + decay_rest
        first_part = -(self.m_d1 / (2.0 * w)) * (
            np.exp(w * (tt - self.t_b)) - sign * np.exp(-w * (tt + self.t_b))
        )
        last_part = (self.m_d2 / (2.0 * w)) * (
            sign * np.exp(-w * (tt - self.t_e)) - np.exp(w * (tt + self.t_e - 2.0 * T))
        )
        mid = grow + sign * decay
        on_first = grow + sign * (kd1_decay * e1 * e1 / den + decay_rest) + first_part
        on_last = (kd2_grow * e1 * e1 / den + grow_rest) + sign * decay + last_part
        return w**n * np.where(first, on_first, np.where(last, on_last, mid))

    def com(self, times) -> np.ndarray:
        """CoM position ``c(t) = p + C1 e^{wt} + C2 e^{-wt} + c2`` (eq. 11-13), in [m]."""
        return self.zmp(times) + self._free(times, 0)

    def com_velocity(self, times) -> np.ndarray:
        """Analytic ``c_dot(t)``, in [m]/[s]."""
        _, first, last = self._pieces(times)
        p_dot = np.where(first, self.m_d1, 0.0) + np.where(last, self.m_d2, 0.0)
        return p_dot + self._free(times, 1)

    def com_acceleration(self, times) -> np.ndarray:
        """Analytic ``c_ddot(t)`` (the ZMP is piecewise linear), in [m]/[s]^2."""
        return self._free(times, 2)

    def state_at(self, t: float) -> np.ndarray:
        """Position, velocity and acceleration at one time, shape ``(3,) + s``.

        Same formulas as :meth:`state` (see :meth:`_free`) on a scalar time:
        the per-tick path of the generator, without array dispatch overhead.
        """
        t = float(t)
        w, T = self.omega, self.T
        first = t < self.t_b and self.t_b > 0.0
        last = (not first) and t >= self.t_e and self.t_e < self.T
        e1 = math.exp(-w * T)
        den = 1.0 - e1 * e1
        kd1_decay = self.k_d1 * math.exp(-w * t)
        kd2_grow = self.k_d2 * math.exp(w * (t - T))
        grow_rest = -self.k_d1 * (math.exp(w * (t - 2.0 * T)) / den)
        decay_rest = -self.k_d2 * (math.exp(-w * (t + T)) / den)
        grow = kd2_grow / den + grow_rest
        decay = kd1_decay / den + decay_rest
        out = []
        for n in range(3):
            sign = -1.0 if n % 2 else 1.0
            if first:
                part = -(self.m_d1 / (2.0 * w)) * (
                    math.exp(w * (t - self.t_b)) - sign * math.exp(-w * (t + self.t_b))
                )
                val = grow + sign * (kd1_decay * (e1 * e1 / den) + decay_rest) + part
            elif last:
                part = (self.m_d2 / (2.0 * w)) * (
                    sign * math.exp(-w * (t - self.t_e)) - math.exp(w * (t + self.t_e - 2.0 * T))
                )
                val = (kd2_grow * (e1 * e1 / den) + grow_rest) + sign * decay + part
            else:
                val = grow + sign * decay
            out.append(w**n * val)
        zmp: np.ndarray
        zmp_rate: np.ndarray | float
        if first:
            zmp, zmp_rate = self.x_t0 + self.m_d1 * t, self.m_d1
        elif last:
            zmp, zmp_rate = self.x_s + self.m_d2 * (t - self.t_e), self.m_d2
        else:
            zmp, zmp_rate = self.x_s, 0.0
        return np.stack([zmp + out[0], zmp_rate + out[1], out[2]])

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


def closed_form_step(
    x_t0, x_s, x_t1, T: float, t_b: float, t_e: float, omega: float
) -> ClosedFormStep:
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
        x_t0, x_s, x_t1 = (
            np.array(v)
            for v in np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x_t0, x_s, x_t1)))
        )
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
    m_d1 = (x_s - x_t0) / t_b if t_b > 0.0 else np.zeros_like(x_s)  # eq. 6
    m_d2 = (x_t1 - x_s) / ds_end if ds_end > 0.0 else np.zeros_like(x_s)  # eq. 7
    # eq. 15-16 written as slope * duration * sinh(w d)/(w d): finite as d -> 0.
    k_d1 = -(x_s - x_t0) * _sinh_over(w * t_b)
    k_d2 = (x_t1 - x_s) * _sinh_over(w * ds_end)
    # eq. 17-18 divided through by e^{wT} (no overflow for long steps).
    e1, e2 = np.exp(-w * T), np.exp(-2.0 * w * T)
    C1 = (k_d2 * e1 - k_d1 * e2) / (1.0 - e2)
    C2 = (k_d1 - k_d2 * e1) / (1.0 - e2)
    return ClosedFormStep(x_t0, x_s, x_t1, T, t_b, t_e, w, m_d1, m_d2, k_d1, k_d2, C1, C2)
