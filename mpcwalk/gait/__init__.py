"""Gait timing and trajectories: contact schedule, swing foot, torso, jtraj/ctraj."""

from mpcwalk.gait.contact_schedule import MAX_POLYGON_EDGES, ContactSchedule, Phase
from mpcwalk.gait.ctraj import CartesianTrajectory, ctraj
from mpcwalk.gait.interpolation import (
    step_interpolation,
    step_interpolation_derivative,
    swing_height_profile,
    swing_height_profile_derivative,
)
from mpcwalk.gait.jtraj import JointTrajectory, jtraj
from mpcwalk.gait.swing_foot import FeetState, FootState, SwingFootTrajectory

__all__ = [
    "MAX_POLYGON_EDGES",
    "CartesianTrajectory",
    "ContactSchedule",
    "FeetState",
    "FootState",
    "JointTrajectory",
    "Phase",
    "SwingFootTrajectory",
    "ctraj",
    "jtraj",
    "step_interpolation",
    "step_interpolation_derivative",
    "swing_height_profile",
    "swing_height_profile_derivative",
]
