"""Footsteps: types (3D poses), the velocity planner (paper M), path files and reachability
(paper A), landings placed on a terrain."""

from mpcwalk.footsteps.footstep import (
    FootGeometry,
    Footstep,
    FootstepPlan,
    HeightMap,
    Side,
    StepTiming,
    rotation_2d,
    terrain_height_map,
    wrap_angle,
)
from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.footsteps.mdat import (
    MDAT_FIELDS,
    PathTarget,
    PathWaypoint,
    parse_mdat,
    path_targets,
    plan_from_path,
    quaternion_to_yaw,
    read_mdat,
    write_mdat,
    yaw_to_quaternion,
)
from mpcwalk.footsteps.path_follower import PathFollower
from mpcwalk.footsteps.reachability import (
    ATLAS_REACHABILITY,
    SMALL_HUMANOID_REACHABILITY,
    ClampedFootstep,
    ClampedStep,
    ReachabilityRectangle,
    opening_side,
)
from mpcwalk.footsteps.rotations import (
    MAX_FOOTSTEP_TILT,
    quaternion_rpy,
    rpy_matrix,
    rpy_quaternion,
)
from mpcwalk.footsteps.terrain_steps import TerrainStepPlacer, place_on_terrain
from mpcwalk.footsteps.velocity_planner import (
    VelocityCommand,
    VelocityPlanner,
    integrate_torso,
    plan_from_velocity,
)

__all__ = [
    "ATLAS_REACHABILITY",
    "MAX_FOOTSTEP_TILT",
    "MDAT_FIELDS",
    "SMALL_HUMANOID_REACHABILITY",
    "ClampedFootstep",
    "ClampedStep",
    "FootGeometry",
    "Footstep",
    "FootstepPlan",
    "HeightMap",
    "LegLimits",
    "PathFollower",
    "PathTarget",
    "PathWaypoint",
    "ReachabilityRectangle",
    "Side",
    "StepTiming",
    "TerrainStepPlacer",
    "VelocityCommand",
    "VelocityPlanner",
    "integrate_torso",
    "opening_side",
    "parse_mdat",
    "path_targets",
    "place_on_terrain",
    "plan_from_path",
    "plan_from_velocity",
    "quaternion_rpy",
    "quaternion_to_yaw",
    "read_mdat",
    "rotation_2d",
    "rpy_matrix",
    "rpy_quaternion",
    "terrain_height_map",
    "wrap_angle",
    "write_mdat",
    "yaw_to_quaternion",
]
