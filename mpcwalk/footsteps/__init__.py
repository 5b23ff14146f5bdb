"""Footsteps: types, the velocity planner (paper M), path files (paper A)."""

from .footstep import FootGeometry, Footstep, FootstepPlan, Side, StepTiming, rotation_2d, wrap_angle

__all__ = ["FootGeometry", "Footstep", "FootstepPlan", "Side", "StepTiming", "rotation_2d", "wrap_angle"]
