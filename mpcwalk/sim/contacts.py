"""Foot contact wrenches and the measured centre of pressure from MuJoCo contacts."""

from collections.abc import Sequence

import mujoco
import numpy as np

from mpcwalk._checks import frozen_array
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.sensors import FootContact

_NAN3 = frozen_array([np.nan, np.nan, np.nan])


def _subtree_bodies(model: mujoco.MjModel, root: int) -> list[int]:
    """Body ``root`` and all its descendants."""
    bodies = [root]
    for body in range(root + 1, model.nbody):
        parent = int(model.body_parentid[body])
        if parent in bodies:
            bodies.append(body)
    return bodies


class ContactEstimator:
    """Sums the MuJoCo contact forces on each sole and computes the CoP (paper M eq. 31).

    The contact forces come from ``mj_contactForce`` (the constraint solver's answer) at the
    contact points of the colliding geoms of each foot (the sole boxes), rotated from the
    contact frame to the world frame. The CoP of a set of points is
    ``p = sum_i p_i f_z,i / sum_i f_z,i`` with ``f_z,i`` the vertical force at point ``p_i``.

    Args:
        model: MuJoCo model of the robot and its floor.
        sole_sites: Names of the left and right sole sites (``robot.foot_frames``).
        contact_threshold: Vertical force [N] above which a foot counts as in contact and
            its CoP is defined.

    Raises:
        ConfigurationError: A sole site is missing or its foot has no colliding geom.
    """

    def __init__(
        self, model: mujoco.MjModel, sole_sites: Sequence[str], *, contact_threshold: float
    ) -> None:
        if not contact_threshold >= 0.0:
            raise ConfigurationError(
                f"contact_threshold must be a force >= 0 N, got {contact_threshold!r}."
            )
        self.contact_threshold = float(contact_threshold)
        self.site_ids: tuple[int, ...] = tuple(
            mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name) for name in sole_sites
        )
        colliding = (model.geom_contype != 0) | (model.geom_conaffinity != 0)
        self._foot_of_geom = np.full(model.ngeom, -1, dtype=int)
        for foot, (name, site) in enumerate(zip(sole_sites, self.site_ids)):
            if site < 0:
                raise ConfigurationError(f"The MuJoCo model has no sole site '{name}'.")
            bodies = _subtree_bodies(model, int(model.site_bodyid[site]))
            geoms = [
                g for g in range(model.ngeom) if colliding[g] and model.geom_bodyid[g] in bodies
            ]
            if not geoms:
                raise ConfigurationError(
                    f"The foot carrying sole site '{name}' has no colliding geom; the robot "
                    "description needs a sole box with contype/conaffinity set."
                )
            self._foot_of_geom[geoms] = foot

    def measure(
        self, model: mujoco.MjModel, data: mujoco.MjData
    ) -> tuple[FootContact, FootContact, np.ndarray, bool]:
        """Contacts of both feet and the overall CoP at the current (forwarded) ``data``.

        Returns:
            ``(left, right, cop, has_cop)``: the two :class:`FootContact`, the CoP over the
            contact points of both feet (shape (3,), NaN without contact) and whether it is
            defined.
        """
        contacts = data.contact
        ncon = data.ncon
        geoms = np.asarray(contacts.geom, dtype=int).reshape(-1, 2)[:ncon]
        foot1, foot2 = self._foot_of_geom[geoms[:, 0]], self._foot_of_geom[geoms[:, 1]]
        active = np.asarray(contacts.efc_address)[:ncon] >= 0
        active &= np.asarray(contacts.exclude)[:ncon] == 0
        index = np.flatnonzero(active & ((foot1 >= 0) | (foot2 >= 0)))
        foot = np.where(foot2 >= 0, foot2, foot1)[index]
        sign = np.where(foot2 >= 0, 1.0, -1.0)[index]  # the force on geom2 is along +normal
        wrenches = np.zeros((len(index), 6))
        for row, i in enumerate(index):
            mujoco.mj_contactForce(model, data, int(i), wrenches[row])
        frames = np.asarray(contacts.frame).reshape(-1, 3, 3)[index]  # rows: normal, tangents
        world = sign[:, None, None] * np.einsum("nji,nkj->nki", frames, wrenches.reshape(-1, 2, 3))
        forces, moments = world[:, 0], world[:, 1]  # moments: torsional/rolling (condim > 3)
        points = np.asarray(contacts.pos).reshape(-1, 3)[index]
        levers = points - data.site_xpos[list(self.site_ids)][foot]
        moments = moments + np.stack(
            [  # lever x force (np.cross is slow on small arrays)
                levers[:, 1] * forces[:, 2] - levers[:, 2] * forces[:, 1],
                levers[:, 2] * forces[:, 0] - levers[:, 0] * forces[:, 2],
                levers[:, 0] * forces[:, 1] - levers[:, 1] * forces[:, 0],
            ],
            axis=1,
        )
        selector = (foot[None, :] == np.arange(2)[:, None]).astype(float)  # (2, n)
        force_sums = selector @ forces
        torque_sums = selector @ moments
        weighted = selector @ (forces[:, 2:3] * points)  # sum_i f_z,i p_i per foot
        counts = selector.sum(axis=1).astype(int)
        feet = []
        for side in range(2):
            cop, in_contact = self._cop(weighted[side], force_sums[side, 2])
            feet.append(
                FootContact(
                    force=frozen_array(force_sums[side]),
                    torque=frozen_array(torque_sums[side]),
                    cop=cop,
                    in_contact=in_contact,
                    nb_points=int(counts[side]),
                )
            )
        cop, has_cop = self._cop(weighted.sum(axis=0), force_sums[:, 2].sum())
        return feet[0], feet[1], cop, has_cop

    def _cop(self, weighted_points: np.ndarray, vertical_force: float) -> tuple[np.ndarray, bool]:
        """CoP ``sum_i f_z,i p_i / sum_i f_z,i`` (eq. 31) given both sums; NaN without contact."""
        if vertical_force <= self.contact_threshold or vertical_force <= 0.0:
            return _NAN3, False
        return frozen_array(weighted_points / vertical_force), True
