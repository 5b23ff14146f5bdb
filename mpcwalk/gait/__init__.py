"""Gait timing and trajectories: contact schedule, swing foot, torso, jtraj/ctraj."""

from .contact_schedule import MAX_POLYGON_EDGES, ContactSchedule, Phase

__all__ = ["ContactSchedule", "MAX_POLYGON_EDGES", "Phase"]
