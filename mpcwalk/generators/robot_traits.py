"""What a generator reads of a robot: its CoM height, walking defaults, leg limits and how far
sideways its ankles can carry the CoP."""

from typing import Protocol

from mpcwalk.footsteps.leg_limits import LegLimits
from mpcwalk.gait.gait_defaults import GaitDefaults


class RobotTraits(Protocol):
    """The traits of a robot a pattern generator is built from
    (:meth:`~mpcwalk.generators.pattern_generator.PatternGenerator.for_robot`);
    :class:`~mpcwalk.robot.robot.Robot` has them, and so can a test double: the generators
    never load a robot themselves."""

    @property
    def com_height(self) -> float:
        """CoM height above the soles [m]."""

    @property
    def gait(self) -> GaitDefaults:
        """Walking defaults (the ``[gait]`` table of the robot's preset)."""

    @property
    def leg_limits(self) -> LegLimits:
        """Per-step reach of the legs."""

    @property
    def lateral_cop_reach(self) -> float:
        """How far sideways from a sole's centre the CoP can go with the whole weight on that
        foot [m] (half the sole's width, or less where the ankle roll motors are weaker)."""
