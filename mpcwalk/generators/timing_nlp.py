"""Optimal step timing: the next two landings and step durations as a nonlinear program.

The DCM-based formulation of Khadiv et al. (2016, 2020, "Walking control based on step
timing adaptation"), over two steps and with the ankle's centre of pressure: with the CoP
held at ``p`` in the stance sole (at ``u0``) the LIPM's DCM grows as
``xi(t) = p + (xi0 - p) exp(omega t)``, so after the time ``T1`` left in the current step and
the duration ``T2`` of the next one (its CoP at its landing ``u1``)::

    xi1 = p  + (xi0 - p)  exp(omega T1)            (at the landing on u1)
    xi2 = u1 + (xi1 - u1) exp(omega T2)            (at the landing on u2)

    minimise   w_u (|u1 - u1n|^2 + |u2 - u2n|^2) + w_t ((T1 - T1n)^2 + (T2 - Tn)^2)
               + w_b (|xi1 - u1 - b1n|^2 + |xi2 - u2 - b2n|^2) + w_p |p - u0|^2
    subject to R0^T (u1 - u0) in reach of step 1, R1^T (u2 - u1) in reach of step 2,
               R0^T (p - u0) in the sole, T1 in [T1min, T1max], T2 in [T2min, T2max],
               u1 in the late adjustment's box about its published landing

with ``b1n``, ``b2n`` the nominal DCM offsets of the plan (:func:`nominal_offsets`). The
durations enter through ``exp(omega T)`` and multiply the positions: the program is
nonlinear (Khadiv's change of variable ``sigma = exp(omega T)`` makes the one-step problem a
QP; two steps and the CoP keep products of variables). It has 8 variables and 6 rows; it is
built once as a CasADi ``nlpsol`` function and solved by IPOPT (shipped in CasADi's wheel),
with the adaptive barrier, warm-started from the last solution and its multipliers. The cost
is scaled by ``1e4`` (positions in cm) so that IPOPT's tolerance means something. CasADi's
``sqpmethod`` with ``qrqp`` or ``osqp`` was tried: it stopped without convergence on a 3 cm
push (eigen-clip or regularised Hessian), so it is not offered.
"""

from dataclasses import dataclass
from typing import Any

import numpy as np

from mpcwalk.exceptions import ConfigurationError

_COST_SCALE = 1e4  # [1/m^2 -> 1/cm^2]
_IPOPT: dict[str, Any] = {"print_level": 0, "sb": "yes", "tol": 1e-8, "mu_strategy": "adaptive"}
_WARM: dict[
    str, Any
] = {  # start at the given point and multipliers, barely pushed inside the bounds
    "warm_start_init_point": "yes",
    "mu_init": 1e-3,
    "warm_start_bound_push": 1e-9,
    "warm_start_bound_frac": 1e-9,
    "warm_start_slack_bound_push": 1e-9,
    "warm_start_slack_bound_frac": 1e-9,
    "warm_start_mult_bound_push": 1e-9,
}


@dataclass(frozen=True)
class TimingWeights:
    """Weights of the step-timing program.

    Attributes:
        footstep: Landing distance to the plan's, in [1/m^2].
        duration: Duration distance to the plan's, in [1/s^2].
        offset: DCM offset distance to the plan's, in [1/m^2].
        cop: Centre of pressure distance to the stance sole's centre, in [1/m^2].
    """

    footstep: float = 1.0
    duration: float = 0.1
    offset: float = 10.0
    cop: float = 1.0


@dataclass(frozen=True)
class TimingProblem:
    """The data of one solve (world frame, positions in [m], times in [s]).

    Attributes:
        dcm: DCM now ``xi0``, shape (2,).
        stance: Stance sole centre ``u0``, (2,); ``stance_yaw`` its yaw [rad].
        nominal: Planned landings ``u1n``, ``u2n``, shape (2, 2).
        offsets: Nominal DCM offsets ``b1n``, ``b2n``, shape (2, 2).
        durations: Nominal ``T1n`` (time left) and ``Tn`` (next step), (2,).
        duration_bounds: ``[[T1min, T1max], [T2min, T2max]]``, shape (2, 2).
        reach: Bounds of step 1 (from ``u0``, in its frame) and step 2 (from ``u1``, in the
            frame of ``landing_yaw``): ``[[lo1, hi1], [lo2, hi2]]``, shape (2, 2, 2).
        landing_yaw: Yaw of the first landing [rad] (the frame of step 2's reach).
        half_sole: Half length and width of the sole, (2,).
        box: ``[lower, upper]`` of the first landing (world), shape (2, 2) (inf: none).
    """

    dcm: np.ndarray
    stance: np.ndarray
    stance_yaw: float
    nominal: np.ndarray
    offsets: np.ndarray
    durations: np.ndarray
    duration_bounds: np.ndarray
    reach: np.ndarray
    landing_yaw: float
    half_sole: np.ndarray
    box: np.ndarray


@dataclass(frozen=True)
class TimingSolution:
    """A solution of the step-timing program.

    Attributes:
        success: Whether the solver converged.
        durations: ``T1`` (time left in the step) and ``T2`` [s], shape (2,).
        landings: ``u1``, ``u2`` [m], shape (2, 2).
        cop: Centre of pressure ``p`` [m], shape (2,).
        dcm: DCM at the two landings ``xi1``, ``xi2`` [m], shape (2, 2).
        iterations: Iterations of the solver.
    """

    success: bool
    durations: np.ndarray
    landings: np.ndarray
    cop: np.ndarray
    dcm: np.ndarray
    iterations: int


def nominal_offsets(landings: np.ndarray, final: np.ndarray, omega: float, T: float):
    """Nominal DCM offsets ``b_i = xi_i - u_i`` at each landing of a plan that ends with the
    DCM at ``final`` [m] (the feet's midpoint), the CoP at each stance sole for ``T`` [s]:
    backwards, ``b_i = (b_(i+1) + u_(i+1) - u_i) exp(-omega T)`` with ``b_last = final -
    u_last``. ``landings``: shape (n, 2); returns shape (n, 2)."""
    u = np.asarray(landings, dtype=float)
    b = np.zeros_like(u)
    decay = np.exp(-omega * T)
    if len(u):
        b[-1] = np.asarray(final, dtype=float) - u[-1]
        for i in range(len(u) - 2, -1, -1):
            b[i] = (b[i + 1] + u[i + 1] - u[i]) * decay
    return b


class TimingNLP:
    """The step-timing program, built once, solved with a warm start.

    Args:
        omega: The LIPM's natural frequency [1/s].
        weights: Cost weights.

    Raises:
        ConfigurationError: A non-positive ``omega``.
    """

    def __init__(self, omega: float, weights: TimingWeights | None = None) -> None:
        import casadi as ca

        if not (np.isfinite(omega) and omega > 0.0):
            raise ConfigurationError(f"omega must be a positive frequency [1/s], got {omega!r}.")
        self.omega = float(omega)
        self.weights = w = weights or TimingWeights()
        x = ca.SX.sym("x", 8)  # T1, T2, u1 (2), u2 (2), p (2)
        P = ca.SX.sym("p", 16)  # xi0, u0, u1n, u2n, b1n, b2n, T1n, Tn, yaw0, yaw1
        T1, T2, u1, u2, p = x[0], x[1], x[2:4], x[4:6], x[6:8]
        xi0, u0, u1n, u2n, b1n, b2n = (P[2 * i : 2 * i + 2] for i in range(6))
        T1n, Tn, yaw0, yaw1 = P[12], P[13], P[14], P[15]
        xi1 = p + (xi0 - p) * ca.exp(omega * T1)
        xi2 = u1 + (xi1 - u1) * ca.exp(omega * T2)
        cost = _COST_SCALE * (
            w.footstep * (ca.sumsqr(u1 - u1n) + ca.sumsqr(u2 - u2n))
            + w.duration * ((T1 - T1n) ** 2 + (T2 - Tn) ** 2)
            + w.offset * (ca.sumsqr(xi1 - u1 - b1n) + ca.sumsqr(xi2 - u2 - b2n))
            + w.cop * ca.sumsqr(p - u0)
        )

        def local(yaw, v):  # R(yaw)^T v
            return ca.vertcat(
                ca.cos(yaw) * v[0] + ca.sin(yaw) * v[1], -ca.sin(yaw) * v[0] + ca.cos(yaw) * v[1]
            )

        g = ca.vertcat(local(yaw0, u1 - u0), local(yaw1, u2 - u1), local(yaw0, p - u0))
        nlp = {"x": x, "p": P, "f": cost, "g": g}
        cold_options: dict[str, Any] = {"print_time": False, "ipopt": _IPOPT}
        warm_options: dict[str, Any] = {"print_time": False, "ipopt": {**_IPOPT, **_WARM}}
        self._cold = ca.nlpsol("step_timing", "ipopt", nlp, cold_options)
        self._warm_solver = ca.nlpsol("step_timing_warm", "ipopt", nlp, warm_options)
        self._dcm = ca.Function("dcm", [x, P], [ca.horzcat(xi1, xi2).T])
        self._warm: dict | None = None

    def reset(self) -> None:
        """Forget the warm start."""
        self._warm = None

    def solve(self, problem: TimingProblem, *, warm: bool = True) -> TimingSolution:
        """Solve ``problem``, from the last solution when ``warm`` (and there is one)."""
        q = problem
        params = np.concatenate(
            [
                q.dcm,
                q.stance,
                q.nominal.ravel(),
                q.offsets.ravel(),
                q.durations,
                [q.stance_yaw, q.landing_yaw],
            ]
        )
        lbx = np.concatenate([q.duration_bounds[:, 0], q.box[0], [-np.inf] * 4])
        ubx = np.concatenate([q.duration_bounds[:, 1], q.box[1], [np.inf] * 4])
        lbg = np.concatenate([q.reach[0, 0], q.reach[1, 0], -q.half_sole])
        ubg = np.concatenate([q.reach[0, 1], q.reach[1, 1], q.half_sole])
        args = {"p": params, "lbx": lbx, "ubx": ubx, "lbg": lbg, "ubg": ubg}
        solver = self._cold
        if warm and self._warm is not None:
            args.update(self._warm)
            solver = self._warm_solver
        else:
            args["x0"] = np.concatenate([q.durations, q.nominal.ravel(), q.stance])
        args["x0"] = np.clip(np.asarray(args["x0"], dtype=float).ravel(), lbx, ubx)
        out = solver(**args)
        stats = solver.stats()
        x = np.asarray(out["x"], dtype=float).ravel()
        success = bool(stats.get("success", False)) and bool(np.all(np.isfinite(x)))
        if success:
            self._warm = {"x0": x, "lam_x0": out["lam_x"], "lam_g0": out["lam_g"]}
        return TimingSolution(
            success=success,
            durations=x[:2].copy(),
            landings=x[2:6].reshape(2, 2).copy(),
            cop=x[6:8].copy(),
            dcm=np.asarray(self._dcm(x, params), dtype=float),
            iterations=int(stats.get("iter_count", -1)),
        )
