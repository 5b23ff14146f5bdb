"""The terrain in the simulated world: a robot's scene with the blocks of a
:class:`~mpcwalk.terrain.Terrain` (:func:`terrain_model`).

Every block of the terrain (:meth:`Terrain.boxes <mpcwalk.terrain.Terrain.boxes>`) becomes
one static box geom of the world body, with the floor's friction and contact settings; the
floor plane goes down to :attr:`Terrain.floor <mpcwalk.terrain.Terrain.floor>` when the
terrain has pits. Geoms cannot be added to a compiled MuJoCo model, so the robot's scene is
compiled again from the spec the loader kept (:func:`~mpcwalk.robot.scene.kept_spec`), once
per robot and terrain: the robot's own models never change, its bodies, joints, actuators and
sensors keep their indices, and a walk on the level floor simulates ``robot.mj_model`` itself.
"""

import functools
from typing import TYPE_CHECKING

import mujoco

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.robot.scene import kept_spec
from mpcwalk.terrain import Terrain

if TYPE_CHECKING:
    from mpcwalk.robot.robot import Robot

#: Name of the floor plane in every robot's scene.
FLOOR = "floor"
#: Name of the terrain's material; its boxes are ``terrain_box_0``, ``terrain_box_1``...
TERRAIN = "terrain"
#: Colour of the terrain's blocks (RGBA).
TERRAIN_RGBA = (0.62, 0.56, 0.48, 1.0)
#: Settings of the floor geom the terrain's boxes take.
_CONTACT = ("contype", "conaffinity", "condim", "friction", "solref", "solimp", "priority")


def box_name(index: int) -> str:
    """Name of the terrain's box ``index`` in the scene."""
    return f"{TERRAIN}_box_{index}"


def add_terrain(spec: mujoco.MjSpec, terrain: Terrain) -> None:
    """Add the blocks of ``terrain`` to a robot's scene ``spec`` (in place) and move its floor
    down to the terrain's floor.

    Raises:
        ConfigurationError: A spec without the floor of the loader's scenes.
    """
    floor = spec.geom(FLOOR)
    if floor is None:
        raise ConfigurationError(
            f"A terrain is laid in a robot's scene, whose floor is the geom '{FLOOR}'; this "
            "spec has none: load the robot with mpcwalk.robot.load_robot."
        )
    spec.add_material(name=TERRAIN, rgba=list(TERRAIN_RGBA))
    for index, box in enumerate(terrain.boxes()):
        geom = spec.worldbody.add_geom(
            name=box_name(index),
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=list(box.half_size),
            pos=list(box.center),
            quat=list(box.quaternion),
            material=TERRAIN,
        )
        for setting in _CONTACT:
            setattr(geom, setting, getattr(floor, setting))
    if terrain.floor < 0.0:
        floor.pos = [0.0, 0.0, terrain.floor]


def terrain_model(robot: "Robot", terrain: Terrain | None) -> mujoco.MjModel:
    """The MuJoCo model of ``robot``'s scene on ``terrain`` (shared: the simulation copies
    it); ``robot.mj_model`` itself on the level floor (None or a terrain without features).

    Raises:
        ConfigurationError: A robot whose scene cannot be compiled again (its MuJoCo model
            changed by hand).
    """
    if terrain is None or terrain.is_flat:
        return robot.mj_model
    return _compiled(robot, terrain)


def scene_spec(robot: "Robot") -> mujoco.MjSpec:
    """A copy of the spec ``robot.mj_model`` was compiled from (built again for a robot from
    another process), to compile the robot's scene again with more in it.

    Raises:
        ConfigurationError: A robot whose scene cannot be compiled again (its MuJoCo model
            changed by hand).
    """
    spec = kept_spec(robot.mj_model)
    if spec is None:  # a robot from another process: its scene built again
        from mpcwalk.robot.loading import build_robot

        visual = robot.mj_model.nmesh > 0  # a URDF robot loaded without meshes has none
        again = build_robot(robot.preset, robot.description_path, visual=visual).mj_model
        sizes = ("nq", "nv", "nu", "nbody", "ngeom", "nsite", "nsensor")
        spec = kept_spec(again)
        if spec is None or any(getattr(again, n) != getattr(robot.mj_model, n) for n in sizes):
            raise ConfigurationError(
                f"Robot '{robot.name}': its MuJoCo model is not the one its description "
                f"{robot.description_path.name} compiles to, so no terrain can be laid in its "
                "scene; load the robot with load_robot and leave its mj_model as it is."
            )
    return spec


@functools.lru_cache(maxsize=4)
def _compiled(robot: "Robot", terrain: Terrain) -> mujoco.MjModel:
    spec = scene_spec(robot)
    add_terrain(spec, terrain)
    try:
        model = spec.compile()
    except ValueError as error:  # pragma: no cover - boxes always compile
        raise ConfigurationError(
            f"MuJoCo cannot compile {robot.name}'s scene with the terrain ({error})."
        ) from error
    # the robot's size, not the terrain's: a video's camera frames the robot as on the floor
    model.stat.extent = robot.mj_model.stat.extent
    model.stat.center[:] = robot.mj_model.stat.center
    return model


__all__ = ["FLOOR", "TERRAIN", "add_terrain", "box_name", "scene_spec", "terrain_model"]
