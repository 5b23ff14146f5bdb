"""Joint roles found from the kinematics (:func:`detect_joint_roles`).

Detection, at a configuration ``q`` with the robot upright (base x forward, z up, y to the
left), every direction expressed in the base frame:

- **Axis kind.** A revolute joint whose axis has its largest component along x is a *roll*
  joint, along y a *pitch* joint, along z a *yaw* joint. An axis whose largest component is
  below :data:`AXIS_THRESHOLD` (a joint at 45 degrees) gets no role; the roles' ``notes`` say
  so.
- **Legs.** The leg of a foot frame is the chain of revolute joints from the floating base to
  that frame, less the joints both feet's chains share. In chain order from the base: the
  first yaw joint is ``hip_yaw``. With two or more roll joints the first is ``hip_roll``,
  the last ``ankle_roll``; with three or more pitch joints the first is ``hip_pitch``, the
  last ``ankle_pitch`` and the one in between nearest mid-leg the ``knee``. Fewer roll or
  pitch joints take their role from their height above the sole, as a fraction ``h`` of the
  leg (the first leg joint's height): a pitch joint is the hip pitch above ``h = 2/3``, the
  ankle pitch below ``1/3`` and the knee in between; a single roll joint is the hip roll in
  the upper half of the leg, the ankle roll in the lower half.
- **Arms.** An arm is a branch of the tree that holds no leg joint, lies wholly on one side of
  the base (every joint, body CoM and frame of it at ``y > 0``: left, ``y < 0``:
  right) and reaches
  at least :data:`ARM_REACH` times the leg length from its first joint; a head, on the middle
  line, is none, and a hand's fingers are part of their arm. Along the arm's chain from its
  first joint to its farthest point (the hand), the ``elbow`` is the bending joint (axis at
  more than 60 degrees from the line shoulder-hand) nearest the middle of that line, at least
  a fifth of the line from either end. ``shoulder_pitch`` and ``shoulder_roll`` are the first
  pitch and roll joints before the elbow and nearer the arm's first joint than the elbow. A shoulder without a pitch joint (Talos's turns
  about yaw, roll and yaw) has no ``shoulder_pitch``.
"""

from collections.abc import Iterable

import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.joint_roles import ARM_ROLES, LEG_ROLES, SIDES, JointRoles

#: Smallest largest-component of a unit joint axis that makes it a roll, pitch or yaw joint
#: (41 degrees off the axis; a joint at 45 degrees is ambiguous).
AXIS_THRESHOLD = 0.75
#: Smallest reach of an arm from its first joint, as a fraction of the leg length.
ARM_REACH = 0.25
#: Largest |cos| between a bending joint's axis and the line shoulder-hand (60 degrees).
_BENDING = 0.5
#: Smallest distance of the elbow from either end of the arm, as a fraction of its length.
_ELBOW_MARGIN = 0.2

_KINDS = ("roll", "pitch", "yaw")


class Detection:
    """The kinematic facts detection needs: positions and axes in the base frame."""

    def __init__(self, model: pin.Model, q: np.ndarray, foot_frames: tuple[str, str]) -> None:
        for frame in foot_frames:
            if not model.existFrame(frame):
                raise ConfigurationError(
                    f"Joint roles: foot frame '{frame}' is not in the model; its frames are "
                    f"{', '.join(f.name for f in model.frames)}."
                )
        self.model = model
        self.notes: list[str] = []
        data = model.createData()
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        pin.computeJointJacobians(model, data, q)
        floating = model.njoints > 1 and model.nvs[1] == 6
        base = data.oMi[1] if floating else pin.SE3.Identity()
        to_base = base.rotation.T
        self.position = {j: to_base @ (data.oMi[j].translation - base.translation) for j in
                         range(1, model.njoints)}  # fmt: skip
        self.frame_position = [to_base @ (f.translation - base.translation) for f in data.oMf]
        self.com_position = {j: to_base @ (data.oMi[j].act(model.inertias[j].lever) - base.translation)
                             for j in range(1, model.njoints)}  # fmt: skip
        self.axis: dict[int, np.ndarray] = {}
        for j in range(1, model.njoints):
            if model.joints[j].shortname().startswith("JointModelR") and model.nvs[j] == 1:
                column = model.joints[j].idx_v
                axis = pin.getJointJacobian(model, data, j, pin.LOCAL_WORLD_ALIGNED)[3:6, column]
                self.axis[j] = to_base @ axis / max(float(np.linalg.norm(axis)), 1e-12)
        self.foot_joints = [int(model.frames[model.getFrameId(f)].parentJoint) for f in foot_frames]
        self.sole_z = [self.frame_position[model.getFrameId(f)][2] for f in foot_frames]

    def name(self, joint: int | None) -> str | None:
        return None if joint is None else str(self.model.names[joint])

    def kind(self, joint: int) -> str | None:
        """``"roll"``, ``"pitch"``, ``"yaw"`` or None (ambiguous axis)."""
        axis = self.axis[joint]
        k = int(np.argmax(np.abs(axis)))
        if abs(axis[k]) < AXIS_THRESHOLD:
            self.notes.append(
                f"joint {self.name(joint)}'s axis {np.round(axis, 2).tolist()} is neither roll, "
                "pitch nor yaw"
            )
            return None
        return _KINDS[k]

    def chain(self, joint: int) -> list[int]:
        """The joints from the base down to ``joint`` (included)."""
        chain = []
        while joint > 0:
            chain.append(joint)
            joint = int(self.model.parents[joint])
        return chain[::-1]

    def points(self, subtree: Iterable[int]) -> list[tuple[np.ndarray, int]]:
        """The joint origins, body CoMs and frames of the joints ``subtree``, each with its
        joint."""
        joints = {int(j) for j in subtree}
        points = [(self.position[j], j) for j in joints] + [
            (self.com_position[j], j) for j in joints
        ]
        points += [
            (self.frame_position[i], int(frame.parentJoint))
            for i, frame in enumerate(self.model.frames)
            if frame.parentJoint in joints
        ]
        return points

    def roles(self) -> JointRoles:
        chains = [self.chain(j) for j in self.foot_joints]
        legs = [[j for j in own if j not in other and j in self.axis]
                for own, other in ((chains[0], chains[1]), (chains[1], chains[0]))]  # fmt: skip
        names: dict[str, str | None] = {}
        lengths = []
        for side, leg, sole_z in zip(SIDES, legs, self.sole_z):
            length = float(self.position[leg[0]][2] - sole_z) if leg else 0.0
            lengths.append(length)
            for role, joint in self.leg_roles(leg, sole_z, length).items():
                names[f"{side}_{role}"] = self.name(joint)
        leg_joints = set(chains[0]) | set(chains[1])
        arm_reach = ARM_REACH * float(np.mean(lengths))
        for side, sign in zip(SIDES, (1.0, -1.0)):
            for role, joint in self.arm_roles(side, sign, leg_joints, arm_reach).items():
                names[f"{side}_{role}"] = self.name(joint)
        return JointRoles(names, tuple(self.notes))

    def leg_roles(self, leg: list[int], sole_z: float, length: float) -> dict[str, int | None]:
        """The leg roles of the joints ``leg`` (base to foot) above a sole at ``sole_z``."""
        kinds: dict[str, list[int]] = {kind: [] for kind in _KINDS}
        for joint in leg:
            kind = self.kind(joint)
            if kind is not None:
                kinds[kind].append(joint)
        span = max(length, 1e-9)

        def height(joint: int) -> float:
            return float(self.position[joint][2] - sole_z) / span

        roles: dict[str, int | None] = dict.fromkeys(LEG_ROLES)
        roles["hip_yaw"] = kinds["yaw"][0] if kinds["yaw"] else None
        rolls, pitches = kinds["roll"], kinds["pitch"]
        if len(rolls) >= 2:
            roles["hip_roll"], roles["ankle_roll"] = rolls[0], rolls[-1]
        elif rolls:
            roles["hip_roll" if height(rolls[0]) > 0.5 else "ankle_roll"] = rolls[0]
        if len(pitches) >= 3:
            roles["hip_pitch"], roles["ankle_pitch"] = pitches[0], pitches[-1]
            roles["knee"] = min(pitches[1:-1], key=lambda j: abs(height(j) - 0.5))
        else:
            for joint in pitches:
                h = height(joint)
                role = "hip_pitch" if h > 2 / 3 else "ankle_pitch" if h < 1 / 3 else "knee"
                if roles[role] is None:
                    roles[role] = joint
        return roles

    def arm_roles(
        self, side: str, sign: float, leg_joints: set[int], reach: float
    ) -> dict[str, int | None]:
        """The arm roles on ``side`` (``sign``: +1 left, -1 right)."""
        model = self.model
        candidates = {}
        for joint in self.axis:
            subtree = [int(j) for j in model.subtrees[joint]]
            if leg_joints & set(subtree):
                continue
            points = [point for point, _ in self.points(subtree)]
            if all(sign * p[1] > 0.0 for p in points):
                far = max(float(np.linalg.norm(p - self.position[joint])) for p in points)
                candidates[joint] = far
        tops = {j: far for j, far in candidates.items() if model.parents[j] not in candidates}
        arms = sorted((j for j, far in tops.items() if far >= reach), key=lambda j: -tops[j])
        if not arms:
            self.notes.append(f"no {side} arm found")
            return dict.fromkeys(ARM_ROLES)
        if len(arms) > 1:
            self.notes.append(
                f"{side} arm: took {self.name(arms[0])}'s branch (the longest), not "
                f"{', '.join(str(self.name(j)) for j in arms[1:])}"
            )
        return self.arm_chain_roles(arms[0])

    def arm_chain_roles(self, root: int) -> dict[str, int | None]:
        """Shoulder pitch, shoulder roll and elbow of the arm whose first joint is ``root``."""
        model = self.model
        subtree = {int(j) for j in model.subtrees[root]}
        ends = self.points(subtree)
        start = self.position[root]
        end, end_joint = max(ends, key=lambda e: float(np.linalg.norm(e[0] - start)))
        chain = [j for j in self.chain(end_joint) if j in subtree and j in self.axis]
        length = float(np.linalg.norm(end - start))
        line = (end - start) / length
        elbow, best = None, np.inf
        for joint in chain:
            from_start = float(np.linalg.norm(self.position[joint] - start))
            to_end = float(np.linalg.norm(end - self.position[joint]))
            bending = abs(float(self.axis[joint] @ line)) < _BENDING
            inside = min(from_start, to_end) >= _ELBOW_MARGIN * length
            if bending and inside and abs(from_start - to_end) < best:
                elbow, best = joint, abs(from_start - to_end)
        # the shoulder: before the elbow and nearer the arm's first joint than the elbow
        bound = end if elbow is None else self.position[elbow]
        shoulder = [
            j
            for j in (chain if elbow is None else chain[: chain.index(elbow)])
            if np.linalg.norm(self.position[j] - start) < np.linalg.norm(self.position[j] - bound)
        ]
        kinds = {j: self.kind(j) for j in shoulder}
        return {
            "shoulder_pitch": next((j for j in shoulder if kinds[j] == "pitch"), None),
            "shoulder_roll": next((j for j in shoulder if kinds[j] == "roll"), None),
            "elbow": elbow,
        }


def detect_joint_roles(model: pin.Model, q: np.ndarray, foot_frames: tuple[str, str]) -> JointRoles:
    """The joint roles of ``model`` found from its kinematics at ``q`` (see
    :mod:`mpcwalk.robot.joint_role_detection`), never from the joint names.

    Args:
        model: Pinocchio model (floating base or fixed).
        q: Configuration with the robot upright, base x forward and z up [m, rad].
        foot_frames: Left and right foot frames (each ends a leg).

    Raises:
        ConfigurationError: A foot frame that is not in the model.
    """
    return Detection(model, np.asarray(q, dtype=float), foot_frames).roles()


__all__ = ["ARM_REACH", "AXIS_THRESHOLD", "Detection", "detect_joint_roles"]
