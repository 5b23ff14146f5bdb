"""The gait's references of the controller: feet, CoM and torso-yaw targets along a schedule.

:class:`GaitReference` follows paper M's swing-foot and torso-yaw trajectories (eq. 19-23)
along the contact schedule, which a footstep-adaptive generator may replace during the walk;
:class:`GaitTargets` are its targets at one time, which a stabilizer may move before the
whole-body IK gets them.
"""

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.footsteps.footstep import Side
from mpcwalk.gait.contact_schedule import ContactSchedule
from mpcwalk.gait.height_profile import height_profile
from mpcwalk.gait.swing_foot import FeetState, FootState, SwingFootTrajectory
from mpcwalk.ik.targets import IKTargets
from mpcwalk.models.flywheel import FlywheelState
from mpcwalk.terrain import Terrain

_DIFFERENCE_STEP = 1e-5  # [s] of the swing foot's acceleration by finite differences


@dataclass(frozen=True)
class GaitTargets:
    """Targets of the whole-body IK at one time, as the gait gives them.

    A stabilizer may move them (:meth:`~mpcwalk.control.stabilizers.base.Stabilizer.adjust_targets`)
    before :meth:`ik_targets` turns them into poses.

    Attributes:
        feet: Feet poses and velocities (contact flags, step index).
        com_xy: Horizontal CoM position, shape (2,), in [m] (its height is the robot's).
        torso_yaw: Torso yaw [rad] (the torso is kept upright, unless ``flywheel`` leans it).
        flywheel: The upper body's lean and momentum a hip-strategy generator planned
            (:class:`~mpcwalk.models.flywheel.FlywheelState`), or None: the torso leans by it
            and the IK's angular-momentum task produces its momentum.
    """

    feet: FeetState
    com_xy: np.ndarray
    torso_yaw: float
    flywheel: FlywheelState | None = None

    def ik_targets(self, ground_height: float, com_height: float) -> IKTargets:
        """IK targets: the CoM ``com_height`` [m] above ``ground_height`` [m], the soles at
        their full orientation (yaw, and the roll and pitch of a tilted tread; exactly the yaw's
        rotation when flat), the torso upright at the yaw (valid by construction: built without
        the checks of ``IKTargets(...)``)."""
        com = np.array([self.com_xy[0], self.com_xy[1], ground_height + com_height])
        left, right = self.feet.left, self.feet.right
        torso, momentum = _yaw_rotation(self.torso_yaw), None
        if self.flywheel is not None:  # the hip strategy: lean and angular momentum
            torso = pin.exp3(self.flywheel.rotation_vector) @ torso
            momentum = self.flywheel.angular_momentum
        return IKTargets.trusted(
            com,
            pin.SE3(_sole_rotation(left), np.array(left.position, dtype=float)),
            pin.SE3(_sole_rotation(right), np.array(right.position, dtype=float)),
            torso,
            angular_momentum=momentum,
        )


def _yaw_rotation(yaw: float) -> np.ndarray:
    """Rotation matrix of ``yaw`` [rad] about the world z axis."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _sole_rotation(foot: FootState) -> np.ndarray:
    """Rotation matrix of a sole: ``Rz(yaw) Ry(pitch) Rx(roll)``, exactly
    :func:`_yaw_rotation` when the sole is flat."""
    return _yaw_rotation(foot.yaw) if foot.is_flat else foot.rotation


class GaitReference:
    """Feet and torso-yaw references of a walk along its contact schedule.

    Args:
        schedule: Footsteps and contact phases the walk starts with.
        step_height: Swing-foot height [m].
        profile: Swing profile, ``"cosine"`` (paper M) or ``"ctraj"`` (paper A), see
            :class:`~mpcwalk.gait.swing_foot.SwingFootTrajectory`.
        com_height: CoM height above the ground of the feet [m].
        terrain: The ground the swing feet clear (None: the floor).

    Raises:
        ConfigurationError: ``schedule`` is not a ContactSchedule.
    """

    def __init__(
        self,
        schedule: ContactSchedule,
        step_height: float,
        profile: str,
        com_height: float,
        *,
        terrain: Terrain | None = None,
    ) -> None:
        if not isinstance(schedule, ContactSchedule):
            raise ConfigurationError(
                f"schedule must be a ContactSchedule, got {type(schedule).__name__}."
            )
        self.initial_schedule = schedule
        self.schedule = schedule
        self.terrain = terrain
        self.trajectory = SwingFootTrajectory(schedule, step_height, profile, terrain=terrain)
        self.com_height = float(com_height)

    def restart(self) -> None:
        """Back to the initial schedule, for a new walk."""
        self.follow(self.initial_schedule, None)

    def follow(
        self,
        schedule: ContactSchedule,
        swing: tuple[float, Side] | None,
        now: float | None = None,
        *,
        smooth: bool = False,
    ) -> None:
        """Follow ``schedule`` from now on; the foot of ``swing`` = (time [s], side), in the
        air at that time, goes on from its pose there (no jump) to its new landing, from
        ``now`` [s] on the schedule's clock (default: that time; later when the clock jumped
        ahead, a landing brought forward). ``smooth``: re-plan the rest of the swing as a
        quintic from the foot's position, velocity and acceleration there (late step
        adjustment: no jump in velocity either), else rescale the rest of its interpolant."""
        previous = self.trajectory
        self.schedule = schedule
        self.trajectory = SwingFootTrajectory(
            schedule, previous.step_height, previous.profile, terrain=self.terrain
        )
        if swing is not None:
            t, side = swing
            foot = previous.foot_poses(t)[side]
            acceleration = None
            if smooth:  # backward difference of the velocity: the interpolants are C2 inside
                before = previous.foot_poses(t - _DIFFERENCE_STEP)[side]
                acceleration = (
                    np.asarray(foot.linear_velocity) - np.asarray(before.linear_velocity)
                ) / _DIFFERENCE_STEP
            self.trajectory.restart_swing(t if now is None else now, foot, acceleration)

    def targets(
        self, t: float, com_xy: np.ndarray, flywheel: FlywheelState | None = None
    ) -> GaitTargets:
        """Feet and torso-yaw targets at ``t`` [s], with the CoM ``com_xy`` [m] and the
        upper body's ``flywheel`` (a hip-strategy generator's, else None)."""
        feet, yaw = self.trajectory.references(t)
        return GaitTargets(feet, com_xy, float(yaw), flywheel)

    def ik_targets(self, gait: GaitTargets, t: float) -> IKTargets:
        """IK targets of ``gait`` at ``t``: the CoM at the CoM height above the ground
        reference of the schedule's height profile (the footsteps' heights, smoothed; see
        :class:`~mpcwalk.gait.height_profile.HeightProfile`)."""
        profile = height_profile(self.schedule, self.com_height)
        ground = profile.level if profile.is_level else float(profile.ground(t))
        return gait.ik_targets(ground, self.com_height)
