"""Gait timing and trajectories: contact schedule, swing foot, torso, jtraj/ctraj."""

from .contact_schedule import MAX_POLYGON_EDGES, ContactSchedule, Phase
from .ctraj import CartesianTrajectory, ctraj
from .interpolation import (
    step_interpolation,
    step_interpolation_derivative,
    swing_height_profile,
    swing_height_profile_derivative,
)
from .jtraj import JointTrajectory, jtraj
from .swing_foot import FeetState, FootState, SwingFootTrajectory

__all__ = [
    "CartesianTrajectory", "ContactSchedule", "FeetState", "FootState", "JointTrajectory",
    "MAX_POLYGON_EDGES", "Phase", "SwingFootTrajectory", "ctraj", "jtraj",
    "step_interpolation", "step_interpolation_derivative", "swing_height_profile",
    "swing_height_profile_derivative",
]
