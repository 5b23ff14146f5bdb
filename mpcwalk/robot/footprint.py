"""The sole a foot's geometry offers: the lowest face of its collision (or visual) shapes.

:func:`sole_from_geometry` compiles a description (URDF or MJCF) with its shapes in MuJoCo,
gathers the shapes of the foot's rigid body (the foot link or the sole site's body, and the
links fixed to it), expresses their points in the foot frame and keeps those within
``layer`` of the lowest: the bounding rectangle of these is the footprint, its centre at the
lowest height the sole centre. It gives a preset's ``sole_offset`` (URDF) and
``sole_size``, and ``mpcwalk robots check`` compares it with the preset's.

Shapes: boxes by their corners, spheres, ellipsoids, cylinders and capsules by points on
their surface, meshes by their vertices (STL, OBJ and MuJoCo's MSH). A URDF foot whose
shapes MuJoCo does not read (Collada meshes, as Romeo's and iCub's) is measured on the same
shapes read by Pinocchio (:func:`urdf_foot_points`: any mesh format it reads, primitives by
their bounding boxes). ``package://NAME/...`` mesh files are looked for in
``package_dirs`` and in the folders above the description. A Collada file drawn with another
axis up (its ``<up_axis>``, as iCub's feet, ``Y_UP``) is turned to Z up as the format says:
the mesh reader gives its vertices as drawn, and iCub's 15.6 x 6.1 cm soles then read 6.1 x
15.6 cm, turned by a quarter turn.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin

from mpcwalk.exceptions import ConfigurationError, FrameNotFound
from mpcwalk.robot.urdf_repair import repair_inertias

#: Thickness [m] of the slice above the lowest point whose points make the footprint.
DEFAULT_LAYER = 0.005

_READABLE_MESHES = (".stl", ".obj", ".msh")
_URDF_COMPILER = (
    '<mujoco><compiler angle="radian" discardvisual="false" fusestatic="false" '
    'strippath="false" inertiafromgeom="false" balanceinertia="false"/></mujoco>'
)


@dataclass(frozen=True)
class SoleFootprint:
    """The lowest face of a foot's geometry, in the foot frame.

    Attributes:
        offset: Centre of the footprint rectangle, at the lowest point's height, in the foot
            frame [m] (a URDF preset's ``sole_offset``).
        size: Length along the foot frame's x and width along its y [m] (``sole_size``).
        source: The geometry measured: ``"collision"`` or ``"visual"``.
    """

    offset: tuple[float, float, float]
    size: tuple[float, float]
    source: str

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """x min, x max, y min, y max of the footprint in the foot frame [m]."""
        (x, y, _), (length, width) = self.offset, self.size
        return x - length / 2, x + length / 2, y - width / 2, y + width / 2

    def __str__(self) -> str:
        x, y, z = self.offset
        return (
            f"{self.size[0]:.3f} x {self.size[1]:.3f} m centred at ({x:.3f}, {y:.3f}, {z:.3f}) m "
            f"({self.source} geometry)"
        )


def sole_from_geometry(
    description: str | Path,
    foot: str,
    *,
    geometry: str = "auto",
    layer: float = DEFAULT_LAYER,
    package_dirs: Sequence[str | Path] = (),
) -> SoleFootprint:
    """The sole a foot's shapes offer: centre and size of their lowest face, in the foot frame.

    Args:
        description: A URDF (``.urdf``) or MJCF (``.xml``) file.
        foot: The foot frame: a link or body name, or (MJCF) a site name; the footprint is
            expressed in its frame (z up when the foot is flat).
        geometry: ``"collision"``, ``"visual"``, or ``"auto"``: the collision shapes where
            the foot has some, else the visual ones.
        layer: Thickness [m] of the slice above the lowest point that makes the footprint
            (the sole of a real foot is not exactly flat).
        package_dirs: Folders holding the packages of ``package://NAME/...`` mesh files (the
            folders above the description are looked in too).

    Returns:
        The footprint: its centre ``offset`` [m] and its ``size`` (length, width) [m].

    Raises:
        FrameNotFound: ``foot`` is neither a body nor a site of the description.
        ConfigurationError: The foot has no shape of that kind that MuJoCo reads, or
            ``geometry`` or ``layer`` is invalid.
    """
    if geometry not in ("auto", "collision", "visual"):
        raise ConfigurationError(
            f"geometry={geometry!r}; expected 'auto', 'collision' or 'visual'."
        )
    found = foot_footprints(description, [foot], layer=layer, package_dirs=package_dirs)[foot]
    kinds = ("collision", "visual") if geometry == "auto" else (geometry,)
    for kind in kinds:
        if kind in found:
            return found[kind]
    raise ConfigurationError(
        f"Foot '{foot}' of {Path(description).name} has no {' or '.join(kinds)} shape that "
        "MuJoCo or Pinocchio reads; measure its sole by hand for the preset's sole_offset "
        "and sole_size."
    )


def foot_footprints(
    description: str | Path,
    feet: Sequence[str],
    *,
    layer: float = DEFAULT_LAYER,
    package_dirs: Sequence[str | Path] = (),
    axes: np.ndarray | None = None,
) -> dict[str, dict[str, SoleFootprint]]:
    """The collision and visual footprints of each foot (:func:`sole_from_geometry`'s, the
    description compiled once): foot -> ``"collision"``/``"visual"`` -> footprint, a kind
    missing where the foot has no such shape that MuJoCo or Pinocchio reads.

    ``axes`` (3, 3), the sole's axes (columns: length, width, up) in the foot frame, measures
    the footprint along them (a foot frame turned from its sole, a preset's ``sole_rpy``):
    the offset stays in the foot frame, the size is along the sole's axes.

    Raises:
        FrameNotFound: A foot is neither a body nor a site of the description.
        ConfigurationError: ``layer`` is negative, or MuJoCo cannot compile the description.
    """
    if not layer >= 0.0:
        raise ConfigurationError(f"layer={layer} m; expected a thickness >= 0.")
    model = _geometry_model(Path(description), [Path(d) for d in package_dirs])
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    result: dict[str, dict[str, SoleFootprint]] = {}
    for foot in feet:
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, foot)
        if body >= 0:
            origin, rotation = data.xpos[body], data.xmat[body].reshape(3, 3)
        else:
            site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, foot)
            if site < 0:
                names = [model.body(i).name for i in range(model.nbody)]
                names += [model.site(i).name for i in range(model.nsite)]
                raise FrameNotFound(foot, names, Path(description).name)
            body = int(model.site_bodyid[site])
            origin, rotation = data.site_xpos[site], data.site_xmat[site].reshape(3, 3)
        weld = model.body_weldid[body]
        geoms = [g for g in range(model.ngeom) if model.body_weldid[model.geom_bodyid[g]] == weld]
        result[foot] = {}
        for kind in ("collision", "visual"):
            chosen = [g for g in geoms if _collides(model, g) == (kind == "collision")]
            points = [p for p in (_geom_points(model, data, g) for g in chosen) if len(p)]
            if points:
                local = (np.concatenate(points) - origin) @ rotation  # into the foot frame
                result[foot][kind] = _footprint(local, layer, kind, axes)
    path = Path(description)
    if path.suffix.lower() == ".urdf" and not all(len(found) == 2 for found in result.values()):
        for kind in ("collision", "visual"):
            missing = [foot for foot in feet if kind not in result[foot]]
            if not missing:
                continue
            for foot, local in urdf_foot_points(path, missing, kind, package_dirs).items():
                if len(local) >= 3:
                    result[foot][kind] = _footprint(local, layer, kind, axes)
    return result


def urdf_foot_points(
    description: Path,
    feet: Sequence[str],
    kind: str,
    package_dirs: Sequence[str | Path] = (),
) -> dict[str, np.ndarray]:
    """Points (n, 3) of each foot link's ``kind`` shapes (``"collision"`` or ``"visual"``),
    and of the links fixed to it, in the foot link's frame, read by Pinocchio (every mesh
    format it reads; primitives by the corners of their bounding boxes); an empty array for
    a foot without such shapes or when the shapes cannot be read."""
    text = repair_inertias(description.read_text())[0]
    model = pin.buildModelFromXML(text)
    folders = [str(d) for d in package_dirs]
    folders += [str(d) for d in description.resolve().parents][:6]
    geometry_type = pin.GeometryType.COLLISION if kind == "collision" else pin.GeometryType.VISUAL
    empty = {foot: np.zeros((0, 3)) for foot in feet}
    try:
        geometry = pin.buildGeomFromUrdfString(model, text, geometry_type, package_dirs=folders)
    except (RuntimeError, ValueError):
        return empty
    result = {}
    for foot in feet:
        if not model.existFrame(foot):
            result[foot] = empty[foot]
            continue
        frame = model.frames[model.getFrameId(foot)]
        to_foot = frame.placement.inverse()
        points = []
        for item in geometry.geometryObjects:
            local = _shape_points(item.geometry) if item.parentJoint == frame.parentJoint else None
            if local is not None and len(local):
                local = local @ collada_up_rotation(getattr(item, "meshPath", "")).T
                placement = to_foot * item.placement
                points.append(local @ placement.rotation.T + placement.translation)
        result[foot] = np.vstack(points) if points else empty[foot]
    return result


#: Collada's up axes, each turned to Z up (a rotation: the up axis becomes z).
_UP_ROTATIONS = {
    "X_UP": np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]),
    "Y_UP": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),
    "Z_UP": np.eye(3),
}


def collada_up_rotation(mesh_path: str | Path) -> np.ndarray:
    """The rotation (3, 3) taking a mesh file's vertices, as drawn, to Z up: its Collada
    ``<up_axis>`` (X_UP, Y_UP or Z_UP, the format's default Y_UP when unsaid); the identity
    for any other file or one that cannot be read."""
    path = Path(str(mesh_path))
    if path.suffix.lower() != ".dae" or not path.is_file():
        return np.eye(3)
    try:
        with open(path, encoding="utf-8", errors="replace") as stream:
            head = stream.read(65536)
    except OSError:
        return np.eye(3)
    found = re.search(r"<up_axis>\s*([XYZ]_UP)\s*</up_axis>", head)
    return _UP_ROTATIONS[found.group(1) if found else "Y_UP"]


def _shape_points(shape) -> np.ndarray | None:
    """Mesh vertices, or the corners of a primitive's bounding box, in the shape's frame."""
    if hasattr(shape, "vertices"):
        try:
            return np.asarray(shape.vertices(), dtype=float)
        except (RuntimeError, TypeError):
            return None
    if hasattr(shape, "halfSide"):
        half = np.asarray(shape.halfSide, dtype=float)
    elif hasattr(shape, "radius") and hasattr(shape, "halfLength"):
        capsule = type(shape).__name__ == "Capsule"
        half = np.array([shape.radius, shape.radius, shape.halfLength + capsule * shape.radius])
    elif hasattr(shape, "radius"):
        half = np.full(3, float(shape.radius))
    else:
        return None
    corners = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).reshape(3, -1).T
    return corners * half


def _collides(model: mujoco.MjModel, geom: int) -> bool:
    return bool(model.geom_contype[geom] or model.geom_conaffinity[geom])


def _footprint(
    points: np.ndarray, layer: float, source: str, axes: np.ndarray | None = None
) -> SoleFootprint:
    """The bounding rectangle of ``points`` [m] (foot frame) within ``layer`` of the lowest,
    along ``axes`` (columns in the foot frame; default: the foot frame's)."""
    turn = np.eye(3) if axes is None else np.asarray(axes, dtype=float)
    points = points @ turn
    lowest = float(points[:, 2].min())
    low = points[points[:, 2] <= lowest + layer]
    (x_min, y_min), (x_max, y_max) = low[:, :2].min(axis=0), low[:, :2].max(axis=0)
    centre = turn @ np.array([0.5 * float(x_min + x_max), 0.5 * float(y_min + y_max), lowest])
    return SoleFootprint(
        offset=(float(centre[0]), float(centre[1]), float(centre[2])),
        size=(float(x_max - x_min), float(y_max - y_min)),
        source=source,
    )


def _sphere_points(count: int = 96) -> np.ndarray:
    """``count`` points spread on the unit sphere (Fibonacci lattice), the poles included."""
    z = np.linspace(-1.0, 1.0, count)
    angle = np.pi * (3.0 - np.sqrt(5.0)) * np.arange(count)
    radius = np.sqrt(1.0 - z**2)
    return np.column_stack([radius * np.cos(angle), radius * np.sin(angle), z])


def _circle_points(count: int = 32) -> np.ndarray:
    angle = np.linspace(0.0, 2.0 * np.pi, count, endpoint=False)
    return np.column_stack([np.cos(angle), np.sin(angle)])


def _geom_points(model: mujoco.MjModel, data: mujoco.MjData, geom: int) -> np.ndarray:
    """Points of ``geom``'s surface in the world [m] (none for planes and height fields)."""
    size, kind, types = model.geom_size[geom], mujoco.mjtGeom(model.geom_type[geom]), mujoco.mjtGeom
    if kind == types.mjGEOM_BOX:
        corners = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).reshape(3, -1).T
        local = corners * size
    elif kind in (types.mjGEOM_SPHERE, types.mjGEOM_ELLIPSOID):
        local = _sphere_points() * (size if kind == types.mjGEOM_ELLIPSOID else size[0])
    elif kind == types.mjGEOM_CYLINDER:
        ring = _circle_points() * size[0]
        local = np.vstack([np.column_stack([ring, np.full(len(ring), h)]) for h in (-1, 1)])
        local[:, 2] *= size[1]
    elif kind == types.mjGEOM_CAPSULE:
        ball = _sphere_points() * size[0]
        local = np.vstack([ball + [0.0, 0.0, h * size[1]] for h in (-1, 1)])
    elif kind == types.mjGEOM_MESH:
        mesh = model.geom_dataid[geom]
        start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
        local = np.asarray(model.mesh_vert[start : start + count], dtype=float)
    else:
        return np.zeros((0, 3))
    return data.geom_xpos[geom] + local @ data.geom_xmat[geom].reshape(3, 3).T


def _resolve_package(uri: str, description: Path, package_dirs: Sequence[Path]) -> str:
    """The file of a ``package://NAME/rest`` URI, or the URI when not found."""
    name, _, rest = uri[len("package://") :].partition("/")
    for folder in (*package_dirs, *description.resolve().parents):
        candidate = folder / name / rest
        if candidate.is_file():
            return candidate.as_posix()
    return uri


def _geometry_model(path: Path, package_dirs: Sequence[Path]) -> mujoco.MjModel:
    """MuJoCo model of the description at ``path`` with its collision and visual shapes
    (the meshes MuJoCo does not read left out)."""
    if not path.is_file():
        raise ConfigurationError(f"Description file {path} not found; give a URDF or MJCF file.")
    if path.suffix.lower() == ".urdf":
        root = ET.fromstring(repair_inertias(path.read_text())[0])
        for element in root.iter("mesh"):
            filename = element.get("filename", "")
            if filename.startswith("package://"):
                filename = _resolve_package(filename, path, package_dirs)
            elif filename.startswith("file://"):
                filename = filename[len("file://") :]
            elif filename and not Path(filename).is_absolute():
                filename = (path.parent / filename).as_posix()
            element.set("filename", filename)
        text = re.sub(
            r"(<robot\b[^>]*>)",
            lambda match: match.group(1) + _URDF_COMPILER,
            ET.tostring(root, encoding="unicode"),
            count=1,
        )
        spec = mujoco.MjSpec.from_string(text)
    else:
        spec = mujoco.MjSpec.from_file(str(path))
    meshes = {mesh.name: mesh for mesh in spec.meshes}
    for geom in list(spec.geoms):
        mesh = meshes.get(geom.meshname)
        if mesh is not None and not _readable(mesh.file, spec.meshdir, path):
            spec.delete(geom)
    used = {geom.meshname for geom in spec.geoms}
    for mesh in list(spec.meshes):
        if mesh.name not in used:
            spec.delete(mesh)
    try:
        return spec.compile()
    except ValueError as error:
        raise ConfigurationError(
            f"MuJoCo cannot compile {path.name} with its shapes ({error}); fix the description."
        ) from error


def _readable(file: str, meshdir: str, description: Path) -> bool:
    """Whether MuJoCo reads the mesh ``file`` (a format it knows, and the file exists)."""
    if Path(file).suffix.lower() not in _READABLE_MESHES:
        return False
    candidates = [Path(file), description.parent / meshdir / file, description.parent / file]
    return any(candidate.is_file() for candidate in candidates)


__all__ = [
    "DEFAULT_LAYER",
    "SoleFootprint",
    "collada_up_rotation",
    "foot_footprints",
    "sole_from_geometry",
    "urdf_foot_points",
]
