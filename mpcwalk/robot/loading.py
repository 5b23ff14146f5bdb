"""Robots: one description loaded into Pinocchio and MuJoCo, with names mapped.

A robot is a description file plus a small preset (``robots/presets/<name>.toml``): the two
foot frames, the sole size, the nominal walking posture, its CoM height and, for URDF models,
the actuator gains. The MJCF look-alikes written by this project (``bioloid-like``,
``atlas-like``) live in ``robots/``; URDF humanoids come from the ``example-robot-data``
package. The loader adds what MuJoCo needs and a URDF lacks (floating base, foot contact
boxes, sole and IMU sites, position actuators) and, for every robot, the floor, a light and
the sensors:

- ``imu_gyro`` [rad/s], ``imu_accelerometer`` [m/s^2], ``imu_orientation`` (quaternion w, x,
  y, z) at the site ``imu``;
- ``{left,right}_foot_force`` [N], ``{left,right}_foot_torque`` [N m] (wrench from the foot's
  parent link, in the sole frame) and ``{left,right}_foot_touch`` [N] (normal contact force)
  at the sole sites.

Conventions: world z up, x forward. Sole frames are named ``left_sole`` and ``right_sole``
in both engines (a Pinocchio frame, a MuJoCo site), at the sole centre, z up when the foot is
flat. Pinocchio's free-flyer configuration stores the base quaternion as (x, y, z, w) and the
base linear velocity in the base frame; MuJoCo's free joint stores (w, x, y, z) and the linear
velocity in the world frame: use :meth:`Robot.q_to_qpos` and friends to convert.
"""

import fnmatch
import functools
import importlib.metadata
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError, MpcwalkError

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib

ROBOTS_DIR = Path(__file__).resolve().parents[2] / "robots"
"""Folder of the robot descriptions written by this project and of their presets."""

PRESETS_DIR = ROBOTS_DIR / "presets"
SOLE_FRAMES = ("left_sole", "right_sole")
IMU_SITE = "imu"
_ERD_DISTRIBUTION = "example-robot-data"
_ERD_PACKAGE_URI = "package://example-robot-data/robots/"
_MESH_SUFFIXES = (".stl", ".obj", ".msh")
_URDF_COMPILER = (
    '<mujoco><compiler angle="radian" discardvisual="false" fusestatic="false" '
    'strippath="false" inertiafromgeom="false" balanceinertia="false"/></mujoco>'
)


class RobotNotFound(MpcwalkError, ValueError):
    """The requested robot has no preset, or its description is not installed."""

    def __init__(self, name: str, available: Sequence[str], reason: str = "") -> None:
        self.name = name
        self.available = list(available)
        why = f" ({reason})" if reason else ""
        super().__init__(
            f"Unknown robot '{name}'{why}; choose one of {', '.join(self.available) or '(none)'}."
        )


class FrameNotFound(MpcwalkError, LookupError):
    """A frame (Pinocchio frame, MuJoCo site or URDF link) does not exist in a robot."""

    def __init__(self, frame: str, available: Sequence[str], robot: str = "") -> None:
        self.frame = frame
        self.available = sorted(available)
        where = f" in robot '{robot}'" if robot else ""
        super().__init__(
            f"Frame '{frame}' not found{where}; the frames that exist are: "
            f"{', '.join(self.available)}."
        )


@dataclass(frozen=True)
class ActuatorGains:
    """Position servo parameters applied to the joints whose name matches ``joints``.

    Attributes:
        joints: Shell-style pattern of joint names (``"*_knee_joint"``).
        kp: Stiffness [N m/rad].
        kv: Damping [N m s/rad].
        armature: Reflected rotor inertia [kg m^2], set in Pinocchio and MuJoCo.
        force_limit: Torque limit [N m]; None keeps the URDF effort limit.
    """

    joints: str
    kp: float
    kv: float
    armature: float = 0.0
    force_limit: float | None = None


@dataclass(frozen=True)
class RobotPreset:
    """The data that turns a description file into a walking robot (one TOML file).

    Attributes:
        name: Robot name (``bioloid-like``).
        format: ``"mjcf"`` (file in ``robots/``) or ``"urdf"`` (file in example-robot-data).
        description: Description file, relative to its folder.
        foot_frames: Left and right foot frames: sole sites (MJCF) or foot links (URDF).
        sole_offset: Sole centre in the foot link frame [m] (URDF only).
        sole_size: Sole length and width [m].
        sole_thickness: Height of the foot contact box the loader adds [m] (URDF only).
        com_height: CoM height above the soles in the nominal posture [m].
        torso_frame: Frame to keep upright while walking.
        imu_frame: Link carrying the IMU site (URDF only; MJCF files have a site ``imu``).
        imu_offset: Position of the IMU site in that link [m].
        nominal_posture: Joint angles of the walking posture [rad]; others are 0.
        actuators: Gains by joint-name pattern, first match wins (URDF only).
        timestep: Physics time step [s] (URDF only; MJCF files set their own).
        gait: Optional walking defaults of the ``[gait]`` table (step_duration [s],
            double_support_ratio, step_height [m], leg limits [m] / [rad]...), read by the
            walk runner; empty when the preset has none.
    """

    name: str
    format: str
    description: str
    foot_frames: tuple[str, str]
    sole_size: tuple[float, float]
    com_height: float
    torso_frame: str
    sole_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    sole_thickness: float = 0.01
    imu_frame: str = ""
    imu_offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    nominal_posture: dict[str, float] = field(default_factory=dict)
    actuators: tuple[ActuatorGains, ...] = ()
    timestep: float = 0.002
    gait: dict[str, float] = field(default_factory=dict)

    @staticmethod
    def from_file(path: Path) -> "RobotPreset":
        """Read a preset from a TOML file (see ``robots/presets/``)."""
        try:
            raw = tomllib.loads(path.read_text())
            feet, imu = raw.get("feet", {}), raw.get("imu", {})
            return RobotPreset(
                name=raw["name"],
                format=raw["format"],
                description=raw["description"],
                foot_frames=(feet["left"], feet["right"]),
                sole_size=tuple(feet["sole_size"]),
                sole_offset=tuple(feet.get("sole_offset", (0.0, 0.0, 0.0))),
                sole_thickness=float(feet.get("sole_thickness", 0.01)),
                com_height=float(raw["com_height"]),
                torso_frame=raw["torso_frame"],
                imu_frame=imu.get("frame", ""),
                imu_offset=tuple(imu.get("offset", (0.0, 0.0, 0.0))),
                nominal_posture={k: float(v) for k, v in raw.get("nominal_posture", {}).items()},
                actuators=tuple(ActuatorGains(**a) for a in raw.get("actuators", [])),
                timestep=float(raw.get("timestep", 0.002)),
                gait={k: float(v) for k, v in raw.get("gait", {}).items()},
            )
        except (KeyError, TypeError, ValueError, tomllib.TOMLDecodeError) as error:
            raise ConfigurationError(
                f"Robot preset {path.name} is malformed ({type(error).__name__}: {error}); "
                "compare it with robots/presets/bioloid_like.toml."
            ) from error


@functools.lru_cache(maxsize=1)
def _example_robot_data_dir() -> Path | None:
    """Folder ``.../share/example-robot-data/robots`` of the installed package, or None."""
    try:
        distribution = importlib.metadata.distribution(_ERD_DISTRIBUTION)
    except importlib.metadata.PackageNotFoundError:
        return None
    for file in distribution.files or ():
        parts = file.parts
        for i in range(len(parts) - 1):
            if parts[i : i + 2] == ("example-robot-data", "robots"):
                return Path(distribution.locate_file(Path(*parts[: i + 2])))
    return None


def _presets() -> dict[str, Path]:
    presets = {}
    for path in sorted(PRESETS_DIR.glob("*.toml")):
        match = re.search(r'^name\s*=\s*"([^"]+)"', path.read_text(), re.MULTILINE)
        if match:
            presets[match.group(1)] = path
    return presets


def _description_path(preset: RobotPreset) -> Path | None:
    if preset.format == "mjcf":
        path = ROBOTS_DIR / preset.description
    else:
        root = _example_robot_data_dir()
        path = root / preset.description if root is not None else None
    return path if path is not None and path.is_file() else None


def robot_names() -> tuple[str, ...]:
    """Names of the robots that :func:`load_robot` can load on this machine."""
    names = []
    for name, path in _presets().items():
        if _description_path(RobotPreset.from_file(path)) is not None:
            names.append(name)
    return tuple(names)


def load_robot(name: str, *, visual: bool = True) -> "Robot":
    """Load a robot into Pinocchio and MuJoCo.

    Args:
        name: One of :func:`robot_names` (``bioloid-like``, ``atlas-like``, ``g1``...).
        visual: Keep the mesh geometries of URDF models (for rendering). Without them the
            MuJoCo model compiles faster and simulates the same.

    Returns:
        The robot, standing in its nominal posture ``q0`` with its soles on the ground z = 0.

    Raises:
        RobotNotFound: Unknown name, or its description file is not installed.
        FrameNotFound: A frame named in the preset does not exist in the description.
    """
    presets = _presets()
    if name not in presets:
        raise RobotNotFound(name, robot_names())
    preset = RobotPreset.from_file(presets[name])
    path = _description_path(preset)
    if path is None:
        raise RobotNotFound(
            name,
            robot_names(),
            f"its description {preset.description} is not installed; "
            "`pip install example-robot-data` provides the URDF models",
        )
    return _build_robot(preset, path, visual=visual)


@dataclass(frozen=True, eq=False)
class Robot:
    """One robot in Pinocchio (free-flyer model) and in MuJoCo (scene with floor).

    Attributes:
        name: Robot name.
        preset: The preset it was built from.
        description_path: Description file (MJCF or URDF) both models come from.
        model: Pinocchio model; configuration q = (base position [m], base quaternion x, y, z,
            w, joint angles [rad]) in Pinocchio's joint order.
        data: Pinocchio data of ``model`` (shared scratch space).
        mj_model: MuJoCo model: the robot, its floor, actuators and sensors.
        q0: Nominal walking posture, soles flat on z = 0, feet midpoint at x = y = 0.
        foot_frames: Left and right sole frame names (Pinocchio frames and MuJoCo sites).
        sole_size: Sole length and width [m].
        com_height: CoM height above the soles in the nominal posture [m] (from the preset).
        torso_frame: Frame to keep upright while walking.
        joint_names: Actuated joints in Pinocchio's order.
    """

    name: str
    preset: RobotPreset
    description_path: Path
    model: pin.Model
    data: pin.Data
    mj_model: mujoco.MjModel
    q0: np.ndarray
    foot_frames: tuple[str, str]
    sole_size: tuple[float, float]
    com_height: float
    torso_frame: str
    joint_names: tuple[str, ...]
    _q_index: np.ndarray = field(repr=False)
    _v_index: np.ndarray = field(repr=False)
    _qpos_index: np.ndarray = field(repr=False)
    _dof_index: np.ndarray = field(repr=False)
    _ctrl_qpos_index: np.ndarray = field(repr=False)

    @property
    def total_mass(self) -> float:
        """Total mass [kg]."""
        return float(pin.computeTotalMass(self.model))

    def frame_id(self, frame: str) -> int:
        """Pinocchio frame index of ``frame``; raises :class:`FrameNotFound`."""
        if not self.model.existFrame(frame):
            raise FrameNotFound(frame, [f.name for f in self.model.frames], self.name)
        return int(self.model.getFrameId(frame))

    def compute_frame_placement(self, q: np.ndarray, frame: str) -> pin.SE3:
        """World placement of ``frame`` at configuration ``q`` (Pinocchio)."""
        frame_id = self.frame_id(frame)
        pin.forwardKinematics(self.model, self.data, q)
        return pin.updateFramePlacement(self.model, self.data, frame_id).copy()

    def compute_sole_placements(self, q: np.ndarray) -> tuple[pin.SE3, pin.SE3]:
        """World placements of the left and right soles at ``q``."""
        left, right = self.foot_frames
        return self.compute_frame_placement(q, left), self.compute_frame_placement(q, right)

    def compute_com(self, q: np.ndarray) -> np.ndarray:
        """Whole-body CoM position [m], shape (3,), at ``q``."""
        return pin.centerOfMass(self.model, self.data, q).copy()

    def q_to_qpos(self, q: np.ndarray) -> np.ndarray:
        """Pinocchio configuration -> MuJoCo ``qpos``."""
        qpos = np.zeros(self.mj_model.nq)
        qpos[0:3] = q[0:3]
        qpos[3:7] = (q[6], q[3], q[4], q[5])
        qpos[self._qpos_index] = q[self._q_index]
        return qpos

    def qpos_to_q(self, qpos: np.ndarray) -> np.ndarray:
        """MuJoCo ``qpos`` -> Pinocchio configuration (base quaternion normalized)."""
        q = np.zeros(self.model.nq)
        q[0:3] = qpos[0:3]
        quat = np.asarray(qpos[3:7], dtype=float)
        q[3:7] = np.array([quat[1], quat[2], quat[3], quat[0]]) / np.linalg.norm(quat)
        q[self._q_index] = qpos[self._qpos_index]
        return q

    def v_to_qvel(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Pinocchio velocity at ``q`` -> MuJoCo ``qvel`` (base linear velocity to world)."""
        qvel = np.zeros(self.mj_model.nv)
        rotation = pin.Quaternion(np.asarray(q[3:7], dtype=float)).normalized().matrix()
        qvel[0:3] = rotation @ v[0:3]
        qvel[3:6] = v[3:6]
        qvel[self._dof_index] = v[self._v_index]
        return qvel

    def qvel_to_v(self, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
        """MuJoCo ``qvel`` at ``qpos`` -> Pinocchio velocity (base linear velocity to local)."""
        v = np.zeros(self.model.nv)
        rotation = np.zeros(9)
        quaternion = np.asarray(qpos[3:7], dtype=float)
        mujoco.mju_quat2Mat(rotation, quaternion / np.linalg.norm(quaternion))
        v[0:3] = rotation.reshape(3, 3).T @ qvel[0:3]
        v[3:6] = qvel[3:6]
        v[self._v_index] = qvel[self._dof_index]
        return v

    def q_to_ctrl(self, q: np.ndarray) -> np.ndarray:
        """Position-actuator targets (MuJoCo ``ctrl``, actuator order) holding posture ``q``."""
        return self.q_to_qpos(q)[self._ctrl_qpos_index]

    def make_mj_data(self, q: np.ndarray | None = None) -> mujoco.MjData:
        """MuJoCo data at ``q`` (default ``q0``), at rest, actuators holding ``q``, forwarded."""
        q = self.q0 if q is None else q
        mj_data = mujoco.MjData(self.mj_model)
        mj_data.qpos[:] = self.q_to_qpos(q)
        mj_data.ctrl[:] = self.q_to_ctrl(q)
        mujoco.mj_forward(self.mj_model, mj_data)
        return mj_data


def _urdf_spec(path: Path, robots_root: Path, visual: bool) -> mujoco.MjSpec:
    """MuJoCo spec of a URDF file, meshes found in example-robot-data, no collisions."""
    text = path.read_text().replace(_ERD_PACKAGE_URI, robots_root.as_posix() + "/")
    text = re.sub(r"(<robot\b[^>]*>)", lambda match: match.group(1) + _URDF_COMPILER, text, count=1)
    spec = mujoco.MjSpec.from_string(text)
    meshes = {mesh.name: mesh for mesh in spec.meshes}
    for geom in list(spec.geoms):  # keep visual meshes MuJoCo can read; drop collision geoms
        mesh = meshes.get(geom.meshname)
        readable = mesh is not None and Path(mesh.file).suffix.lower() in _MESH_SUFFIXES
        if not visual or geom.contype != 0 or geom.conaffinity != 0 or (mesh and not readable):
            spec.delete(geom)
    used = {geom.meshname for geom in spec.geoms}
    for mesh in list(spec.meshes):
        if mesh.name not in used:
            spec.delete(mesh)
    spec.worldbody.first_body().add_freejoint(name="root")
    return spec


def _add_pinocchio_frame(model: pin.Model, name: str, link: str, offset: Sequence[float]) -> None:
    """Add an operational frame ``name`` at ``offset`` [m] in the frame of ``link``."""
    parent = model.getFrameId(link)
    placement = model.frames[parent].placement * pin.SE3(np.eye(3), np.asarray(offset, float))
    model.addFrame(
        pin.Frame(name, model.frames[parent].parentJoint, parent, placement, pin.FrameType.OP_FRAME)
    )


def _add_urdf_robot_parts(spec: mujoco.MjSpec, model: pin.Model, preset: RobotPreset) -> None:
    """Sole sites and contact boxes, IMU site, position actuators, armature (both engines)."""
    links = [body.name for body in spec.bodies if body.name != "world"]
    length, width = preset.sole_size
    thickness = preset.sole_thickness
    offset = np.array(preset.sole_offset, dtype=float)
    for link, sole in zip(preset.foot_frames, SOLE_FRAMES):
        body = spec.body(link)
        if body is None or not model.existFrame(link):
            raise FrameNotFound(link, links, preset.name)
        body.add_site(
            name=sole,
            pos=offset,
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[length / 2 + 0.002, width / 2 + 0.002, 0.4 * thickness],
            rgba=[0.2, 0.8, 0.2, 0.3],
        )
        body.add_geom(
            name=f"{sole}_box",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[length / 2, width / 2, thickness / 2],
            pos=offset + [0.0, 0.0, thickness / 2],
            contype=1,
            conaffinity=0,
            friction=[1.0, 0.005, 0.0001],
            rgba=[0.8, 0.3, 0.2, 1.0],
        )
        _add_pinocchio_frame(model, sole, link, offset)
    imu_link = preset.imu_frame or spec.worldbody.first_body().name
    if spec.body(imu_link) is None or not model.existFrame(imu_link):
        raise FrameNotFound(imu_link, links, preset.name)
    spec.body(imu_link).add_site(name=IMU_SITE, pos=list(preset.imu_offset), size=[0.01, 0, 0])
    _add_pinocchio_frame(model, IMU_SITE, imu_link, preset.imu_offset)
    for joint_id in range(2, model.njoints):
        name = model.names[joint_id]
        gains = next((g for g in preset.actuators if fnmatch.fnmatchcase(name, g.joints)), None)
        if gains is None:
            raise ConfigurationError(
                f"Robot preset '{preset.name}' gives no actuator gains for joint '{name}'; add an "
                "[[actuators]] entry whose `joints` pattern matches it."
            )
        idx_v = model.idx_vs[joint_id]
        model.armature[idx_v] = gains.armature
        spec.joint(name).armature = gains.armature
        effort = gains.force_limit or float(model.effortLimit[idx_v])
        actuator = spec.add_actuator(name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        actuator.set_to_position(kp=gains.kp, kv=gains.kv)
        idx_q = model.idx_qs[joint_id]
        lower, upper = model.lowerPositionLimit[idx_q], model.upperPositionLimit[idx_q]
        if np.isfinite(lower) and np.isfinite(upper) and lower < upper:
            actuator.ctrlrange = [lower, upper]
            actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
        if np.isfinite(effort) and effort > 0.0:
            actuator.forcerange = [-effort, effort]
            actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    spec.option.timestep = preset.timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST


def _add_scene(spec: mujoco.MjSpec, preset: RobotPreset) -> None:
    """Floor, light and sensors, the same for every robot."""
    sole_sites = SOLE_FRAMES if preset.format == "urdf" else preset.foot_frames
    for site in (IMU_SITE, *sole_sites):
        if spec.site(site) is None:
            raise FrameNotFound(site, [s.name for s in spec.sites], preset.name)
    spec.add_texture(
        name="floor_grid",
        type=mujoco.mjtTexture.mjTEXTURE_2D,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
        width=512,
        height=512,
        rgb1=[0.25, 0.3, 0.35],
        rgb2=[0.15, 0.2, 0.25],
    )
    material = spec.add_material(name="floor_grid", texrepeat=[4, 4], texuniform=True)
    material.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = "floor_grid"
    spec.worldbody.add_geom(
        name="floor",
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[0, 0, 0.05],
        material="floor_grid",
        contype=0,
        conaffinity=1,
        friction=[1.0, 0.005, 0.0001],
    )
    spec.worldbody.add_light(
        name="sun", pos=[0, 0, 4], dir=[0, 0, -1], type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
    )
    site = mujoco.mjtObj.mjOBJ_SITE
    sensor = mujoco.mjtSensor
    spec.add_sensor(name="imu_gyro", type=sensor.mjSENS_GYRO, objtype=site, objname=IMU_SITE)
    spec.add_sensor(
        name="imu_accelerometer", type=sensor.mjSENS_ACCELEROMETER, objtype=site, objname=IMU_SITE
    )
    spec.add_sensor(
        name="imu_orientation", type=sensor.mjSENS_FRAMEQUAT, objtype=site, objname=IMU_SITE
    )
    for side, sole in zip(("left", "right"), sole_sites):
        for kind, sensor_type in (
            ("force", sensor.mjSENS_FORCE),
            ("torque", sensor.mjSENS_TORQUE),
            ("touch", sensor.mjSENS_TOUCH),
        ):
            spec.add_sensor(
                name=f"{side}_foot_{kind}", type=sensor_type, objtype=site, objname=sole
            )


def _build_robot(preset: RobotPreset, path: Path, *, visual: bool) -> Robot:
    if preset.format == "mjcf":
        model = pin.buildModelFromMJCF(str(path))
        spec = mujoco.MjSpec.from_file(str(path))
        foot_frames = preset.foot_frames
    elif preset.format == "urdf":
        model = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
        spec = _urdf_spec(path, _example_robot_data_dir(), visual)
        _add_urdf_robot_parts(spec, model, preset)
        foot_frames = SOLE_FRAMES
    else:
        raise ConfigurationError(
            f"Robot preset '{preset.name}' has format '{preset.format}'; expected 'mjcf' or 'urdf'."
        )
    _add_scene(spec, preset)
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
    return Robot(
        name=preset.name,
        preset=preset,
        description_path=path,
        model=model,
        data=data,
        mj_model=mj_model,
        q0=q0,
        foot_frames=tuple(foot_frames),
        sole_size=preset.sole_size,
        com_height=preset.com_height,
        torso_frame=preset.torso_frame,
        joint_names=tuple(joint_names),
        _q_index=np.array(q_index),
        _v_index=np.array(v_index),
        _qpos_index=np.array(qpos_index),
        _dof_index=np.array(dof_index),
        _ctrl_qpos_index=np.array(ctrl_qpos_index),
    )
