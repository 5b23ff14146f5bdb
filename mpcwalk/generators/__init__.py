"""CoM/ZMP pattern generators, all behind :class:`PatternGenerator`."""

from mpcwalk.generators.pattern_generator import (
    GeneratorOutput,
    Horizon,
    PatternGenerator,
    SolveInfo,
)
from mpcwalk.generators.registry import (
    GENERATORS,
    generator_class,
    generator_names,
    make_generator,
)
from mpcwalk.generators.robot_traits import RobotTraits
from mpcwalk.generators.rollout import Rollout, rollout
from mpcwalk.models.com_state import ComState

__all__ = [
    "GENERATORS",
    "ComState",
    "GeneratorOutput",
    "Horizon",
    "PatternGenerator",
    "RobotTraits",
    "Rollout",
    "SolveInfo",
    "generator_class",
    "generator_names",
    "make_generator",
    "rollout",
]
