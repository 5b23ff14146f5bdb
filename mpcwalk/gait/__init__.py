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
from mpcwalk.gait.sole_clearance import (
    ClearanceReport,
    measure_swing_clearance,
    sole_clearance,
)
from mpcwalk.gait.swing_clearance import SwingClearance, SwingShape
from mpcwalk.gait.swing_foot import FeetState, FootState, SwingFootTrajectory

__all__ = [
    "MAX_POLYGON_EDGES",
    "CartesianTrajectory",
    "ClearanceReport",
    "ContactSchedule",
    "FeetState",
    "FootState",
    "JointTrajectory",
    "Phase",
    "SwingClearance",
    "SwingFootTrajectory",
    "SwingShape",
    "ctraj",
    "jtraj",
    "measure_swing_clearance",
    "sole_clearance",
    "step_interpolation",
    "step_interpolation_derivative",
    "swing_height_profile",
    "swing_height_profile_derivative",
]
