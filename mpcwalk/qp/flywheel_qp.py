"""The footstep-adaptive walking QP with a flywheel: the hip strategy (Pratt et al. 2006).

:class:`~mpcwalk.qp.footstep_qp.FootstepQP` plans the CoM (jerks) and the next footsteps;
its ZMP rows constrain ``c - c_ddot / omega^2``, which with a flywheel is the centroidal
moment pivot (CMP, :mod:`mpcwalk.models.flywheel`). This QP adds, per CoM axis, the torque
``tau_a`` the upper body applies (the rate of the flywheel momentum ``k_a``) over the first
``samples`` intervals of the horizon, held over each interval::

    x = [U_x (N), U_y (N), F_x (nf), F_y (nf), T_x (M), T_y (M)]

    ZMP  p_i = c_i - c_ddot_i / omega^2 - tau_i / (m g)    in its support (the CMP may leave it)
    |tau_i| <= tau_max,   |k_i| <= k_max,   |phi_i| <= phi_max
    cost += torque_weight ||tau / tau_max||^2 + momentum_weight ||k / k_max||^2
            + angle_weight ||phi / phi_max||^2            (every sample)

The cost of :class:`FootstepQP` still pulls the CMP to the centre of the support, so an
undisturbed walk leaves the flywheel at rest: the torque is only used when the ZMP rows would
otherwise bind, and the momentum and lean costs bring the upper body back upright. The
momentum and the lean are affine in the torques (exact integration,
:func:`~mpcwalk.models.flywheel.flywheel_transition`); after the ``M`` torques the momentum
is constant, so its bound is checked at the first ``M`` samples and the lean's at those and
the last one. Dense and rebuilt every tick, as the footstep QP; what the flywheel adds
depends on the first interval of the horizon alone (its cost block, its bound rows and their
factor), so it is built once per first interval (the sample grid does not slide: a walk meets
a handful).
"""

import dataclasses
from dataclasses import dataclass

import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.models.flywheel import FlywheelLimits
from mpcwalk.models.lipm import LIPM
from mpcwalk.qp.cost_factor import inverse_cholesky
from mpcwalk.qp.footstep_parameters import FootstepMpcParameters
from mpcwalk.qp.footstep_qp import FootstepQP
from mpcwalk.qp.footstep_supports import SampleSupports, StepVariables
from mpcwalk.qp.program import Prediction


@dataclass(frozen=True)
class FlywheelParameters:
    """The flywheel's share of the hip-strategy MPC.

    Attributes:
        samples: Intervals ``M`` of the horizon with a torque variable (the flywheel acts
            early: beyond this the torque is zero).
        torque_weight: Cost of the torque per sample, relative to its limit (unitless).
        momentum_weight: Cost of the momentum per sample, relative to its limit.
        angle_weight: Cost of the lean per sample, relative to its limit (it brings the
            upper body back upright).
    """

    samples: int = 12  # [] 0.6 s at 0.05 s
    torque_weight: float = 0.05
    momentum_weight: float = 0.05
    angle_weight: float = 0.2

    def __post_init__(self) -> None:
        if isinstance(self.samples, bool) or int(self.samples) != self.samples or self.samples < 1:
            raise ConfigurationError(
                f"FlywheelParameters.samples must be a positive integer, got {self.samples!r}."
            )
        object.__setattr__(self, "samples", int(self.samples))
        for name in ("torque_weight", "momentum_weight", "angle_weight"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value > 0.0):
                raise ConfigurationError(
                    f"FlywheelParameters.{name} must be a positive number, got {value!r}."
                )

    def replace(self, **changes) -> "FlywheelParameters":
        """Copy with some fields changed."""
        return dataclasses.replace(self, **changes)


class FlywheelFootstepQP(FootstepQP):
    """:class:`FootstepQP` plus the upper body's torque per axis (the flywheel).

    Set :attr:`flywheel_state` (the lean [rad] and momentum [kg m^2/s] per CoM axis, shape
    (2, 2): rows ``phi``, ``k``; columns x, y) before each :meth:`update`.

    Args:
        lipm: Pendulum model.
        parameters: Horizon and weights of the footstep MPC.
        nb_footsteps: Number of footstep variables.
        limits: The upper body's limits (:class:`~mpcwalk.models.flywheel.FlywheelLimits`).
        flywheel: Torque horizon and weights.
    """

    def __init__(
        self,
        lipm: LIPM,
        parameters: FootstepMpcParameters,
        nb_footsteps: int,
        limits: FlywheelLimits,
        flywheel: FlywheelParameters = FlywheelParameters(),
    ) -> None:
        super().__init__(lipm, parameters, nb_footsteps)
        if not isinstance(limits, FlywheelLimits):
            raise ConfigurationError(
                f"limits must be a FlywheelLimits, got {type(limits).__name__}."
            )
        self.limits, self.flywheel = limits, flywheel
        self.M = min(flywheel.samples, self.N)
        self.n_base = self.n
        self.n = self.n_base + 2 * self.M
        self.flywheel_state = np.zeros((2, 2))
        self._state_at_update = np.zeros((2, 2))
        self._fly: dict | None = None  # the lean and momentum maps of the last update
        self._blocks: dict[int, dict] = {}  # what the flywheel adds, per first interval
        self._now: dict = {}  # the blocks of the last update

    def _flywheel_maps(self, first: float) -> dict:
        """Lean and momentum at the samples as ``free (N,) + map (N, M) tau`` per unit state
        (``phi0``, ``k0`` columns of ``*_state`` (N, 2)), for a first interval of ``first``
        [s] and one inertia per axis."""
        N, M, Ts = self.N, self.M, self.parameters.sampling_period
        lengths = np.full(N, Ts)
        lengths[0] = first
        ends = np.cumsum(lengths)
        maps = []
        for inertia in self.limits.inertia:
            k_map = np.zeros((N, M))
            phi_map = np.zeros((N, M))
            for j in range(M):
                k_map[j:, j] = lengths[j]
                phi_map[j, j] = 0.5 * lengths[j] ** 2 / inertia
                phi_map[j + 1 :, j] = (
                    0.5 * lengths[j] ** 2 + lengths[j] * (ends[j + 1 :] - ends[j])
                ) / inertia
            state_phi = np.stack([np.ones(N), ends / inertia], axis=1)  # phi0, k0
            maps.append({"k": k_map, "phi": phi_map, "phi_state": state_phi})
        return {"first": first, "axes": maps}

    def _flywheel_blocks(self, first: float) -> dict:
        """What the flywheel adds to the QP for a first interval of ``first`` [s], built
        once per first interval (the sample grid does not slide, so a walk meets a few):
        its maps, its cost block (before the cost's scale) and the matrices that turn the
        lean and momentum without torques into its linear cost, its bound rows (the
        torque, the momentum at the first ``M`` samples, the lean there and at the last
        sample; rows ``+``, then ``-``, per axis) and their bounds."""
        key = round(first * 1e9)
        blocks = self._blocks.get(key)
        if blocks is not None:
            return blocks
        N, M, fw, limits = self.N, self.M, self.flywheel, self.limits
        maps = self._flywheel_maps(first)
        lean_rows = np.append(np.arange(M), N - 1)
        P = np.zeros((2 * M, 2 * M))
        q_k, q_phi, bounds, rows = [], [], [], []
        for a, axis in enumerate(maps["axes"]):
            tau_max, k_max, phi_max = (
                limits.max_torque[a],
                limits.max_momentum[a],
                limits.max_angle[a],
            )
            scale_t, scale_k, scale_p = (
                1.0 / v if v > 0.0 else 1.0 for v in (tau_max, k_max, phi_max)
            )
            H = (
                fw.torque_weight * scale_t**2 * np.eye(M)
                + fw.momentum_weight * scale_k**2 * axis["k"].T @ axis["k"]
                + fw.angle_weight * scale_p**2 * axis["phi"].T @ axis["phi"]
            )
            P[a * M : (a + 1) * M, a * M : (a + 1) * M] = H + H.T
            q_k.append(2.0 * fw.momentum_weight * scale_k**2 * axis["k"].T)
            q_phi.append(2.0 * fw.angle_weight * scale_p**2 * axis["phi"].T)
            for matrix in (np.eye(M), axis["k"][:M], axis["phi"][lean_rows]):
                block = np.zeros((2 * len(matrix), 2 * M))
                block[: len(matrix), a * M : (a + 1) * M] = matrix
                block[len(matrix) :, a * M : (a + 1) * M] = -matrix
                rows.append(block)
            bounds.append((tau_max, k_max, phi_max))
        blocks = {
            "maps": maps,
            "P": P,
            "q_k": q_k,
            "q_phi": q_phi,
            "lean_rows": lean_rows,
            "bounds": bounds,
            "G": np.vstack(rows),
        }
        self._blocks[key] = blocks
        return blocks

    def update(
        self,
        x0: np.ndarray,
        t: float,
        velocity_reference: np.ndarray,
        supports: SampleSupports,
        steps: StepVariables,
        eta: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> None:
        """:meth:`FootstepQP.update` (its rows with the flywheel's columns, zero, and the
        flywheel's rows, :meth:`_extra_rows`), then the flywheel's cost and its columns of
        the ZMP rows, from :attr:`flywheel_state`."""
        self._state_at_update = np.array(self.flywheel_state, dtype=float)
        super().update(x0, t, velocity_reference, supports, steps, eta)
        N, M, nb, p = self.N, self.M, self.n_base, self.parameters
        blocks, state = self._now, self._state_at_update
        self.P[nb:, nb:] = self.cost_scale * blocks["P"]
        for a, axis in enumerate(blocks["maps"]["axes"]):
            cols = slice(nb + a * M, nb + (a + 1) * M)
            self.q[cols] = self.cost_scale * (
                blocks["q_k"][a] @ np.full(N, state[1, a])
                + blocks["q_phi"][a] @ (axis["phi_state"] @ state[:, a])
            )
        # the ZMP rows (the first rows of G) see -tau / (m g) of their interval
        point, row = np.nonzero(supports.rows)
        normals = supports.normals[point, row]
        interval = point // p.constraint_points
        early = np.flatnonzero(interval < M)
        for a in range(2):
            self.G[early, nb + a * M + interval[early]] = -normals[early, a] / self.limits.weight

    def _extra_rows(self, supports: SampleSupports) -> tuple[np.ndarray, np.ndarray]:
        """The flywheel's bounds: the torque, the momentum at the first ``M`` samples, the
        lean there and at the last sample (rows ``+``, then ``-``, per quantity and axis)."""
        M, nb = self.M, self.n_base
        # the first of the tick's uses of the flywheel's blocks (update and cost_factor follow)
        blocks = self._now = self._flywheel_blocks(float(self.sample_times[0] - self.time))
        self._fly = blocks["maps"]
        state, lean_rows = self._state_at_update, blocks["lean_rows"]
        bounds = []
        for a, axis in enumerate(blocks["maps"]["axes"]):
            k_free = np.full(M, state[1, a])
            phi_free = (axis["phi_state"] @ state[:, a])[lean_rows]
            for free, bound in zip((np.zeros(M), k_free, phi_free), blocks["bounds"][a]):
                bounds += [bound - free, bound + free]
        G = blocks.get("G_rows")
        if G is None:  # the rows with every column of the QP, made once
            G = blocks["G_rows"] = np.zeros((len(blocks["G"]), self.n))
            G[:, nb:] = blocks["G"]
        return G, np.concatenate(bounds)

    def cost_factor(self) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`FootstepQP.cost_factor` with the flywheel's columns last: its cost block
        depends on the first interval alone, so its factor is computed once per first
        interval."""
        order, inverse = super().cost_factor()  # zero in the flywheel's columns
        blocks = self._now
        inverse_fly = blocks.get("inverse_factor")
        if inverse_fly is None:
            inverse_fly = blocks["inverse_factor"] = inverse_cholesky(blocks["P"])
        nb = self.n_base
        inverse[nb:, nb:] = inverse_fly / np.sqrt(self.cost_scale)
        return np.concatenate([order, np.arange(nb, self.n)]), inverse

    # ------------------------------------------------------------- solutions
    def footsteps(self, x: np.ndarray) -> np.ndarray:
        """Footstep positions of a solution, shape (nf, 2), in [m]."""
        return np.asarray(x)[2 * self.N : self.n_base].reshape(2, self.nf).T

    def torques(self, x: np.ndarray) -> np.ndarray:
        """Flywheel torques of a solution, shape (M, 2) (per CoM axis), in [N m]."""
        return np.asarray(x)[self.n_base :].reshape(2, self.M).T

    def flywheel_prediction(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Lean [rad] and momentum [kg m^2/s] at the samples of a solution, shapes (N, 2)."""
        self.require_update()
        assert self._fly is not None  # set by update()
        tau, state = self.torques(x), self._state_at_update
        lean, momentum = np.empty((self.N, 2)), np.empty((self.N, 2))
        for a, maps in enumerate(self._fly["axes"]):
            momentum[:, a] = state[1, a] + maps["k"] @ tau[:, a]
            lean[:, a] = maps["phi_state"] @ state[:, a] + maps["phi"] @ tau[:, a]
        return lean, momentum

    def zmp_prediction(self, prediction: Prediction, x: np.ndarray) -> np.ndarray:
        """The ZMP at the samples of a solution [m], shape (N, 2): the CMP of ``prediction``
        minus ``tau / (m g)`` of each sample's interval."""
        tau = np.zeros((self.N, 2))
        tau[: self.M] = self.torques(x)
        return prediction.zmp - tau / self.limits.weight

    def shift_primal(self, x: np.ndarray, samples: float) -> np.ndarray:
        """Warm start: :meth:`FootstepQP.shift_primal`, the torques shifted alike."""
        base = super().shift_primal(np.asarray(x)[: self.n_base], samples)
        tau = self.torques(x)
        pos = np.clip(np.arange(self.M) + samples, 0.0, self.M - 1)
        shifted = [np.interp(pos, np.arange(self.M), tau[:, a]) for a in range(2)]
        return np.concatenate([base, *shifted])


__all__ = ["FlywheelFootstepQP", "FlywheelParameters"]
