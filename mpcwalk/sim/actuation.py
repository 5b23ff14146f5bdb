"""How the simulated robot's joints are driven: position servos or torque motors.

``"position"`` (the default) keeps the actuators of the robot's description: position servos
of the preset's stiffness, damping and torque limit, fed joint angles. ``"torque"`` swaps each
of them for a motor of gear 1 whose control is the joint torque [N m], limited to the robot's
torque limits (:func:`~mpcwalk.ik.inverse_dynamics.torque_limits`: the servo's, else the
model's effort limit); the joints, their armature and damping, the sensors and the contacts
stay. The robot's own models never change: the torque-driven scene is compiled again from
the spec the loader kept (:func:`~mpcwalk.robot.terrain_scene.scene_spec`), once per robot
and terrain, with the terrain's blocks when there is one.
"""

import functools

import mujoco
import numpy as np

from mpcwalk.exceptions import ConfigurationError
from mpcwalk.ik.inverse_dynamics import torque_limits
from mpcwalk.robot.robot import Robot
from mpcwalk.robot.terrain_scene import add_terrain, scene_spec, terrain_model
from mpcwalk.terrain import Terrain

#: The ways the joints can be driven.
ACTUATIONS = ("position", "torque")


def check_actuation(actuation: object) -> str:
    """``actuation`` if it is one of :data:`ACTUATIONS`.

    Raises:
        ConfigurationError: Any other value.
    """
    if actuation not in ACTUATIONS:
        raise ConfigurationError(
            f"actuation must be one of {', '.join(ACTUATIONS)}, got {actuation!r}; 'position' "
            "drives the joints with position servos, 'torque' with torque motors."
        )
    return str(actuation)


def use_motors(spec: mujoco.MjSpec, robot: Robot) -> None:
    """Turn every joint actuator of ``spec`` into a torque motor (in place): gear 1, control
    range and force range the joint's torque limit (unlimited where it has none)."""
    limits = dict(zip(robot.joint_names, torque_limits(robot)))
    for actuator in spec.actuators:
        limit = limits.get(actuator.target, np.inf)
        actuator.set_to_motor()
        actuator.gear = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        bounded = bool(np.isfinite(limit))
        state = mujoco.mjtLimited.mjLIMITED_TRUE if bounded else mujoco.mjtLimited.mjLIMITED_FALSE
        actuator.ctrllimited = actuator.forcelimited = state
        if bounded:
            actuator.ctrlrange = actuator.forcerange = [-float(limit), float(limit)]


def actuated_model(robot: Robot, terrain: Terrain | None, actuation: str) -> mujoco.MjModel:
    """The MuJoCo model of ``robot``'s scene on ``terrain`` with ``actuation`` (shared: the
    simulation copies it).

    Raises:
        ConfigurationError: An unknown actuation, or a robot whose scene cannot be compiled
            again.
    """
    if check_actuation(actuation) == "position":
        return terrain_model(robot, terrain)
    return _torque_model(robot, None if terrain is None or terrain.is_flat else terrain)


@functools.lru_cache(maxsize=4)
def _torque_model(robot: Robot, terrain: Terrain | None) -> mujoco.MjModel:
    spec = scene_spec(robot)
    if terrain is not None:
        add_terrain(spec, terrain)
    use_motors(spec, robot)
    model = spec.compile()
    model.stat.extent = robot.mj_model.stat.extent
    model.stat.center[:] = robot.mj_model.stat.center
    return model


__all__ = ["ACTUATIONS", "actuated_model", "check_actuation", "use_motors"]
