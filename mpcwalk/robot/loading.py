"""Loading robots: one description built into Pinocchio and MuJoCo, with names mapped.

A robot is a description file plus a small preset (``robots/presets/<name>.toml``, read by
:class:`~mpcwalk.robot.preset.RobotPreset`): the two foot frames, the sole size, the nominal
walking posture, its CoM height and, for URDF models, the actuator gains. The MJCF
look-alikes written by this project (``bioloid-like``, ``atlas-like``) live in ``robots/``;
URDF humanoids come from the ``example-robot-data`` package. The loader adds what MuJoCo
needs and a URDF lacks (floating base, foot contact boxes, sole and IMU sites, position
actuators) and, for every robot, the floor, a light and the sensors:

- ``imu_gyro`` [rad/s], ``imu_accelerometer`` [m/s^2], ``imu_orientation`` (quaternion w, x,
  y, z) at the site ``imu``;
- ``{left,right}_foot_force`` [N], ``{left,right}_foot_torque`` [N m] (wrench from the foot's
  parent link, in the sole frame) and ``{left,right}_foot_touch`` [N] (normal contact force)
  at the sole sites.

A preset's ``[base]`` table turns the root link of a URDF that does not point x forward, z up
(:mod:`mpcwalk.robot.base_orientation`), in the text both engines load. The
:class:`~mpcwalk.robot.robot.Robot` it returns also carries what MuJoCo knows and the
controller needs (the servo gains of each joint), read here once, and the joint roles
(:mod:`mpcwalk.robot.joint_roles`: found from the kinematics, the preset's ``[joints]`` table
over them).
"""

import functools
import importlib.metadata
import re
from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

from mpcwalk._checks import frozen_array
from mpcwalk.exceptions import ConfigurationError, FrameNotFound, RobotNotFound
from mpcwalk.robot.base_orientation import reorient_urdf_root
from mpcwalk.robot.joint_role_detection import detect_joint_roles
from mpcwalk.robot.joint_roles import with_preset_table
from mpcwalk.robot.package_data import ROBOT_DATA, package_data_dir
from mpcwalk.robot.preset import RobotPreset
from mpcwalk.robot.robot import Robot, ServoGains
from mpcwalk.robot.scene import (
    IMU_SITE,
    SOLE_FRAMES,
    add_scene,
    add_urdf_robot_parts,
    keep_spec,
    urdf_spec,
)
from mpcwalk.robot.urdf_repair import repair_inertias

ROBOTS_DIR = package_data_dir(ROBOT_DATA)
"""Folder of the robot descriptions written by this project and of their presets."""

PRESETS_DIR = ROBOTS_DIR / "presets"
_ERD_DISTRIBUTION = "example-robot-data"


@functools.lru_cache(maxsize=1)
def example_robot_data_dir() -> Path | None:
    """Folder ``.../share/example-robot-data/robots`` of the installed package, or None."""
    try:
        distribution = importlib.metadata.distribution(_ERD_DISTRIBUTION)
    except importlib.metadata.PackageNotFoundError:
        return None
    for file in distribution.files or ():
        parts = file.parts
        for i in range(len(parts) - 1):
            if parts[i : i + 2] == ("example-robot-data", "robots"):
                return Path(str(distribution.locate_file(Path(*parts[: i + 2]))))
    return None


def _presets() -> dict[str, Path]:
    """Preset files by robot name."""
    presets = {}
    for path in sorted(PRESETS_DIR.glob("*.toml")):
        match = re.search(r'^name\s*=\s*"([^"]+)"', path.read_text(), re.MULTILINE)
        if match:
            presets[match.group(1)] = path
    return presets


def _description_path(preset: RobotPreset, folder: Path | None = None) -> Path | None:
    """The preset's description file, or None when it is not installed: next to a user's
    preset file (``folder``) first, then the shipped robots or example-robot-data."""
    path: Path | None
    if folder is not None and (folder / preset.description).is_file():
        return folder / preset.description
    if preset.format == "mjcf":
        path = ROBOTS_DIR / preset.description
    else:
        root = example_robot_data_dir()
        path = root / preset.description if root is not None else None
    return path if path is not None and path.is_file() else None


def robot_names() -> tuple[str, ...]:
    """Names of the robots that :func:`load_robot` can load on this machine."""
    names = []
    for name, path in _presets().items():
        if _description_path(RobotPreset.from_file(path)) is not None:
            names.append(name)
    return tuple(names)


def load_robot(name: str | Path, *, visual: bool = True) -> Robot:
    """Load a robot into Pinocchio and MuJoCo.

    Args:
        name: One of :func:`robot_names` (``bioloid-like``, ``atlas-like``, ``g1``...), or
            the path of a preset file (``.toml``, as in ``robots/presets/``) of a user's robot:
            its ``description`` (URDF or MJCF) is looked for next to the preset file, then
            among the shipped descriptions and example-robot-data's.
        visual: Keep the mesh geometries of URDF models (for rendering). Without them the
            MuJoCo model compiles faster and simulates the same.

    Returns:
        The robot, standing in its nominal posture ``q0`` with its soles on the ground z = 0.

    Raises:
        RobotNotFound: Unknown name, or its description file is not installed.
        FrameNotFound: A frame named in the preset does not exist in the description.
    """
    if _is_preset_path(name):
        preset_file = Path(name)
        if not preset_file.is_file():
            what = "a folder" if preset_file.is_dir() else "not found"
            raise RobotNotFound(
                str(name), robot_names(), f"the preset file {preset_file} is {what}"
            )
        preset = RobotPreset.from_file(preset_file)
        path = _description_path(preset, preset_file.parent)
        name = preset.name
    else:
        presets = _presets()
        if name not in presets:
            raise RobotNotFound(str(name), robot_names())
        preset = RobotPreset.from_file(presets[name])
        path = _description_path(preset)
    if path is None:
        raise RobotNotFound(
            name,
            robot_names(),
            f"its description {preset.description} is not installed; "
            "`pip install example-robot-data` provides the URDF models",
        )
    return build_robot(preset, path, visual=visual)


def _is_preset_path(name: str | Path) -> bool:
    """Whether ``name`` names a preset file rather than a shipped robot."""
    return isinstance(name, Path) or str(name).endswith(".toml") or "/" in str(name)


def build_robot(preset: RobotPreset, path: Path, *, visual: bool) -> Robot:
    """The robot of ``preset`` from its description file ``path`` (:func:`load_robot` once
    it found them)."""
    if preset.format == "mjcf":
        if (preset.base_forward, preset.base_up) != ("x", "z"):
            raise ConfigurationError(
                f"Robot preset '{preset.name}': a [base] table (forward = "
                f"{preset.base_forward!r}, up = {preset.base_up!r}) is supported for URDF "
                "descriptions only; turn the root body of the MJCF file instead (its quat)."
            )
        model = pin.buildModelFromMJCF(str(path))
        spec = mujoco.MjSpec.from_file(str(path))
        foot_frames = preset.foot_frames
    elif preset.format == "urdf":
        original = path.read_text()
        text, _ = repair_inertias(original)
        text = reorient_urdf_root(text, preset.base_forward, preset.base_up)
        model = (
            pin.buildModelFromXML(text, pin.JointModelFreeFlyer())
            if text != original
            else pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
        )
        root = example_robot_data_dir()
        if root is None:
            raise RobotNotFound(preset.name, robot_names(), "example-robot-data is not installed")
        spec = urdf_spec(path, root, visual, text)
        add_urdf_robot_parts(spec, model, preset)
        foot_frames = SOLE_FRAMES
    else:
        raise ConfigurationError(
            f"Robot preset '{preset.name}' has format '{preset.format}'; expected 'mjcf' or 'urdf'."
        )
    add_scene(spec, preset)
    try:
        mj_model = spec.compile()
    except ValueError as error:
        raise ConfigurationError(
            f"MuJoCo cannot compile robot '{preset.name}' ({error}); fix its description file."
        ) from error
    free = mujoco.mjtJoint.mjJNT_FREE
    if model.joints[1].shortname() != "JointModelFreeFlyer" or mj_model.jnt_type[0] != free:
        raise ConfigurationError(
            f"Robot '{preset.name}': the first joint must be the floating base in both engines."
        )
    keep_spec(mj_model, spec)  # to compile the scene again with a terrain
    q_index, v_index, qpos_index, dof_index, joint_names = [], [], [], [], []
    for joint_id in range(2, model.njoints):
        name = model.names[joint_id]
        mj_joint = mujoco.mj_name2id(mj_model, mujoco.mjtObj.mjOBJ_JOINT, name)
        if mj_joint < 0 or model.nqs[joint_id] != 1 or model.nvs[joint_id] != 1:
            raise ConfigurationError(
                f"Robot '{preset.name}': joint '{name}' is missing in MuJoCo or is not a 1-DoF "
                "revolute/prismatic joint; only those are supported."
            )
        joint_names.append(name)
        q_index.append(model.idx_qs[joint_id])
        v_index.append(model.idx_vs[joint_id])
        qpos_index.append(mj_model.jnt_qposadr[mj_joint])
        dof_index.append(mj_model.jnt_dofadr[mj_joint])
    ctrl_qpos_index = mj_model.jnt_qposadr[mj_model.actuator_trnid[:, 0]]
    data = model.createData()
    q0 = pin.neutral(model)
    for name, angle in preset.nominal_posture.items():
        if name not in joint_names:
            raise ConfigurationError(
                f"Robot preset '{preset.name}': nominal posture names joint '{name}', which does "
                f"not exist; the joints are {', '.join(joint_names)}."
            )
        q0[model.idx_qs[model.getJointId(name)]] = angle
    pin.framesForwardKinematics(model, data, q0)
    for frame in (*foot_frames, preset.torso_frame):
        if not model.existFrame(frame):
            raise FrameNotFound(frame, [f.name for f in model.frames], preset.name)
    soles = [data.oMf[model.getFrameId(frame)].translation for frame in foot_frames]
    q0[0:3] -= (soles[0] + soles[1]) / 2
    left, right = foot_frames
    return Robot(
        name=preset.name,
        preset=preset,
        description_path=path,
        model=model,
        data=data,
        mj_model=mj_model,
        q0=q0,
        foot_frames=(left, right),
        sole_size=preset.sole_size,
        com_height=preset.com_height,
        torso_frame=preset.torso_frame,
        joint_names=tuple(joint_names),
        gait=preset.gait,
        leg_limits=preset.gait.leg_limits(_half_stance_width(model, data, q0, (left, right))),
        servo_gains=_servo_gains(mj_model, joint_names),
        joint_roles=with_preset_table(
            detect_joint_roles(model, q0, (left, right)),
            preset.joints,
            arms=preset.arms,
            joint_names=joint_names,
            source=f"Robot preset '{preset.name}'",
        ),
        _q_index=np.array(q_index),
        _v_index=np.array(v_index),
        _qpos_index=np.array(qpos_index),
        _dof_index=np.array(dof_index),
        _ctrl_qpos_index=np.array(ctrl_qpos_index),
    )


def _half_stance_width(
    model: pin.Model, data: pin.Data, q: np.ndarray, soles: Sequence[str]
) -> float:
    """Half the horizontal distance [m] between the two sole frames at ``q``."""
    pin.forwardKinematics(model, data, q)
    left, right = (
        pin.updateFramePlacement(model, data, model.getFrameId(frame)).translation.copy()
        for frame in soles
    )
    return 0.5 * float(np.linalg.norm(left[:2] - right[:2]))


def _servo_gains(mj_model: mujoco.MjModel, joint_names: Sequence[str]) -> ServoGains:
    """Stiffness, velocity gain plus joint damping, and torque limit of the position actuator
    of each joint (inf, 0, inf for a joint without one)."""
    nb_joints = len(joint_names)
    stiffness, damping = np.full(nb_joints, np.inf), np.zeros(nb_joints)
    torque_limit = np.full(nb_joints, np.inf)
    index_of = {name: i for i, name in enumerate(joint_names)}
    for actuator in range(mj_model.nu):
        joint = int(mj_model.actuator_trnid[actuator, 0])
        name = mujoco.mj_id2name(mj_model, mujoco.mjtObj.mjOBJ_JOINT, joint)
        kp = float(mj_model.actuator_gainprm[actuator, 0])
        if name not in index_of or kp <= 0.0:
            continue
        i = index_of[name]
        stiffness[i] = kp
        damping[i] = -float(mj_model.actuator_biasprm[actuator, 2]) + float(
            mj_model.dof_damping[mj_model.jnt_dofadr[joint]]
        )
        if mj_model.actuator_forcelimited[actuator]:
            torque_limit[i] = float(np.max(np.abs(mj_model.actuator_forcerange[actuator])))
    return ServoGains(frozen_array(stiffness), frozen_array(damping), frozen_array(torque_limit))


__all__ = [
    "IMU_SITE",
    "PRESETS_DIR",
    "ROBOTS_DIR",
    "SOLE_FRAMES",
    "build_robot",
    "load_robot",
    "robot_names",
]
