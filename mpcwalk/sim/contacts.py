"""Foot contact wrenches and the centre of pressure from MuJoCo contacts (ground truth)."""

from collections.abc import Sequence

import mujoco
import numpy as np

from mpcwalk._checks import freeze, frozen_array
from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.sensors import FootContact

_NAN3 = frozen_array([np.nan, np.nan, np.nan])
_ZERO3 = frozen_array([0.0, 0.0, 0.0])
_SIDES = np.arange(2)[:, None]
_EDGES = np.arange(4)
_CROSS_A = np.array([1, 2, 0])  # (a x b)_i = a_j b_k - a_k b_j for (i, j, k) cyclic
_CROSS_B = np.array([2, 0, 1])


def _subtree_bodies(model: mujoco.MjModel, root: int) -> list[int]:
    """Body ``root`` and all its descendants."""
    bodies = [root]
    for body in range(root + 1, model.nbody):
        parent = int(model.body_parentid[body])
        if parent in bodies:
            bodies.append(body)
    return bodies


class ContactWrenches:
    """Sums the MuJoCo contact forces on each sole and computes the CoP (paper M eq. 31).

    The contact forces are the constraint solver's answer (``efc_force``, decoded as
    ``mj_contactForce`` does, for all contacts at once) at the contact points of the colliding
    geoms of each foot (the sole boxes), rotated from the contact frame to the world frame.
    This is the simulator's ground truth: the robot's foot force/torque sensors read the same
    wrenches in the sole frame, with their noise. The CoP of a set of points is
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
        self._site_list = list(self.site_ids)
        self._pyramidal = bool(mujoco.mj_isPyramidal(model))
        self._moments: bool | None = None
        no_force = FootContact(_ZERO3, _ZERO3, _NAN3, False)
        self._no_contact = (no_force, no_force, _NAN3, False)

    def measure(
        self, model: mujoco.MjModel, data: mujoco.MjData
    ) -> tuple[FootContact, FootContact, np.ndarray, bool]:
        """Contacts of both feet and the overall CoP at the current (forwarded) ``data``.

        Returns:
            ``(left, right, cop, has_cop)``: the two :class:`FootContact`, the CoP over the
            contact points of both feet (shape (3,), NaN without contact) and whether it is
            defined.
        """
        contacts, ncon = data.contact, data.ncon
        if ncon == 0:
            return self._no_contact
        feet_of = self._foot_of_geom[contacts.geom[:ncon]]  # (ncon, 2): foot of each geom
        on_geom2 = feet_of[:, 1] >= 0  # the force on geom2 is along +normal
        foot = np.where(on_geom2, feet_of[:, 1], feet_of[:, 0])  # -1: not a foot's contact
        keep = (foot >= 0) & (contacts.efc_address[:ncon] >= 0) & (contacts.exclude[:ncon] == 0)
        # the usual case, every contact a sole's and in the solver: a slice (views, no gathers)
        index: slice | np.ndarray = slice(0, ncon) if keep.all() else np.flatnonzero(keep)
        on_geom2, foot = on_geom2[index], foot[index]
        frames = contacts.frame[index].reshape(-1, 3, 3)  # rows: normal, tangents
        points = contacts.pos[index]
        wrenches = self._contact_wrenches(model, data, index)  # contact frames
        sign = np.where(on_geom2, 1.0, -1.0)
        forces = sign[:, None] * (wrenches[:, None, :3] @ frames)[:, 0]
        selector = (foot == _SIDES).astype(float)  # (2, n)
        force_sums = selector @ forces
        # sum_i (p_i - o) f_i^T per foot (o: sole origin): its skew part is the moment
        # about o, its last column sum_i f_z,i (p_i - o) gives the CoP
        origins = data.site_xpos[self._site_list]
        products = (selector @ (points[:, :, None] * forces[:, None, :]).reshape(-1, 9)).reshape(
            2, 3, 3
        ) - origins[:, :, None] * force_sums[:, None, :]
        torque_sums = products[:, _CROSS_A, _CROSS_B] - products[:, _CROSS_B, _CROSS_A]
        if self._moments is not None:  # torsional/rolling moments of condim > 3 contacts
            torque_sums += selector @ (sign[:, None] * (wrenches[:, None, 3:] @ frames)[:, 0])
        weighted = products[:, :, 2] + origins * force_sums[:, 2:3]  # sum_i f_z,i p_i
        feet = []
        for side in range(2):
            cop, in_contact = self._cop(weighted[side], force_sums[side, 2])
            feet.append(
                FootContact(
                    force=freeze(force_sums[side].copy()),
                    torque=freeze(torque_sums[side].copy()),
                    cop=cop,
                    in_contact=in_contact,
                )
            )
        cop, has_cop = self._cop(weighted.sum(axis=0), force_sums[:, 2].sum())
        return feet[0], feet[1], cop, has_cop

    def _contact_wrenches(
        self, model: mujoco.MjModel, data: mujoco.MjData, index: slice | np.ndarray
    ) -> np.ndarray:
        """Wrenches of the contacts ``index`` (a slice or an index array) in their contact
        frames, shape (n, 6): what ``mj_contactForce`` gives, decoded from ``efc_force`` for all
        of them at once.

        A 3D contact (the soles' boxes on the floor) is decoded in one go: a pyramidal cone's
        four edge forces ``f`` give the normal force ``sum f`` and the frictional ones
        ``mu_i (f_2i - f_2i+1)`` (``mju_decodePyramid``); an elliptic cone's rows are the
        forces. Others go through ``mj_contactForce``.
        """
        contacts = data.contact
        dim = contacts.dim[index]
        wrenches = np.zeros((len(dim), 6))
        three = dim == 3
        if three.all():  # the feet's contacts: no masks
            selected: slice | np.ndarray = slice(None)
            rows, friction = contacts.efc_address[index], contacts.friction[index]
            positions = others = np.zeros(0, dtype=int)
        else:
            positions = np.arange(data.ncon)[index]  # contact numbers
            rows = contacts.efc_address[positions[three]]
            friction = contacts.friction[positions[three]]
            selected, others = three, np.flatnonzero(~three)
        if self._pyramidal:
            edges = data.efc_force[rows[:, None] + _EDGES]
            wrenches[selected, 0] = edges.sum(axis=1)
            wrenches[selected, 1:3] = friction[:, :2] * (edges[:, 0::2] - edges[:, 1::2])
        else:
            wrenches[selected, :3] = data.efc_force[rows[:, None] + _EDGES[:3]]
        for row in others:
            mujoco.mj_contactForce(model, data, int(positions[row]), wrenches[row])
        self._moments = True if len(others) else None
        return wrenches

    def _cop(self, weighted_points: np.ndarray, vertical_force: float) -> tuple[np.ndarray, bool]:
        """CoP ``sum_i f_z,i p_i / sum_i f_z,i`` (eq. 31) given both sums; NaN without contact."""
        if vertical_force <= self.contact_threshold or vertical_force <= 0.0:
            return _NAN3, False
        return freeze(weighted_points / vertical_force), True
