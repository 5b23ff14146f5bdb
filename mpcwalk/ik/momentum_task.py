"""The centroidal angular-momentum task of the whole-body IK (the hip strategy's realisation).

The centroidal momentum matrix ``A_G(q)`` (Orin and Goswami 2013; Pinocchio's
``computeCentroidalMap``) maps the joint velocity to the momentum about the CoM,
``h_G = A_G(q) v``; its angular rows give the angular momentum ``L``. The position-level IK
steps ``dq = v dt``, so the task asks ``A_G[3:5] dq = dt L_target`` for the horizontal axes
(the IK's linearisation ``J dq = -gain e`` with ``J = A_G[3:5] / I`` and
``e = -dt L_target / (gain I)``): each row is divided by the upper body's inertia ``I`` about
that axis, so that the residual reads as an upper-body rotation [rad] and takes a weight of
the torso orientation's scale.
"""

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.tasks import finite_vector


class AngularMomentumTask:
    """Horizontal centroidal angular momentum at a target, one IK step at a time.

    Args:
        inertia: Upper body's inertia about x and y [kg m^2] (the rows' scales).
        weight: Weight [cost/rad] of the equivalent rotation.
    """

    name = "angular_momentum"
    dimension = 2

    def __init__(self, inertia: Sequence[float], weight: float = 1.0) -> None:
        inertia_xy = np.asarray(inertia, dtype=float)
        if inertia_xy.shape != (2,) or not np.all(inertia_xy > 0.0):
            raise ConfigurationError(
                f"AngularMomentumTask inertia must be two positive numbers (about x, y) "
                f"[kg m^2], got {inertia!r}."
            )
        if not (np.isfinite(weight) and weight >= 0.0):
            raise ConfigurationError(
                f"AngularMomentumTask weight must be a non-negative number, got {weight!r}."
            )
        self.scale = 1.0 / inertia_xy
        self.weight = float(weight)
        self.target = np.zeros(3)

    def set_target(self, momentum: np.ndarray) -> None:
        """Target centroidal angular momentum, world axes, shape (3,), in [kg m^2/s] (its z
        component is left free)."""
        self.target = finite_vector(momentum, 3, "angular momentum target")

    def compute_jacobian(self, model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
        """``A_G[3:5] / I``, shape (2, nv) (a forward pass of its own)."""
        centroidal = pin.computeCentroidalMap(model, data, q)
        return self.scale[:, None] * centroidal[3:5]

    def momentum(self, model: pin.Model, data: pin.Data, q: np.ndarray, v: np.ndarray):
        """Centroidal angular momentum ``A_G(q) v`` [kg m^2/s], world axes, shape (3,)."""
        return pin.computeCentroidalMap(model, data, q)[3:] @ v

    def least_squares_terms(
        self, model: pin.Model, data: pin.Data, q: np.ndarray, dt: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(H, c)`` of ``weight^2 ||J dq - dt L_target / I||^2`` (Hessian (nv, nv) and
        gradient (nv,) without the factor 2), added to the IK's least squares."""
        J = self.compute_jacobian(model, data, q)
        r = dt * self.scale * self.target[:2]
        w2 = self.weight**2
        return w2 * (J.T @ J), -w2 * (J.T @ r)
