"""Footsteps: types, the velocity planner (paper M), path files and reachability (paper A)."""

from mpcwalk.footsteps.footstep import (
    FootGeometry,
    Footstep,
    FootstepPlan,
    Side,
    StepTiming,
    rotation_2d,
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
from mpcwalk.footsteps.velocity_planner import (
    VelocityCommand,
    VelocityPlanner,
    integrate_torso,
    plan_from_velocity,
)

__all__ = [
    "ATLAS_REACHABILITY",
    "MDAT_FIELDS",
    "SMALL_HUMANOID_REACHABILITY",
    "ClampedFootstep",
    "ClampedStep",
    "FootGeometry",
    "Footstep",
    "FootstepPlan",
    "LegLimits",
    "PathFollower",
    "PathTarget",
    "PathWaypoint",
    "ReachabilityRectangle",
    "Side",
    "StepTiming",
    "VelocityCommand",
    "VelocityPlanner",
    "integrate_torso",
    "opening_side",
    "parse_mdat",
    "path_targets",
    "plan_from_path",
    "plan_from_velocity",
    "quaternion_to_yaw",
    "read_mdat",
    "rotation_2d",
    "wrap_angle",
    "write_mdat",
    "yaw_to_quaternion",
]
