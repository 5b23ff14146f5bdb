"""What the loader adds to a description so that both engines walk the same robot.

For a URDF humanoid (:func:`urdf_spec`, :func:`add_urdf_robot_parts`): a floating base, the
sole sites and contact boxes, the IMU site, position actuators and armatures, in MuJoCo and,
for the frames and armatures, in Pinocchio. For every robot (:func:`add_scene`): the floor, a
light and the sensors (IMU gyro, accelerometer and orientation; force, torque and touch at
each sole). The loader keeps the spec of each robot's scene (:func:`keep_spec`), to compile
it again with more in it (a terrain: :mod:`mpcwalk.robot.terrain_scene`).
"""

import fnmatch
import re
import weakref
from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError, FrameNotFound
from mpcwalk.robot.ground import add_ground_field
from mpcwalk.robot.preset import RobotPreset

SOLE_FRAMES = ("left_sole", "right_sole")
"""Sole frame names of URDF robots, in both engines (MJCF files name their own)."""

IMU_SITE = "imu"
"""Site (MuJoCo) and frame (Pinocchio) of the IMU."""

#: The MuJoCo spec each loaded robot's ``mj_model`` was compiled from.
_SPECS: "weakref.WeakKeyDictionary[mujoco.MjModel, mujoco.MjSpec]" = weakref.WeakKeyDictionary()

_ERD_PACKAGE_URI = "package://example-robot-data/robots/"
_MESH_SUFFIXES = (".stl", ".obj", ".msh")
_URDF_COMPILER = (
    '<mujoco><compiler angle="radian" discardvisual="false" fusestatic="false" '
    'strippath="false" inertiafromgeom="false" balanceinertia="false"/></mujoco>'
)


def urdf_spec(
    path: Path, robots_root: Path, visual: bool, text: str | None = None
) -> mujoco.MjSpec:
    """MuJoCo spec of a URDF file (or of its ``text``, repaired), meshes found in
    example-robot-data, no collisions."""
    text = (path.read_text() if text is None else text).replace(
        _ERD_PACKAGE_URI, robots_root.as_posix() + "/"
    )
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


def _add_pinocchio_frame(
    model: pin.Model,
    name: str,
    link: str,
    offset: Sequence[float] | np.ndarray,
    rotation: np.ndarray | None = None,
) -> None:
    """Add an operational frame ``name`` at ``offset`` [m] in the frame of ``link``, turned
    by ``rotation`` (3, 3) in it (default: aligned)."""
    parent = model.getFrameId(link)
    turn = np.eye(3) if rotation is None else rotation
    placement = model.frames[parent].placement * pin.SE3(turn, np.asarray(offset, float))
    model.addFrame(
        pin.Frame(name, model.frames[parent].parentJoint, parent, placement, pin.FrameType.OP_FRAME)
    )


def add_urdf_robot_parts(spec: mujoco.MjSpec, model: pin.Model, preset: RobotPreset) -> None:
    """Sole sites and contact boxes, IMU site, position actuators, armature (both engines)."""
    links = [body.name for body in spec.bodies if body.name != "world"]
    length, width = preset.sole_size
    thickness = preset.sole_thickness
    offset = np.array(preset.sole_offset, dtype=float)
    turn = pin.rpy.rpyToMatrix(np.array(preset.sole_rpy, dtype=float))
    quat = pin.Quaternion(turn).coeffs()  # x, y, z, w
    sole_quat = [float(quat[3]), float(quat[0]), float(quat[1]), float(quat[2])]
    for link, sole in zip(preset.foot_frames, SOLE_FRAMES):
        body = spec.body(link)
        if body is None or not model.existFrame(link):
            raise FrameNotFound(link, links, preset.name)
        body.add_site(
            name=sole,
            pos=offset,
            quat=sole_quat,
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[length / 2 + 0.002, width / 2 + 0.002, 0.4 * thickness],
            rgba=[0.2, 0.8, 0.2, 0.3],
        )
        body.add_geom(
            name=f"{sole}_box",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[length / 2, width / 2, thickness / 2],
            pos=offset + turn @ [0.0, 0.0, thickness / 2],
            quat=sole_quat,
            contype=1,
            conaffinity=0,
            friction=[1.0, 0.005, 0.0001],
            rgba=[0.8, 0.3, 0.2, 1.0],
        )
        _add_pinocchio_frame(model, sole, link, offset, turn)
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


def keep_spec(model: mujoco.MjModel, spec: mujoco.MjSpec) -> None:
    """Remember that ``model`` was compiled from ``spec`` (for :func:`kept_spec`)."""
    _SPECS[model] = spec


def kept_spec(model: mujoco.MjModel) -> mujoco.MjSpec | None:
    """A copy of the spec ``model`` was compiled from, or None when it was not kept (a model
    made in another process, or by hand)."""
    spec = _SPECS.get(model)
    return None if spec is None else spec.copy()


def add_scene(spec: mujoco.MjSpec, preset: RobotPreset) -> None:
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
    add_ground_field(spec)  # off: a rough ground (mpcwalk.robot.ground.Ground) switches it on
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
